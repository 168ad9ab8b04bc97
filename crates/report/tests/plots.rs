//! The plots are real SVG, and text from files cannot break out of them.

use allan::{Options, TauSpec, analyze};
use report::PlotError;
use report::plots::{Curve, Drawn, Target, adev_heatmap_bins, adev_plot, bias_plot};
use thermal::surface::bin_curves_only;

fn noise(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..n)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

#[test]
fn adev_plot_is_svg_with_escaped_labels() {
    let pts = analyze(
        &noise(4096, 1),
        &Options {
            taus: TauSpec::Octave,
            ..Options::default()
        },
    )
    .unwrap()
    .points;
    let svg = adev_plot(
        Target::Svg,
        "gyro <script>alert(1)</script>",
        "rad/s",
        &[Curve {
            label: "a & b".into(),
            points: &pts,
            asymptotes: vec![report::plots::Asymptote {
                label: "N = 0.29 <unit>".into(),
                at_1s: 0.29,
                slope: -0.5,
            }],
            marker: Some((8.0, pts[3].dev, "σ_min".into())),
            colour: Some(report::plots::temperature_colour(0.5)),
        }],
    )
    .unwrap()
    .into_svg()
    .unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert!(!svg.contains("<script>"), "unescaped title in {svg:.300}");
    assert!(svg.contains("<polyline") || svg.contains("<path"));
    assert!(svg.contains("<text"));
    // The asymptote and the marker are in the legend, escaped.
    assert!(svg.contains("N = 0.29 &lt;unit&gt;"), "asymptote legend missing");
    assert!(svg.contains("σ_min"), "marker legend missing");
    assert!(!svg.contains("<unit>"));
}

#[test]
fn heatmap_and_bias_plot_draw() {
    let x = noise(20_000, 2);
    let t: Vec<f64> = (0..20_000).map(|i| 20.0 + i as f64 * 0.002).collect();
    let rows = bin_curves_only(&x, &t, 10.0, 10.0, 0.683).unwrap();
    let svg = svg_of(adev_heatmap_bins(Target::Svg, "gyro_x", "rad/s", &rows));
    assert!(svg.matches("<rect").count() > 20);
    let bins: Vec<(f64, f64)> = (0..10).map(|i| (20.0 + i as f64, i as f64 * 0.1)).collect();
    let svg = svg_of(bias_plot(Target::Svg, "bias", "rad/s", &bins, &bins, &|t| {
        (t - 20.0) * 0.1
    }));
    assert!(svg.matches("<circle").count() >= 20);
}

#[test]
fn time_plot_decimates_with_an_envelope() {
    let x = noise(2_000_000, 3);
    // One spike must survive the decimation.
    let mut y = x.clone();
    y[1_234_567] = 40.0;
    let env = report::plots::envelope(&y, 100.0);
    assert!(env.len() <= report::plots::TIME_COLUMNS);
    assert!(env.iter().any(|e| e.2 == 40.0));
    let t: Vec<f64> = (0..x.len()).map(|i| 100.0 - i as f64 * 1e-5).collect();
    let svg = svg_of(report::plots::time_plot(
        Target::Svg,
        "gyro",
        "rad/s",
        &[("gyro_x".into(), &y)],
        100.0,
        Some(&t),
    ));
    assert!(svg.len() < 400_000, "{} bytes: not decimated", svg.len());
    assert!(svg.contains("temperature"));
}

#[test]
fn png_on_request() {
    let pts = analyze(&noise(4096, 4), &Options::default()).unwrap().points;
    let dir = std::env::temp_dir().join(format!("imutherm-png-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("adev.png");
    let drawn = adev_plot(Target::Png(&path), "gyro", "rad/s", &[Curve::plain("a", &pts)]).unwrap();
    assert_eq!(drawn, Drawn::Png);
    let bytes = std::fs::read(&path).unwrap();
    assert!(
        bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() > 5000,
        "{} bytes",
        bytes.len()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The SVG text of a plot drawn to [`Target::Svg`].
fn svg_of(drawn: Result<Drawn, PlotError>) -> String {
    drawn.unwrap().into_svg().expect("drawn as SVG")
}
