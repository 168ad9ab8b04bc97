//! The demo's report in a real browser: headless Chromium renders it with
//! the network disabled, every figure must hold a drawn plot, the summary
//! must be on the first screen of a 1280×800 window, the page must log no
//! error and fetch nothing, an ADEV chart must show the hovered point's τ
//! and σ and hide a trace toggled in its legend, and the screenshots
//! (one of them hovered) are kept under
//! `target/report-screenshots/` for people to look at.
//!
//! Needs Debian's `chromium`. `.ci/run` installs it and sets
//! `IMUTHERM_REQUIRE_BROWSER=1`, so CI cannot skip this test; elsewhere it
//! says it is skipped when no browser is installed.

use std::path::PathBuf;
use std::process::Command as Process;

mod support;
use support::chromium::{FLAGS, chromium_or_skip, console_errors, screenshots};
use support::cli;

#[test]
fn the_demo_report_renders_in_chromium() {
    let Some(browser) = chromium_or_skip() else {
        return;
    };
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("browser-demo");
    let _ = std::fs::remove_dir_all(&out);
    cli!["demo", "--quick", "--out", &out].assert().success();
    let page = out.join("report.html");
    let url = format!("file://{}", page.display());
    let profile = out.join("chromium-profile");
    // No network: every request goes to a closed port (the page must need
    // none; the probe below checks it made none).
    let common = FLAGS;
    // Kept as CI artefacts: target/report-screenshots/.
    let shots = screenshots(&out);
    let shot = shots.join("report.png");
    let run = Process::new(&browser)
        .args(common)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--window-size=1200,3000")
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&url)
        .output()
        .expect("chromium runs");
    assert!(
        run.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let png = std::fs::read(&shot).expect("screenshot written");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 50_000,
        "screenshot of {} bytes",
        png.len()
    );

    // The DOM as the browser built it.
    let dom = Process::new(&browser)
        .args(common)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(&url)
        .output()
        .expect("chromium runs");
    let html = String::from_utf8_lossy(&dom.stdout);
    // A figure whose chart the script drew is `plot live`; its SVG stays,
    // for print.
    let figures: Vec<&str> = html.split("<figure class=\"plot").skip(1).collect();
    // 35, and the noise model of each of the six axes in each of the four
    // constant-temperature runs.
    assert_eq!(figures.len(), 35 + 24, "figures in the rendered page");
    let live = figures.iter().filter(|f| f.starts_with(" live\"")).count();
    assert_eq!(live, 16, "ADEV and raw-data figures drawn as interactive charts");
    for (i, f) in figures.iter().enumerate() {
        let body = f.split("</figure>").next().unwrap_or("");
        assert!(body.contains("<svg"), "figure {i} has no svg");
        let marks = body.matches("<circle").count()
            + body.matches("<rect").count()
            + body.matches("<polyline").count();
        assert!(marks > 10, "figure {i} is nearly empty ({marks} marks)");
    }
    check_static_plots(&html);
    // The twelve 3D views (dynamic ADEV, raw and compensated per channel)
    // were drawn by their script (the charts' canvases are uPlot's, inside
    // `div.chart`).
    let canvases = html.matches("<canvas id=\"surface").count();
    assert_eq!(canvases, 12, "3D surfaces");
    let rendered = html
        .split("data-rendered=\"")
        .skip(1)
        .filter(|s| {
            s.split('"')
                .next()
                .and_then(|n| n.parse::<usize>().ok())
                .is_some_and(|n| n > 0)
        })
        .count();
    assert_eq!(rendered, 12, "surfaces drawn");
    // No script error or console message from the page.
    let log = String::from_utf8_lossy(&run.stderr).to_string() + &String::from_utf8_lossy(&dom.stderr);
    let bad = console_errors(&log);
    assert!(bad.is_empty(), "the page logged: {bad:?}");

    // The first screen: a 1280×800 window, as a reader opens the page.
    let first = shots.join("report-first-screen.png");
    let run_first = in_window(
        &browser,
        &profile,
        "1280,800",
        &format!("--screenshot={}", first.display()),
        &url,
    );
    assert!(run_first.status.success(), "chromium failed");
    // Where the summary is, and what the page fetched, measured in the same
    // window by a probe appended to a copy of the page (the report itself
    // carries no test code): it writes its findings into the DOM.
    let probe = out.join("report-probed.html");
    let page_html = std::fs::read_to_string(&page).unwrap();
    let probed = page_html.replace(
        "</body>",
        "<script>(function(){var s=document.getElementById('summary');\
         var r=s?s.getBoundingClientRect():null;\
         var net=performance.getEntriesByType('resource').filter(function(e){return !/^(file|data|blob):/.test(e.name);}).length;\
         document.body.setAttribute('data-probe',(r?Math.round(r.top)+','+Math.round(r.bottom):'none')+';'+window.innerWidth+'x'+window.innerHeight+';'+net);})();</script></body>",
    );
    std::fs::write(&probe, probed).unwrap();
    let measured = in_window(
        &browser,
        &profile,
        "1280,800",
        "--dump-dom",
        &format!("file://{}", probe.display()),
    );
    let dom = String::from_utf8_lossy(&measured.stdout);
    let found = dom
        .split("data-probe=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or_else(|| {
            panic!(
                "the probe did not run: {}",
                String::from_utf8_lossy(&measured.stderr)
            )
        });
    let parts: Vec<&str> = found.split(';').collect();
    eprintln!("summary top,bottom; window; network requests: {found}");
    assert_eq!(parts.len(), 3, "probe: {found}");
    let top: f64 = parts[0]
        .split(',')
        .next()
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no summary on the page: {found}"));
    assert!(
        top < 800.0,
        "the summary starts {top} px down, below the first screen ({found})"
    );
    assert_eq!(parts[2], "0", "the page fetched from the network");
    let log =
        String::from_utf8_lossy(&run_first.stderr).to_string() + &String::from_utf8_lossy(&measured.stderr);
    let bad = console_errors(&log);
    assert!(bad.is_empty(), "the page logged: {bad:?}");
    let hovered = hover_probe(&browser, &common, &profile, &page, &out, &shots);
    let answer = answer_probe(&browser, &profile, &page, &out, &shots);
    for s in [&shot, &first, &hovered, &answer] {
        eprintln!("screenshot: {}", s.display());
    }
}

