//! A model as a C header: its coefficients and one reference function that
//! compensates one sample of every channel as [`Model::apply`] does, for a
//! user's own firmware or ROS node.
//!
//! The function keeps the filters' state (the element's temperature
//! through each channel's lag, the smoothed rate the hysteresis follows)
//! in a struct the caller owns, and takes the time since the previous call,
//! so it runs sample by sample. A sample whose temperature is NaN leaves
//! the state alone and comes back NaN; the next finite one bridges the gap
//! with the line between the two readings, as [`crate::element::lag`].
//! What runs only offline is refused: a dT/dt term (taken over a window
//! centred on the sample) and a coarse readout's smoothing (which needs
//! the next change of the reading).

use std::fmt::Write;

use thiserror::Error;

use crate::tcal::{ChannelModel, Model};

/// A model the header cannot reproduce sample by sample.
#[derive(Debug, Error, PartialEq)]
pub enum CHeaderError {
    /// A channel with a dT/dt term.
    #[error(
        "{0} has a dT/dt term, taken over a window centred on each sample, which a causal function cannot reproduce: refit without it"
    )]
    RateTerm(String),
    /// A model fitted on a coarse temperature readout.
    #[error(
        "the model smooths a temperature read in steps of {0} °C between the reading's changes, which needs the next change: refit on a finer readout"
    )]
    CoarseReadout(f64),
    /// A model of several instances.
    #[error("the model holds {0} instances: export one model per sensor")]
    Instances(usize),
}

fn num(v: f64) -> String {
    // Round-trips a double.
    format!("{v:e}")
}

fn ident(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_uppercase()
            } else {
                '_'
            }
        })
        .collect()
}

