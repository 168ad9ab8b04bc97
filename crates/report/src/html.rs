//! The self-contained HTML page: tables, inline SVG plots, the command and
//! version that made it. Everything that comes from a file is escaped.

use minijinja::{AutoEscape, Environment, context};
use serde::Serialize;

use analysis::summary::Summary;

use crate::charts::{CHARTS_JS, Chart, UPLOT_CSS, UPLOT_JS};

/// Escapes text for HTML content and attribute values.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

/// A page under construction: its blocks, in order, rendered at the end
/// through the page template (`templates/page.html`).
#[derive(Debug, Default)]
pub struct Page {
    title: String,
    blocks: Vec<Block>,
    surfaces: usize,
}

/// One block of the page, as the template reads it.
#[derive(Debug, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
enum Block {
    Heading {
        text: String,
    },
    Paragraph {
        text: String,
    },
    Table {
        caption: String,
        header: Vec<String>,
        rows: Vec<Vec<String>>,
    },
    Figure {
        svg: String,
        caption: String,
        /// The interactive chart's data as JSON, drawn by the page's
        /// script in place of the SVG on screen.
        chart: Option<String>,
    },
    Surface {
        id: usize,
        title: String,
        unit: String,
        /// The slices as JSON, for the page's script.
        data: String,
        /// The σ range `lo,hi` (log₁₀) shared with the views it is
        /// compared with; its own data's range when none.
        zrange: Option<String>,
    },
    Code {
        text: String,
    },
    Summary {
        summary: Box<Summary>,
    },
}

/// A heading and the blocks up to the next, as the template reads them.
#[derive(Debug, Serialize)]
struct Section<'a> {
    title: Option<&'a str>,
    blocks: Vec<&'a Block>,
}

/// One slice of a 3D surface as the page's script reads it: the mean
/// temperature and (log₁₀ τ, log₁₀ σ) per point.
#[derive(Debug, Serialize)]
struct SurfaceSlice {
    t: f64,
    p: Vec<[f64; 2]>,
}

/// A 3D view's slices: each temperature with its (τ, σ) points.
pub type Slices = [(f64, Vec<(f64, f64)>)];

const PAGE_TEMPLATE: &str = include_str!("../templates/page.html");

impl Page {
    /// A page with this title.
    pub fn new(title: &str) -> Page {
        Page {
            title: title.to_string(),
            blocks: Vec::new(),
            surfaces: 0,
        }
    }

    /// A section heading.
    pub fn heading(&mut self, text: &str) {
        self.blocks.push(Block::Heading {
            text: text.to_string(),
        });
    }

    /// A paragraph of text.
    pub fn paragraph(&mut self, text: &str) {
        self.blocks.push(Block::Paragraph {
            text: text.to_string(),
        });
    }

    /// A table: a caption, the header cells, the rows.
    pub fn table(&mut self, caption: &str, header: &[String], rows: &[Vec<String>]) {
        self.blocks.push(Block::Table {
            caption: caption.to_string(),
            header: header.to_vec(),
            rows: rows.to_vec(),
        });
    }

    /// A figure: SVG made by [`crate::plots`] (trusted: imutherm drew it,
    /// and every text in it was passed through plotters' own escaping) with
    /// a caption.
    pub fn figure(&mut self, svg: &str, caption: &str) {
        self.blocks.push(Block::Figure {
            svg: svg.to_string(),
            caption: caption.to_string(),
            chart: None,
        });
    }

    /// A figure that is also an interactive chart ([`Chart`]): on screen
    /// the chart replaces the SVG (values under the cursor, zoom, traces
    /// toggled from the legend); the SVG stays for print and for a browser
    /// without scripts. The charting library goes into the page once.
    pub fn chart_figure(&mut self, svg: &str, caption: &str, chart: &Chart) {
        self.blocks.push(Block::Figure {
            svg: svg.to_string(),
            caption: caption.to_string(),
            chart: Some(chart.to_json()),
        });
    }

    /// An interactive 3D surface σ(τ, T) (drag to turn it, the value under
    /// the pointer read out), drawn on a canvas by imutherm's own script
    /// embedded in the page, so the report needs no network and no library. `rows` are (mean temperature °C,
    /// [(τ s, σ)]) per slice.
    pub fn surface3d(&mut self, title: &str, unit: &str, rows: &[(f64, Vec<(f64, f64)>)]) {
        self.surface3d_on(title, unit, rows, None);
    }