/// The `<text x=… y=…>label</text>` elements of an SVG, trimmed.
fn svg_texts(svg: &str) -> Vec<(f64, f64, String)> {
    svg.split("<text ")
        .skip(1)
        .filter_map(|t| {
            let attr = |name: &str| -> Option<f64> {
                let v = t.split(&format!("{name}=\"")).nth(1)?.split('"').next()?;
                v.parse().ok()
            };
            let body = t.split_once('>')?.1.split("</text>").next()?;
            Some((
                attr(" x").or_else(|| attr("x"))?,
                attr("y")?,
                body.trim().to_string(),
            ))
        })
        .collect()
}

/// The static plots as drawn: on every axis (tick labels sharing an x, or a
/// y) one number format, all exponents or none (`1e-4` beside `0.001` was
/// the fault); the navigation chart's time axis stops near its data (the
/// demo navigates 120 s: no tick at 1000 s), and its legend lies under the
/// plot, below every tick label and axis name.
fn check_static_plots(html: &str) {
    let mut navigation = 0;
    for f in html.split("<figure class=\"plot").skip(1) {
        let body = f.split("</figure>").next().unwrap_or("");
        let texts = svg_texts(body);
        let ticks: Vec<&(f64, f64, String)> = texts.iter().filter(|t| t.2.parse::<f64>().is_ok()).collect();
        let exp = |t: &str| t.contains('e');
        // The decades below 1 of one axis (labels at one x, or one y; a
        // panel beneath may share the x, but its linear ticks are no
        // decades): `0.001` beside `1e-4` was the fault.
        let decade = |t: &str| {
            let v: f64 = t.parse().unwrap();
            v < 1.0 && (v.log10() - v.log10().round()).abs() < 1e-9
        };
        for same in [
            |a: &(f64, f64, String), b: &(f64, f64, String)| a.0 == b.0,
            |a: &(f64, f64, String), b: &(f64, f64, String)| a.1 == b.1,
        ] {
            for t in &ticks {
                let axis: Vec<&str> = ticks
                    .iter()
                    .filter(|u| same(t, u) && decade(&u.2))
                    .map(|u| u.2.as_str())
                    .collect();
                if axis.len() >= 2 {
                    assert!(
                        axis.iter().all(|l| exp(l)) || !axis.iter().any(|l| exp(l)),
                        "one axis in two formats: {axis:?}"
                    );
                }
            }
        }
        if !body.contains("horizontal position error [m]") {
            continue;
        }
        navigation += 1;
        let lowest_tick = ticks.iter().map(|t| t.1).fold(f64::NEG_INFINITY, f64::max);
        let x_ticks: Vec<f64> = ticks
            .iter()
            .filter(|t| t.1 == lowest_tick)
            .map(|t| t.2.parse().unwrap())
            .collect();
        let last = x_ticks.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert!(
            (100.0..1000.0).contains(&last),
            "the time axis's last tick is {last} s: {x_ticks:?}"
        );
        let axis_name = texts
            .iter()
            .find(|t| t.2.contains("time since alignment"))
            .expect("x axis name");
        for t in texts.iter().filter(|t| {
            t.2.contains("measured rms") || t.2.contains("Monte Carlo") || t.2.contains("predicted DRMS")
        }) {
            assert!(
                t.1 > axis_name.1 && t.1 > lowest_tick,
                "legend entry '{}' at y {} is on the plot",
                t.2,
                t.1
            );
        }
    }
    assert!(navigation >= 1, "no navigation chart found");
}

