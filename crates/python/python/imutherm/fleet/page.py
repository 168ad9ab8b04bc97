"""The fleet page (``fleet.html``) and one page per unit
(``units/<id>.html``): self-contained HTML in the look of ``imutherm
report`` (its stylesheet's rules for body, tables and flagged rows,
crates/report/src/html.rs ``STYLE``), histograms as inline SVG, no
script and no network."""

import html
import math
import os

import numpy as np

from .files import write_atomic
from .screen import LOG_TERMS

PAGE = "fleet.html"
#: The report's rules that this page uses (crates/report/src/html.rs STYLE).
STYLE = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
         "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .6em;"
         "text-align:right}th{background:#eee}caption{font-weight:bold;text-align:left;padding:.3em 0}"
         "figure.plot{display:inline-block;margin:.5em}figcaption{font-size:.9em;color:#555}"
         "tr.outside td{background:#fde8e8}td.text{text-align:left}"
         "nav.toc{font-size:.9em;line-height:1.6}nav.toc a{margin-right:.8em}")
HIST_TERMS = ("white_noise", "bias_instability", "tcal_slope", "tcal_residual_rms")
WORST = 20


def write(out_dir, rows, limits):
    """Writes the fleet page and the unit pages; returns the fleet page's path."""
    units = _by_unit(rows)
    for uid, urows in units.items():
        write_atomic(os.path.join(out_dir, "units", f"{uid}.html"), _unit_page(uid, urows))
    path = os.path.join(out_dir, PAGE)
    write_atomic(path, _fleet_page(rows, units, limits))
    return path


def _by_unit(rows):
    units = {}
    for r in rows:
        units.setdefault(r["unit"], []).append(r)
    return units


def _e(x):
    return html.escape(str(x), quote=True)


def _num(x):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    if isinstance(x, float):
        return f"{x:.3g}"
    return str(x)


def _doc(title, body):
    return (f"<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            f"<title>{_e(title)}</title>\n<style>{STYLE}</style></head>\n<body>\n"
            f"<h1>{_e(title)}</h1>\n{body}</body>\n</html>\n")


def _fleet_page(rows, units, limits):
    status = {u: min((r["status"] for r in rs), key=["fail", "error", "outlier", "pass"].index)
              for u, rs in units.items()}
    counts = {s: sum(1 for v in status.values() if v == s) for s in ("pass", "outlier", "fail", "error")}
    parts = [f"<p>{len(units)} units: {counts['pass']} pass, {counts['fail']} out of limits, "
             f"{counts['outlier']} outliers of the fleet (robust z beyond {limits.z_max:g}), "
             f"{counts['error']} could not be analysed. Table: <a href=\"fleet.parquet\">fleet.parquet"
             f"</a>.</p>\n",
             "<nav class=\"toc\"><strong>Contents:</strong> <a href=\"#worst\">Worst units</a> "
             "<a href=\"#spread\">The fleet's spread</a></nav>\n"]
    parts.append(_worst(rows, units, status))
    parts.append("<h2 id=\"spread\">The fleet's spread</h2>\n<p>Each term per channel over the "
                 "units; red bars hold flagged units; dead axes are listed above, not drawn.</p>\n")
    channels = sorted({r["channel"] for r in rows if r.get("channel")})
    parts.append(_spread_table(rows, channels))
    for term in HIST_TERMS:
        for ch in channels:
            # A dead axis has no noise to draw: on a log axis its
            # round-off values would squeeze the fleet into one bar.
            sel = [r for r in rows if r.get("channel") == ch and r.get(term) is not None
                   and r.get("static_spread") != 0.0]
            if sel:
                parts.append(_histogram(term, ch, sel))
    return _doc("imutherm fleet", "".join(parts))


def _worst(rows, units, status):
    order = sorted(units, key=lambda u: units[u][0]["rank"])
    worst = [u for u in order if status[u] != "pass"][:WORST] or order[:min(5, len(order))]
    out = ["<h2 id=\"worst\">Worst units</h2>\n<table>\n<caption>Out of limits first, then "
           "outliers; each unit links to its own page</caption>\n<tr><th>rank</th><th>unit</th>"
           "<th>status</th><th>why</th></tr>\n"]
    for u in worst:
        reasons = sorted({f"{r['channel']}: {r['reasons']}" if r.get("channel") else r["reasons"]
                          for r in units[u] if r.get("reasons")})
        cls = " class=\"outside\"" if status[u] != "pass" else ""
        out.append(f"<tr{cls}><td>{units[u][0]['rank']}</td><td class=\"text\"><a href=\"units/"
                   f"{_e(u)}.html\">{_e(u)}</a></td><td class=\"text\">{_e(status[u])}</td>"
                   f"<td class=\"text\">{'<br>'.join(_e(x) for x in reasons) or '—'}</td></tr>\n")
    out.append("</table>\n")
    return "".join(out)