/// The header's text.
pub fn render(model: &Model) -> Result<String, CHeaderError> {
    if model.instances.len() > 1 {
        return Err(CHeaderError::Instances(model.instances.len()));
    }
    if let Some(step) = model.temperature_step_c {
        return Err(CHeaderError::CoarseReadout(step));
    }
    if let Some(c) = model.channels.iter().find(|c| c.rate_coefficient.is_some()) {
        return Err(CHeaderError::RateTerm(c.name.clone()));
    }
    let n = model.channels.len();
    let maxc = model
        .channels
        .iter()
        .map(|c| c.coefficients.len())
        .max()
        .unwrap_or(1);
    let maxh = model
        .channels
        .iter()
        .filter_map(|c| c.hysteresis_term.as_ref().map(|h| h.coefficients.len()))
        .max()
        .unwrap_or(1);
    let mut s = String::new();
    let w = &mut s;
    let _ = writeln!(
        w,
        "/* Temperature compensation written by imutherm from a {} model.",
        model.schema
    );
    let _ = writeln!(
        w,
        " * x_comp = x - (p(Te) - p(T_ref)) - h(Te, r): Te the temperature through"
    );
    let _ = writeln!(
        w,
        " * the channel's first-order lag, clamped to the fitted range; h the"
    );
    let _ = writeln!(
        w,
        " * hysteresis, amplitude(u) * tanh(r / scale), r the rate smoothed through"
    );
    let _ = writeln!(
        w,
        " * a first-order lag; u = (Te - centre) / half-span. Channels, in order:"
    );
    for (i, c) in model.channels.iter().enumerate() {
        let _ = writeln!(w, " *   {i}: {} ({})", c.name, c.unit);
    }
    let _ = writeln!(w, " */");
    let _ = writeln!(
        w,
        "#ifndef IMUTHERM_TCAL_H\n#define IMUTHERM_TCAL_H\n\n#include <math.h>\n"
    );
    let _ = writeln!(w, "#define IMUTHERM_TCAL_CHANNELS {n}");
    for (i, c) in model.channels.iter().enumerate() {
        let _ = writeln!(w, "#define IMUTHERM_TCAL_{} {i}", ident(&c.name));
    }
    let _ = writeln!(w);
    for (name, value) in [
        ("t_min_c", model.t_min_c),
        ("t_max_c", model.t_max_c),
        ("t_ref_c", model.t_ref_c),
        ("centre_c", model.centre_c),
        ("scale_c", model.scale_c),
    ] {
        let _ = writeln!(w, "static const double imutherm_tcal_{name} = {};", num(value));
    }
    let rows = |f: &dyn Fn(&ChannelModel) -> Vec<f64>, len: usize| -> String {
        model
            .channels
            .iter()
            .map(|c| {
                let mut v = f(c);
                v.resize(len, 0.0);
                format!("{{{}}}", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", "))
            })
            .collect::<Vec<_>>()
            .join(",\n    ")
    };
    let _ = writeln!(
        w,
        "/* p(u), ascending powers of u. */\nstatic const double imutherm_tcal_poly[{n}][{maxc}] = {{\n    {}\n}};",
        rows(&|c| c.coefficients.clone(), maxc)
    );
    let _ = writeln!(
        w,
        "/* Lag of each channel's element, s; 0: none. */\nstatic const double imutherm_tcal_lag_s[{n}] = {{{}}};",
        model
            .channels
            .iter()
            .map(|c| num(c.lag_s.unwrap_or(0.0)))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        w,
        "/* Hysteresis amplitude in u, ascending; its rate scale, °C/s (0: none); its smoothing, s. */\nstatic const double imutherm_tcal_hyst[{n}][{maxh}] = {{\n    {}\n}};",
        rows(
            &|c| c
                .hysteresis_term
                .as_ref()
                .map_or(vec![0.0], |h| h.coefficients.clone()),
            maxh
        )
    );
    let hv = |f: &dyn Fn(&crate::tcal::HysteresisTerm) -> f64| {
        model
            .channels
            .iter()
            .map(|c| num(c.hysteresis_term.as_ref().map_or(0.0, f)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(
        w,
        "static const double imutherm_tcal_hyst_scale[{n}] = {{{}}};",
        hv(&|h| h.rate_scale_c_per_s)
    );
    let _ = writeln!(
        w,
        "static const double imutherm_tcal_hyst_smoothing_s[{n}] = {{{}}};",
        hv(&|h| h.smoothing_s)
    );
    let _ = writeln!(
        w,
        "/* The saturated direction's relaxation, s; 0: none (the saturated rate itself). */\nstatic const double imutherm_tcal_hyst_relax_s[{n}] = {{{}}};\n",
        hv(&|h| h.relax_s.unwrap_or(0.0))
    );
    let _ = write!(
        w,
        r#"/* The filters' state; zero it before the first sample. */
typedef struct {{
    int started;
    double pending_s;  /* time since the last finite temperature */
    double t_in;       /* that temperature */
    double lag[{n}];   /* each channel's element temperature */
    double dir[{n}];   /* that temperature smoothed (for its rate) */
    double sat[{n}];   /* the saturated direction at the last sample */
    double rel[{n}];   /* that direction relaxed */
}} imutherm_tcal_state;

static double imutherm_tcal_poly_at(const double *c, int len, double u)
{{
    double acc = 0.0;
    for (int j = len - 1; j >= 0; --j)
        acc = acc * u + c[j];
    return acc;
}}

/* One step of a first-order lag of tau seconds over h seconds, its input
 * moving on a line from x0 to x1. */
static double imutherm_tcal_lag_step(double y0, double x0, double x1, double h, double tau)
{{
    double m = (x1 - x0) / h;
    return x1 - m * tau + (y0 - x0 + m * tau) * exp(-h / tau);
}}

/* Compensates x[IMUTHERM_TCAL_CHANNELS] in place for the temperature temp_c
 * (°C), dt_s seconds after the previous call. */
static void imutherm_tcal_apply(imutherm_tcal_state *s, double temp_c, double dt_s, double *x)
{{
    if (!isfinite(temp_c)) {{
        s->pending_s += dt_s;
        for (int k = 0; k < IMUTHERM_TCAL_CHANNELS; ++k)
            x[k] = NAN;
        return;
    }}
    double h = s->pending_s + dt_s;
    for (int k = 0; k < IMUTHERM_TCAL_CHANNELS; ++k) {{
        double tau = imutherm_tcal_lag_s[k];
        double sm = imutherm_tcal_hyst_smoothing_s[k];
        double before = tau > 0.0 ? s->lag[k] : s->t_in;
        if (!s->started) {{
            s->lag[k] = temp_c;
            s->dir[k] = temp_c;
        }} else if (tau > 0.0) {{
            s->lag[k] = imutherm_tcal_lag_step(s->lag[k], s->t_in, temp_c, h, tau);
        }}
        double el = tau > 0.0 ? s->lag[k] : temp_c;
        /* The hysteresis follows the element's own rate. */
        if (s->started && sm > 0.0)
            s->dir[k] = imutherm_tcal_lag_step(s->dir[k], before, el, h, sm);
        double te = el;
        if (te < imutherm_tcal_t_min_c)
            te = imutherm_tcal_t_min_c;
        if (te > imutherm_tcal_t_max_c)
            te = imutherm_tcal_t_max_c;
        double u = (te - imutherm_tcal_centre_c) / imutherm_tcal_scale_c;
        double u_ref = (imutherm_tcal_t_ref_c - imutherm_tcal_centre_c) / imutherm_tcal_scale_c;
        double corr = imutherm_tcal_poly_at(imutherm_tcal_poly[k], {maxc}, u)
            - imutherm_tcal_poly_at(imutherm_tcal_poly[k], {maxc}, u_ref);
        if (imutherm_tcal_hyst_scale[k] > 0.0) {{
            double r = (el - s->dir[k]) / sm;
            double d = tanh(r / imutherm_tcal_hyst_scale[k]);
            double relax = imutherm_tcal_hyst_relax_s[k];
            if (relax > 0.0) {{
                s->rel[k] = s->started ? imutherm_tcal_lag_step(s->rel[k], s->sat[k], d, h, relax) : d;
                s->sat[k] = d;
                d = s->rel[k];
            }}
            corr += imutherm_tcal_poly_at(imutherm_tcal_hyst[k], {maxh}, u) * d;
        }}
        x[k] -= corr;
    }}
    s->started = 1;
    s->pending_s = 0.0;
    s->t_in = temp_c;
}}

#endif /* IMUTHERM_TCAL_H */
"#
    );
    Ok(s)
}