    /// Two 3D views meant to be compared (raw and compensated), drawn on
    /// one σ scale: the range of both.
    pub fn surface3d_pair(&mut self, titles: [&str; 2], unit: &str, rows: [&Slices; 2]) {
        let (lo, hi) = rows
            .iter()
            .flat_map(|r| r.iter().filter(|(t, _)| t.is_finite()))
            .flat_map(|(_, pts)| pts.iter().filter(|p| p.0 > 0.0).map(|p| p.1))
            .filter(|d| *d > 0.0 && d.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), d| {
                (a.min(d), b.max(d))
            });
        let shared = (hi > lo).then(|| format!("{:.4},{:.4}", lo.log10(), hi.log10()));
        for (title, rows) in titles.into_iter().zip(rows) {
            self.surface3d_on(title, unit, rows, shared.clone());
        }
    }

    fn surface3d_on(
        &mut self,
        title: &str,
        unit: &str,
        rows: &[(f64, Vec<(f64, f64)>)],
        zrange: Option<String>,
    ) {
        let id = self.surfaces;
        self.surfaces += 1;
        // Four decimals of a logarithm are 0.02 %, and 0.001 °C is below
        // the sensor's quantum: finer digits would only lengthen the page.
        let round = |x: f64, scale: f64| (x * scale).round() / scale;
        let slices: Vec<SurfaceSlice> = rows
            .iter()
            .filter(|r| r.0.is_finite())
            .map(|(t, pts)| SurfaceSlice {
                t: round(*t, 1e3),
                p: pts
                    .iter()
                    .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                    .map(|(tau, dev)| [round(tau.log10(), 1e4), round(dev.log10(), 1e4)])
                    .collect(),
            })
            .collect();
        // Numbers and arrays only: nothing in it can end the script element.
        let data = serde_json::to_string(&slices).unwrap_or_else(|_| "[]".to_string());
        self.blocks.push(Block::Surface {
            id,
            title: title.to_string(),
            unit: unit.to_string(),
            data,
            zrange,
        });
    }

    /// A preformatted block (a command line).
    pub fn code(&mut self, text: &str) {
        self.blocks.push(Block::Code {
            text: text.to_string(),
        });
    }

    /// The summary of what the IMU is ([`Summary`]): drawn first, so that
    /// the answer is on the first screen.
    pub fn summary(&mut self, summary: &Summary) {
        self.blocks.push(Block::Summary {
            summary: Box::new(summary.clone()),
        });
    }

    /// The finished page: the blocks before the first heading, then one
    /// collapsible section per heading, listed in a table of contents.
    pub fn finish(&self) -> Result<String, crate::ReportError> {
        // The first part, untitled, holds what comes before any heading.
        let mut parts: Vec<Section> = vec![Section {
            title: None,
            blocks: Vec::new(),
        }];
        for b in &self.blocks {
            match b {
                Block::Heading { text } => parts.push(Section {
                    title: Some(text),
                    blocks: Vec::new(),
                }),
                b => parts.last_mut().map_or((), |s| s.blocks.push(b)),
            }
        }
        let sections: Vec<&Section> = parts.iter().filter(|s| s.title.is_some()).collect();
        let mut env = Environment::new();
        // Escaping is the template's own, by `esc`, on what came from a file;
        // the SVG, the style and the script are imutherm's and go in as
        // they are.
        env.set_auto_escape_callback(|_| AutoEscape::None);
        env.set_keep_trailing_newline(true);
        env.add_filter("esc", |text: String| escape(&text));
        env.add_filter("num", |x: Option<f64>| {
            x.map_or_else(|| "—".to_string(), significant)
        });
        let rendered = env
            .template_from_named_str("page.html", PAGE_TEMPLATE)
            .and_then(|t| {
                t.render(context! {
                    title => &self.title,
                    style => STYLE,
                    surface_js => SURFACE_JS,
                    has_charts => self.blocks.iter().any(|b| matches!(b, Block::Figure { chart: Some(_), .. })),
                    uplot_js => UPLOT_JS,
                    uplot_css => UPLOT_CSS,
                    charts_js => CHARTS_JS,
                    parts => &parts,
                    sections => &sections,
                    has_summary => self.blocks.iter().any(|b| matches!(b, Block::Summary { .. })),
                })
            });
        rendered.map_err(|e| crate::ReportError::Template(e.to_string()))
    }
}

