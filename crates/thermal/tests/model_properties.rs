//! Whatever a model file holds, loading it either refuses it or gives a
//! model that applies and exports without panicking, and a finite sample at
//! a finite temperature stays finite. (About one generated model in five
//! passes the checks, so both sides are exercised.)

use proptest::prelude::*;

use thermal::firmware::{Firmware, Target, export, load};
use thermal::tcal::{ChannelModel, Model, SCHEMA};

fn number() -> impl Strategy<Value = f64> {
    prop_oneof![
        -200.0..200.0f64,
        -1e-3..1e-3f64,
        Just(0.0),
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(1e308),
        Just(-1e-320),
    ]
}

/// Mostly a sound channel; now and then an odd name, a stray value, a
/// coefficient too many or too few, or a rate term.
fn channel() -> impl Strategy<Value = ChannelModel> {
    let names = prop_oneof![
        8 => prop_oneof![Just("gyro_x"), Just("gyro_y"), Just("gyro_z"), Just("accel_x"), Just("accel_z")],
        1 => prop_oneof![Just("temp"), Just("pressure"), Just("gyro_1"), Just("")],
    ];
    let coefficient = prop_oneof![9 => -1.0..1.0f64, 1 => number()];
    (
        names,
        0usize..6,
        prop::collection::vec(coefficient, 7),
        prop_oneof![4 => Just(0i32), 1 => -1i32..=1],
        prop::option::weighted(0.2, number()),
    )
        .prop_map(|(name, order, pool, miscount, rate_coefficient)| ChannelModel {
            name: name.to_string(),
            unit: "rad/s".into(),
            order,
            coefficients: pool[..(order as i32 + 1 + miscount).max(0) as usize].to_vec(),
            rate_coefficient,
            residual_rms: 0.0,
            residual_max: 0.0,
            cross_validation: Vec::new(),
            hysteresis: None,
            lag_s: None,
            lag_interval_s: None,
            hysteresis_term: None,
            projection: None,
        })
}

/// Mostly a plausible model, with one field at a time spoiled half of the
/// time, so that both sides of the check are reached.
fn model() -> impl Strategy<Value = Model> {
    (
        -60.0..80.0f64,
        0.01..120.0f64,
        0.0..=1.0f64,
        prop::option::of((-1.0..0.0f64, 0.0..1.0f64)),
        prop::collection::vec(channel(), 0..4),
        prop::option::of((0usize..8, number())),
        any::<bool>(),
    )
        .prop_map(|(t_min, span, at, rates, channels, spoil, channels_only)| {
            let mut m = Model {
                schema: SCHEMA.into(),
                t_ref_c: t_min + at * span,
                t_min_c: t_min,
                t_max_c: t_min + span,
                centre_c: t_min + span / 2.0,
                scale_c: span / 2.0,
                bin_width_c: 1.0,
                fitted_on: Vec::new(),
                fitted_on_digests: Vec::new(),
                dtdt_range_c_per_s: rates.map(|(a, b)| [a, b]),
                device_id: None,
                accel_device_id: None,
                instance: None,
                temperature_step_c: None,
                channels,
                instances: Vec::new(),
            };
            if let Some((field, v)) = spoil.filter(|_| !channels_only) {
                match field {
                    0 => m.t_ref_c = v,
                    1 => m.t_min_c = v,
                    2 => m.t_max_c = v,
                    3 => m.centre_c = v,
                    4 => m.scale_c = v,
                    5 => m.bin_width_c = v,
                    6 => m.dtdt_range_c_per_s = Some([v, -v]),
                    _ => m.schema = "imutherm.tcal/0".into(),
                }
            }
            m
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]

    #[test]
    fn a_model_is_refused_or_safe_to_apply(m in model(), temps in prop::collection::vec(number(), 1..40)) {
        if m.validate().is_err() {
            // What is refused in memory is refused from its file (when
            // JSON can hold it: serde_json writes NaN as null).
            if let Ok(text) = serde_json::to_string(&m)
                && serde_json::from_str::<Model>(&text).ok().as_ref() == Some(&m)
            {
                prop_assert!(Model::from_json(&text).is_err());
            }
            return Ok(());
        }
        let text = serde_json::to_string(&m).unwrap();
        prop_assert_eq!(Model::from_json(&text).map(|_| ()), Ok(()));
        for c in &m.channels {
            let mut data = vec![1.0; temps.len()];
            m.apply(&c.name, &mut data, &temps, 1.0).unwrap();
            for (x, t) in data.iter().zip(&temps) {
                if t.is_finite() && c.rate_coefficient.is_none() {
                    prop_assert!(x.is_finite(), "{} at {t} °C gave {x}", c.name);
                }
            }
        }
        for fw in [Firmware::Px4, Firmware::ArduPilot] {
            if let Ok(out) = export(&m, fw, Target::default()) {
                prop_assert!(load(fw, &out.text, None).is_ok(), "{}", out.text);
            }
        }
    }

    #[test]
    fn any_text_is_a_model_or_an_error(text in ".{0,200}") {
        let _ = Model::from_json(&text);
    }
}
