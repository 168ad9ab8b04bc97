//! The report's 3D ADEV views in a real browser: headless Chromium without
//! a GPU draws each one with its axis labels in real units (τ [s], T [°C],
//! σ in the channel's unit), the canvas is not blank, pointing at the
//! surface reads a value out, and the page logs no error. Screenshots of
//! the views go to `target/report-screenshots/`.
//!
//! Needs Debian's `chromium`; with `IMUTHERM_REQUIRE_BROWSER=1` (as `.ci/run`
//! sets it) a missing browser fails the test instead of skipping it.

use std::path::PathBuf;
use std::process::Command as Process;

mod support;
use support::chromium::{FLAGS, chromium_or_skip, console_errors, screenshots};
use support::{Simulation, cli};

/// Appended to a copy of the page (the report carries no test code): moves
/// the 3D views to the top, so the screenshot shows them, and writes what
/// each canvas drew into `<pre id="probe">` as JSON — its labels, how many
/// of its pixels are not background, and the value read out when the
/// pointer is over the surface.
const PROBE: &str = r#"<script>(function(){
var out=[],cs=document.querySelectorAll('canvas[id^=surface]');
var holder=document.createElement('div');document.body.prepend(holder);
cs.forEach(function(c,i){if(i<2){holder.appendChild(c.closest('figure'));}});
cs.forEach(function(c){
 var g=c.getContext('2d'),d=g.getImageData(0,0,c.width,c.height).data,ink=0;
 for(var k=0;k<d.length;k+=4){if(d[k]<240||d[k+1]<240||d[k+2]<240){ink++;}}
 var b=c.getBoundingClientRect(),hover=null;
 for(var y=0.3;y<0.8&&!hover;y+=0.02){for(var x=0.2;x<0.8&&!hover;x+=0.02){
  c.dispatchEvent(new MouseEvent('mousemove',{clientX:b.left+x*b.width,clientY:b.top+y*b.height,bubbles:true}));
  hover=c.dataset.hover||null;}}
 out.push({unit:c.dataset.unit,labels:JSON.parse(c.dataset.labels||'[]'),ink:ink,pixels:c.width*c.height,
  rendered:Number(c.dataset.rendered||0),hover:hover});});
var pre=document.createElement('pre');pre.id='probe';pre.textContent=JSON.stringify(out);document.body.appendChild(pre);
})();</script></body>"#;

#[test]
fn the_3d_views_draw_axes_labelled_in_real_units() {
    let Some(browser) = chromium_or_skip() else {
        return;
    };
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("browser-surface");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    // A 20-minute cooling run at 10 Hz, 5-minute windows every 30 s: 31
    // windows, a surface dense in temperature, in a second or two.
    let cooling = Simulation::new()
        .profile("cooling:90:25:600")
        .duration("1200")
        .rate("10")
        .seed("3")
        .write(&out, "cooling.txt");
    cli![
        "report",
        &cooling,
        "--dyn-window",
        "5min",
        "--dyn-step",
        "30s",
        "--out",
        out.join("rep")
    ]
    .assert()
    .success();
    let page = std::fs::read_to_string(out.join("rep/report.html")).unwrap();
    let probed = out.join("probed.html");
    std::fs::write(&probed, page.replace("</body>", PROBE)).unwrap();
    let url = format!("file://{}", probed.display());
    let profile = format!("--user-data-dir={}", out.join("chromium-profile").display());

    let dom = Process::new(&browser)
        .args(FLAGS)
        .arg(&profile)
        .arg("--window-size=1200,1000")
        .arg("--dump-dom")
        .arg(&url)
        .output()
        .expect("chromium runs");
    let html = String::from_utf8_lossy(&dom.stdout);
    let json = html
        .split("<pre id=\"probe\">")
        .nth(1)
        .and_then(|s| s.split("</pre>").next())
        .unwrap_or_else(|| panic!("the probe did not run: {}", String::from_utf8_lossy(&dom.stderr)))
        .replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&amp;", "&");
    let views: serde_json::Value = serde_json::from_str(&json).expect("probe JSON");
    let views = views.as_array().unwrap();
    // One view per inertial channel of the run.
    assert_eq!(views.len(), 6, "{json}");
    for v in views {
        let unit = v["unit"].as_str().unwrap();
        let labels: Vec<&str> = v["labels"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|l| l.as_str())
            .collect();
        let sigma = format!("σ [{unit}]");
        for want in ["τ [s]", "T [°C]", sigma.as_str()] {
            assert!(labels.contains(&want), "{unit}: no '{want}' among {labels:?}");
        }
        // Decade ticks on τ: the windows reach from 0.1 s (10⁻¹) up.
        assert!(labels.contains(&"10⁻¹") && labels.contains(&"10⁰"), "{labels:?}");
        // 30 windows of cells, a surface: far from blank, far from filled.
        let rendered = v["rendered"].as_u64().unwrap();
        assert!(rendered > 30 * 5, "{unit}: {rendered} cells");
        let (ink, pixels) = (v["ink"].as_f64().unwrap(), v["pixels"].as_f64().unwrap());
        assert!(
            ink > 0.1 * pixels && ink < 0.9 * pixels,
            "{unit}: {ink} of {pixels} pixels drawn"
        );
        let hover = v["hover"]
            .as_str()
            .unwrap_or_else(|| panic!("{unit}: no value under the pointer"));
        assert!(
            hover.starts_with("τ = ") && hover.contains(" °C, σ = ") && hover.ends_with(unit),
            "{hover}"
        );
    }
    let log = String::from_utf8_lossy(&dom.stderr);
    let errors = console_errors(&log);
    assert!(errors.is_empty(), "the page logged {errors:?}");

    let shot = screenshots(&out).join("report-surface.png");
    let run = Process::new(&browser)
        .args(FLAGS)
        .arg(&profile)
        .arg("--window-size=1200,1000")
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&url)
        .output()
        .expect("chromium runs");
    assert!(run.status.success(), "chromium failed");
    let log = String::from_utf8_lossy(&run.stderr);
    let errors = console_errors(&log);
    assert!(errors.is_empty(), "the page logged {errors:?}");
    let png = std::fs::read(&shot).expect("screenshot written");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 20_000,
        "{} bytes",
        png.len()
    );
    eprintln!("screenshot: {}", shot.display());
}