/// `x` to three significant digits (whole numbers from 100 to 99 999 keep
/// all of theirs), without the float noise of a plain `{}`
/// (`0.30000000000000004`); in plain decimals from 0.001 to 99 999.
pub fn significant(x: f64) -> String {
    if !x.is_finite() {
        return "—".to_string();
    }
    if x == 0.0 {
        return "0".to_string();
    }
    let mag = x.abs().log10().floor() as i32;
    if !(-3..5).contains(&mag) {
        let s = format!("{x:.2e}");
        // 1.50e-5 → 1.5e-5
        return match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.')),
            None => s,
        };
    }
    let decimals = (2 - mag).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// The 3D view's script (`assets/surface3d.js`): axes with ticks in real
/// units, a colour bar, the value under the pointer, drag to turn. Marks
/// the canvas `data-rendered` and `data-labels` when done, which the
/// browser test reads.
const SURFACE_JS: &str = include_str!("../assets/surface3d.js");

const STYLE: &str = "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right}\
th{background:#eee}caption{font-weight:bold;text-align:left;padding:.3em 0}figure.plot{display:inline-block;margin:.5em}\
figure.surface{display:inline-block;margin:.5em}canvas{border:1px solid #ddd;cursor:grab}figcaption{font-size:.9em;color:#555}pre{background:#f4f4f4;padding:.6em;overflow-x:auto}\
section.summary{border:1px solid #bbb;padding:0 1em;margin:1em 0}div.answer p{font-size:1.1em}div.answer .figures{display:flex;gap:1em;margin:.5em 0 1em}\
div.answer .figures>div{flex:1;border:1px solid #ccc;padding:.4em .6em}div.answer span{display:block}div.answer .big{font-size:1.5em;font-weight:bold}\
div.answer .what,div.answer .unit{color:#444;font-size:.9em}table.summary td:first-child,table.summary td:nth-child(2){text-align:left}\
tr.outside td{background:#fde8e8}.src{display:block;font-size:.75em;color:#666}\
figure.live>.static{display:none}.chart .u-title{font-size:16px}.chart .u-legend{font-size:13px;max-width:720px}.chart canvas{border:0;cursor:crosshair}.chart .u-legend th,.chart .u-legend td{border:0;background:none;padding:1px 3px}.chart-note{font-size:.8em;color:#666;margin:.2em 0}\
nav.toc{font-size:.9em;line-height:1.6}nav.toc a{margin-right:.8em}details>summary{cursor:pointer}details>summary h2{display:inline}\
@media print{body{max-width:none;margin:0;font-size:10pt}nav.toc,canvas,figure.surface,.chart{display:none}figure.live>.static{display:block}\
details>summary{list-style:none}details>summary::-webkit-details-marker{display:none}figure,table,section.summary{break-inside:avoid}\
h2{break-after:avoid}svg{max-width:100%;height:auto}pre{white-space:pre-wrap}}";

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_keep_three_significant_digits_and_no_float_noise() {
        assert_eq!(significant(0.1 + 0.2), "0.3");
        assert_eq!(significant(0.01), "0.01");
        assert_eq!(significant(1000.0), "1000");
        assert_eq!(significant(12345.6), "12346");
        assert_eq!(significant(-0.0123456), "-0.0123");
        assert_eq!(significant(1.5e-5), "1.5e-5");
        assert_eq!(significant(2.0e6), "2e6");
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(f64::NAN), "—");
    }

    #[test]
    fn file_text_is_escaped() {
        let mut p = Page::new("report");
        p.table(
            "inputs",
            &["file".to_string()],
            &[vec!["<script>alert(1)</script>.txt".to_string()]],
        );
        let html = p.finish().unwrap();
        assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt;.txt"));
        assert!(!html.contains("<script>"));
    }

    #[test]
    fn the_template_lays_out_each_block_on_its_own_line_in_a_collapsible_section() {
        let mut p = Page::new("t & u");
        p.heading("H");
        p.paragraph("a < b");
        p.table(
            "c",
            &["x".to_string(), "y".to_string()],
            &[vec!["1".into(), "2".into()]],
        );
        p.figure("<svg/>", "f");
        p.code("imutherm demo");
        let html = p.finish().unwrap();
        let body = html.split_once("<body>\n").unwrap().1;
        assert_eq!(
            body,
            "<h1>t &amp; u</h1>\n<nav class=\"toc\"><strong>Contents:</strong> <a href=\"#s1\">H</a> </nav>\n\
             <details open id=\"s1\"><summary><h2>H</h2></summary>\n<p>a &lt; b</p>\n<table>\n<caption>c</caption>\n\
             <tr><th>x</th><th>y</th></tr>\n<tr><td>1</td><td>2</td></tr>\n</table>\n\
             <figure class=\"plot\"><svg/><figcaption>f</figcaption></figure>\n<pre>imutherm demo</pre>\n</details>\n\
             </body>\n</html>\n"
        );
        assert!(html.contains("<title>t &amp; u</title>"));
    }

    #[test]
    fn a_chart_figure_carries_its_data_the_svg_for_print_and_the_library_once() {
        let mut p = Page::new("c");
        let pts = allan::analyze(
            &[1.0, 2.0, 1.5, 1.7, 1.2, 1.9, 1.4, 1.6],
            &allan::Options::default(),
        )
        .unwrap()
        .points;
        let chart = crate::charts::adev_chart("a</script>", "g", &[crate::plots::Curve::plain("x", &pts)]);
        p.chart_figure("<svg/>", "one", &chart);
        p.chart_figure("<svg/>", "two", &chart);
        let html = p.finish().unwrap();
        assert_eq!(html.matches("<div class=\"static\"><svg/></div>").count(), 2);
        assert_eq!(html.matches("var uPlot=").count(), 1);
        assert_eq!(html.matches("classList.add('live')").count(), 1);
        assert!(html.contains(".u-legend"));
        let start = html.find("class=\"chart-data\">").unwrap() + "class=\"chart-data\">".len();
        let json = &html[start..start + html[start..].find("</script>").unwrap()];
        let v: serde_json::Value = serde_json::from_str(json).unwrap();
        assert_eq!(v["title"], "a</script>");
        assert_eq!(v["xs"].as_array().unwrap().len(), pts.len());
        // A page without charts carries no script.
        let mut plain = Page::new("p");
        plain.figure("<svg/>", "f");
        assert!(!plain.finish().unwrap().contains("<script"));
    }

    /// Raw and compensated views are drawn on the σ range of both.
    #[test]
    fn a_pair_of_surfaces_shares_one_sigma_range() {
        let mut p = Page::new("s");
        let raw = vec![(30.0, vec![(1.0, 0.01), (10.0, 0.001)])];
        let comp = vec![
            (30.0, vec![(1.0, 0.1), (10.0, 0.002)]),
            (f64::NAN, vec![(1.0, 1e3)]),
        ];
        p.surface3d_pair(["raw", "compensated"], "rad/s", [&raw, &comp]);
        let html = p.finish().unwrap();
        assert_eq!(
            html.matches("data-zrange=\"-3.0000,-1.0000\"").count(),
            2,
            "{html}"
        );
    }

    #[test]
    fn a_surface_carries_its_slices_as_json_and_the_script_once() {
        let mut p = Page::new("s");
        let rows = vec![
            (30.0, vec![(1.0, 0.01), (10.0, 0.001)]),
            (f64::NAN, vec![(1.0, 1.0)]),
        ];
        p.surface3d("gyro_x", "rad/s", &rows);
        p.surface3d("gyro_y", "rad/s", &rows);
        let html = p.finish().unwrap();
        assert_eq!(html.matches("function imuthermSurface").count(), 1);
        let start = html.find("id=\"surface1-data\">").unwrap() + "id=\"surface1-data\">".len();
        let json = &html[start..start + html[start..].find("</script>").unwrap()];
        // log10 of τ and σ: (0, −2) and (1, −3); the NaN slice is left out.
        let v: serde_json::Value = serde_json::from_str(json).unwrap();
        assert_eq!(
            v,
            serde_json::json!([{"t": 30.0, "p": [[0.0, -2.0], [1.0, -3.0]]}])
        );
    }
}