/// Chromium on `url` in a window of `size` (`W,H`), doing `what` (a
/// screenshot, or dumping the DOM).
fn in_window(
    browser: &std::path::Path,
    profile: &std::path::Path,
    size: &str,
    what: &str,
    url: &str,
) -> std::process::Output {
    Process::new(browser)
        .args(FLAGS)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={size}"))
        .arg(what)
        .arg(url)
        .output()
        .expect("chromium runs")
}

/// The answer on the first screen of a 1400×900 window: the sentence and
/// its three figures (the gyro's noise at each temperature; the bias slope
/// and what compensation removes; the 60 s drift raw and compensated) each
/// wholly within the first screen, holding its numbers with their units. Measured by
/// a probe appended to a copy of the page, which writes each element's
/// bottom and text into the DOM; the window's screenshot is kept.
fn answer_probe(
    browser: &std::path::Path,
    profile: &std::path::Path,
    page: &std::path::Path,
    out: &std::path::Path,
    shots: &std::path::Path,
) -> PathBuf {
    let shot = shots.join("report-first-screen-1400x900.png");
    let url = format!("file://{}", page.display());
    let run = in_window(
        browser,
        profile,
        "1400,900",
        &format!("--screenshot={}", shot.display()),
        &url,
    );
    assert!(run.status.success(), "chromium failed");
    let probe = out.join("report-answer.html");
    let html = std::fs::read_to_string(page).unwrap();
    std::fs::write(
        &probe,
        html.replace(
            "</body>",
            "<script>(function(){var o=document.createElement('pre');o.id='probe-out';\
             o.textContent=['answer-sentence','answer-noise','answer-slope','answer-drift'].map(function(id){\
             var e=document.getElementById(id);if(!e)return id+'|none|';var r=e.getBoundingClientRect();\
             return id+'|'+Math.ceil(r.bottom)+'|'+e.textContent.replace(/\\s+/g,' ');}).join('\\n')\
             +'\\nwindow|'+window.innerHeight+'|'+window.innerWidth;document.body.appendChild(o);})();</script></body>",
        ),
    )
    .unwrap();
    let measured = in_window(
        browser,
        profile,
        "1400,900",
        "--dump-dom",
        &format!("file://{}", probe.display()),
    );
    let dom = String::from_utf8_lossy(&measured.stdout);
    let found = dom
        .split("<pre id=\"probe-out\">")
        .nth(1)
        .and_then(|s| s.split("</pre>").next())
        .unwrap_or_else(|| {
            panic!(
                "the probe did not run: {}",
                String::from_utf8_lossy(&measured.stderr)
            )
        });
    eprintln!("answer probe:\n{found}");
    let rows: Vec<Vec<&str>> = found.lines().map(|l| l.splitn(3, '|').collect()).collect();
    // The screenshot is the 1400×900 first screen (PNG's IHDR: width and
    // height, big-endian, at bytes 16 and 20).
    let png = std::fs::read(&shot).expect("screenshot written");
    let dim = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().unwrap());
    assert_eq!((dim(16), dim(20)), (1400, 900), "screenshot size");
    // The same window's viewport, in which the probe measured (headless
    // Chromium keeps part of the 900 px for its window, so the viewport
    // can be shorter: the answer must fit the shorter of the two).
    let window = rows.iter().find(|r| r[0] == "window").expect("window size");
    assert_eq!(window[2], "1400", "window width");
    let fold = window[1].parse::<f64>().unwrap().min(900.0);
    for (id, needs) in [
        (
            "answer-sentence",
            &["°/s/√Hz at", "°/s/°C", "% of that bias", "m raw", "m compensated"][..],
        ),
        ("answer-noise", &["°/s/√Hz at", "°C"][..]),
        ("answer-slope", &["°/s/°C", "% removed"][..]),
        ("answer-drift", &[" m → ", "m saved"][..]),
    ] {
        let row = rows.iter().find(|r| r[0] == id).unwrap();
        let bottom: f64 = row[1]
            .parse()
            .unwrap_or_else(|_| panic!("{id} is not on the page: {found}"));
        assert!(
            bottom <= fold,
            "{id} ends {bottom} px down, below the first screen ({fold} px)"
        );
        let text = row[2];
        assert!(
            text.chars().any(|c| c.is_ascii_digit()),
            "{id} holds no number: {text}"
        );
        for n in needs {
            assert!(text.contains(n), "{id} lacks '{n}': {text}");
        }
    }
    // The noise figure gives one N per constant-temperature run (the
    // quick demo's four).
    let noise = rows.iter().find(|r| r[0] == "answer-noise").unwrap()[2];
    assert_eq!(
        noise.matches(" · ").count(),
        2 * 3,
        "four runs' N and temperatures: {noise}"
    );
    shot
}