def _spread_table(rows, channels):
    out = ["<table>\n<caption>Per channel: median, robust spread (1.4826 MAD, a standard "
           "deviation for normal data), range, units flagged</caption>\n<tr><th>term</th>"
           "<th>channel</th><th>median</th><th>robust spread</th><th>min</th><th>max</th>"
           "<th>units</th><th>flagged</th></tr>\n"]
    for term in HIST_TERMS:
        for ch in channels:
            sel = [r for r in rows if r.get("channel") == ch and r.get(term) is not None]
            if not sel:
                continue
            x = np.array([r[term] for r in sel], dtype=float)
            med = float(np.median(x))
            mad = 1.4826 * float(np.median(np.abs(x - med)))
            cells = [_num(med), _num(mad), _num(float(x.min())), _num(float(x.max())),
                     str(len(sel)), str(sum(1 for r in sel if r["flagged"]))]
            out.append(f"<tr><td class=\"text\">{_e(term)}</td><td class=\"text\">{_e(ch)}</td>"
                       + "".join(f"<td>{_e(c)}</td>" for c in cells) + "</tr>\n")
    out.append("</table>\n")
    return "".join(out)


def _histogram(term, channel, rows, width=320, height=170, bins=24):
    log = term in LOG_TERMS
    vals = np.array([r[term] for r in rows], dtype=float)
    x = np.log10(vals[vals > 0]) if log else vals
    flagged = np.array([r["flagged"] for r in rows])
    flagged = flagged[vals > 0] if log else flagged
    if len(x) == 0:
        return ""
    lo, hi = float(x.min()), float(x.max())
    if hi == lo:
        lo, hi = lo - 0.5, hi + 0.5
    edges = np.linspace(lo, hi, bins + 1)
    good, _ = np.histogram(x[~flagged], edges)
    bad, _ = np.histogram(x[flagged], edges)
    top = max(1, int((good + bad).max()))
    pw, ph, left, base = width - 20, height - 40, 10, height - 28
    bw = pw / bins
    bars = []
    for i in range(bins):
        for count, below, colour in ((good[i], 0, "#4a7ab5"), (bad[i], good[i], "#c0392b")):
            if count:
                h = ph * count / top
                y = base - ph * below / top - h
                bars.append(f"<rect x=\"{left + i * bw:.1f}\" y=\"{y:.1f}\" width=\"{bw - 1:.1f}\" "
                            f"height=\"{h:.1f}\" fill=\"{colour}\"/>")
    label = (lambda v: f"{10 ** v:.3g}") if log else (lambda v: f"{v:.3g}")
    unit = rows[0].get("si_unit") or ""
    svg = (f"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" "
           f"font-family=\"sans-serif\" font-size=\"11\">{''.join(bars)}"
           f"<line x1=\"{left}\" y1=\"{base}\" x2=\"{left + pw}\" y2=\"{base}\" stroke=\"#222\"/>"
           f"<text x=\"{left}\" y=\"{base + 14}\">{_e(label(lo))}</text>"
           f"<text x=\"{left + pw}\" y=\"{base + 14}\" text-anchor=\"end\">{_e(label(hi))}</text>"
           f"<text x=\"{left + pw}\" y=\"12\" text-anchor=\"end\">max {top} units</text></svg>")
    scale = ", log scale" if log else ""
    return (f"<figure class=\"plot\">{svg}<figcaption>{_e(channel)} {_e(term)} "
            f"[{_e(unit + ('/°C' if term == 'tcal_slope' else ''))}]{scale}</figcaption></figure>\n")


UNIT_COLUMNS = ("instance", "channel", "status", "white_noise", "white_noise_lo", "white_noise_hi",
                "bias_instability", "rate_random_walk", "tcal_order", "tcal_slope",
                "tcal_residual_rms", "held_out_bias_rms", "reasons")


def _unit_page(uid, rows):
    head = "".join(f"<th>{_e(c)}</th>" for c in UNIT_COLUMNS)
    body = []
    for r in rows:
        cls = " class=\"outside\"" if r.get("flagged") else ""
        cells = "".join(f"<td class=\"text\">{_e(_num(r.get(c)))}</td>" if c in ("channel", "status", "reasons")
                        else f"<td>{_e(_num(r.get(c)))}</td>" for c in UNIT_COLUMNS)
        body.append(f"<tr{cls}>{cells}</tr>\n")
    files = sorted({os.path.basename(p) for r in rows for p in (r.get("model_file"), r.get("params_file")) if p})
    links = " ".join(f"<a href=\"{_e(f)}\">{_e(f)}</a>" for f in files)
    err = "".join(f"<p>{_e(r['error'])}</p>\n" for r in rows if r.get("error"))
    return _doc(f"imutherm unit {uid}",
                f"<p><a href=\"../fleet.html\">The fleet</a>. Files: {links or '—'}</p>\n{err}"
                f"<table>\n<caption>Per channel (SI units)</caption>\n<tr>{head}</tr>\n"
                f"{''.join(body)}</table>\n")