/// What a reader does with an ADEV chart, done by a probe appended to a
/// copy of the page (the report carries no test code): the mouse moved to
/// a data point's pixel (from the chart's own scales, `u.valToPos`), the
/// legend read, the trace toggled off from the legend and on again. The
/// values the legend shows must be the point's τ and σ with its interval,
/// as the page's JSON holds them; the toggled trace's pixels must go. The
/// chart is moved to the top of the copy so the screenshot shows it
/// hovered.
fn hover_probe(
    browser: &std::path::Path,
    common: &[&str],
    profile: &std::path::Path,
    page: &std::path::Path,
    out: &std::path::Path,
    shots: &std::path::Path,
) -> PathBuf {
    let probe = out.join("report-hover.html");
    let html = std::fs::read_to_string(page).unwrap();
    std::fs::write(
        &probe,
        html.replace("</body>", &format!("<script>{HOVER_PROBE}</script></body>")),
    )
    .unwrap();
    let url = format!("file://{}", probe.display());
    let run = |extra: &[String]| {
        Process::new(browser)
            .args(common)
            .arg(format!("--user-data-dir={}", profile.display()))
            .arg("--window-size=1280,800")
            // Lets the probe's timers run before the page is dumped.
            .arg("--virtual-time-budget=5000")
            .args(extra)
            .arg(&url)
            .output()
            .expect("chromium runs")
    };
    let dumped = run(&["--dump-dom".to_string()]);
    let dom = String::from_utf8_lossy(&dumped.stdout);
    let found = dom
        .split("data-hover=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or_else(|| {
            panic!(
                "the hover probe did not run: {}",
                String::from_utf8_lossy(&dumped.stderr)
            )
        })
        .replace("&quot;", "\"")
        .replace("&amp;", "&");
    eprintln!("hover: {found}");
    let v: serde_json::Value = serde_json::from_str(&found).expect("probe findings are JSON");
    assert!(
        v["charts"].as_u64().unwrap_or(0) >= 16,
        "interactive charts: {found}"
    );
    let json: Vec<f64> = v["json"]
        .as_array()
        .expect("the hovered point's JSON values")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect();
    // The cursor snapped to the hovered point.
    assert_eq!(v["cursor"], v["idx"], "cursor index: {found}");
    // The legend shows four significant digits: equal to 1 part in 1000.
    let close = |shown: f64, want: f64| (shown - want).abs() <= 1e-3 * want.abs();
    let numbers = |text: &str| -> Vec<f64> {
        text.split(|c: char| c == '[' || c == ']' || c == ',' || c.is_whitespace())
            .filter(|w| !w.is_empty())
            .map(|w| {
                w.parse::<f64>()
                    .unwrap_or_else(|_| panic!("'{w}' in '{text}' is not a number"))
            })
            .collect()
    };
    let tau = numbers(v["tau"].as_str().unwrap_or(""));
    assert!(
        tau.len() == 1 && close(tau[0], json[0]),
        "τ shown {tau:?}, in the page {}",
        json[0]
    );
    let sigma = numbers(v["sigma"].as_str().unwrap_or(""));
    assert_eq!(sigma.len(), 3, "σ [lo, hi] shown: {found}");
    for (shown, want) in sigma.iter().zip(&json[1..]) {
        assert!(
            close(*shown, *want),
            "σ shown {sigma:?}, in the page {:?}",
            &json[1..]
        );
    }
    // The trace's colour is on its line before the toggle and gone after.
    assert!(
        v["before"].as_u64().unwrap_or(255) < 40,
        "trace not drawn where expected: {found}"
    );
    assert_eq!(v["shown"], false, "the trace is still shown: {found}");
    assert_eq!(v["off"], true, "the legend entry is not marked off: {found}");
    assert!(
        v["after"].as_u64().unwrap_or(0) > 80,
        "the toggled trace is still drawn: {found}"
    );
    let shot = shots.join("report-hover.png");
    let shown = run(&[format!("--screenshot={}", shot.display())]);
    assert!(shown.status.success(), "chromium failed");
    let log = String::from_utf8_lossy(&dumped.stderr).to_string() + &String::from_utf8_lossy(&shown.stderr);
    let errors = console_errors(&log);
    assert!(errors.is_empty(), "the page logged errors: {errors:?}");
    shot
}

/// The probe: hovers the middle point of the last trace that has a band in
/// the first ADEV chart, then toggles that trace off and on from the
/// legend; writes what it saw into `data-hover` on the body.
const HOVER_PROBE: &str = r#"
window.addEventListener('load', function () {
  setTimeout(function () {
    var out = { charts: (window.imuthermCharts || []).length };
    var c = (window.imuthermCharts || []).filter(function (c) { return c.spec.x.log; })[0];
    if (!c) { document.body.setAttribute('data-hover', JSON.stringify(out)); return; }
    var u = c.u, spec = c.spec, k = 0;
    spec.series.forEach(function (s, j) { if (s.lo) k = j; });
    var ys = spec.series[k].y, i = Math.floor(ys.length / 2);
    while (i + 1 < ys.length && (ys[i] == null || ys[i + 1] == null)) i++;
    document.body.insertBefore(c.figure, document.body.firstChild);
    var hover = function () {
      var r = u.over.getBoundingClientRect();
      u.over.dispatchEvent(new MouseEvent('mousemove', {
        clientX: r.left + u.valToPos(spec.xs[i], 'x'),
        clientY: r.top + u.valToPos(ys[i], 'y'), bubbles: true }));
    };
    hover();
    var legend = u.root.querySelectorAll('.u-legend .u-series');
    var text = function (row) { var v = row.querySelector('.u-value'); return v ? v.textContent : ''; };
    out.idx = i; out.cursor = u.cursor.idx;
    out.tau = text(legend[0]); out.sigma = text(legend[k + 1]);
    out.json = [spec.xs[i], ys[i], spec.series[k].lo[i], spec.series[k].hi[i]];
    // Within 1 px of the trace's line halfway to the next point, how far
    // the nearest colour is from the trace's (largest channel difference).
    var mx = (u.valToPos(spec.xs[i], 'x', true) + u.valToPos(spec.xs[i + 1], 'x', true)) / 2;
    var my = (u.valToPos(ys[i], 'y', true) + u.valToPos(ys[i + 1], 'y', true)) / 2;
    var want = [1, 3, 5].map(function (p) { return parseInt(spec.series[k].colour.substr(p, 2), 16); });
    var nearest = function () {
      var d = u.ctx.getImageData(Math.round(mx) - 1, Math.round(my) - 1, 3, 3).data, best = 1e9;
      for (var p = 0; p < d.length; p += 4) {
        best = Math.min(best, Math.max(Math.abs(d[p] - want[0]), Math.abs(d[p + 1] - want[1]),
          Math.abs(d[p + 2] - want[2])));
      }
      return best;
    };
    out.before = nearest();
    legend[k + 1].firstChild.dispatchEvent(new MouseEvent('click', { bubbles: true }));
    setTimeout(function () {
      out.shown = u.series[k + 1].show;
      out.off = legend[k + 1].classList.contains('u-off');
      out.after = nearest();
      legend[k + 1].firstChild.dispatchEvent(new MouseEvent('click', { bubbles: true }));
      setTimeout(function () {
        hover();
        document.body.setAttribute('data-hover', JSON.stringify(out));
      }, 50);
    }, 50);
  }, 50);
});
"#;
