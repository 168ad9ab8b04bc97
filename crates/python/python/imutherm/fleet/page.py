"""The fleet page (``fleet.html``) and one page per unit
(``units/<id>.html``): self-contained HTML in the look of ``imutherm
report`` (its stylesheet's rules for body, tables and flagged rows,
crates/report/src/html.rs ``STYLE``), histograms as inline SVG, no
script and no network."""

import html
import math
import os

import numpy as np

from . import plots, units as units_mod
from .files import write_atomic
from .screen import LOG_TERMS, dead

PAGE = "fleet.html"
#: The report's rules that this page uses (crates/report/src/html.rs STYLE).
STYLE = ("body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}"
         "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:.25em .6em;"
         "text-align:right}th{background:#eee}caption{font-weight:bold;text-align:left;padding:.3em 0}"
         "figure.plot{display:inline-block;margin:.5em}figcaption{font-size:.9em;color:#555}"
         "tr.outside td{background:#fde8e8}td.text,th.text{text-align:left}"
         "nav.toc{font-size:.9em;line-height:1.6}nav.toc a{margin-right:.8em}"
         # The unit page's own: a status word, reasons that wrap, small
         # unit lines under the headings.
         "p.status{font-size:1.3em;font-weight:bold}p.status.pass{color:#2e7d32}"
         "p.status.fail,p.status.error{color:#c0392b}p.status.outlier{color:#b9770e}"
         "ul.reasons{max-width:100%;overflow-wrap:anywhere}th small{font-weight:normal;color:#555}")
HIST_TERMS = ("white_noise", "bias_instability", "tcal_slope", "tcal_residual_rms")
WORST = 20


def write(out_dir, rows, limits):
    """Writes the fleet page and the unit pages; returns the fleet page's path."""
    by_unit = _by_unit(rows)
    bands = _bands(rows)
    for uid, urows in by_unit.items():
        write_atomic(os.path.join(out_dir, "units", f"{uid}.html"),
                     _unit_page(uid, urows, bands, limits))
    path = os.path.join(out_dir, PAGE)
    write_atomic(path, _fleet_page(rows, by_unit, limits))
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
                 "units; red bars hold flagged units, dashed red lines are the limits; dead axes "
                 "are listed above, neither drawn nor counted in the spread.</p>\n")
    channels = sorted({r["channel"] for r in rows if r.get("channel")})
    parts.append(_spread_table(rows, channels))
    for term in HIST_TERMS:
        for ch in channels:
            # A dead axis has no noise to draw: on a log axis its
            # round-off values would squeeze the fleet into one bar.
            sel = [r for r in rows if r.get("channel") == ch and r.get(term) is not None
                   and not dead(r)]
            if sel:
                parts.append(_histogram(term, ch, sel, limits.for_channel(ch).get(term)))
    return _doc("imutherm fleet", "".join(parts))


def _worst(rows, units, status):
    order = sorted(units, key=lambda u: units[u][0]["rank"])
    worst = [u for u in order if status[u] != "pass"][:WORST] or order[:min(5, len(order))]
    out = ["<h2 id=\"worst\">Worst units</h2>\n<table>\n<caption>Out of limits first, then "
           "outliers; each unit links to its own page</caption>\n<tr><th>rank</th><th>unit</th>"
           "<th>status</th><th class=\"text\">why</th></tr>\n"]
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
            sel = [r for r in rows if r.get("channel") == ch and r.get(term) is not None
                   and not dead(r)]
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


def _histogram(term, channel, rows, limit=None, width=320, height=170, bins=24):
    log = term in LOG_TERMS
    vals = np.array([r[term] for r in rows], dtype=float)
    x = np.log10(vals[vals > 0]) if log else vals
    flagged = np.array([r["flagged"] for r in rows])
    flagged = flagged[vals > 0] if log else flagged
    if len(x) == 0:
        return ""
    # The limits are drawn where they fall (|slope| against both signs);
    # a limit far outside the fleet would squeeze it into a bar, so the
    # axis reaches at most one fleet's span beyond the data for it, and
    # a limit beyond that is named at the edge.
    marks = []
    for name, v in zip(("min", "max"), limit or (None, None)):
        if v is None:
            continue
        for w in ((v, -v) if term == "tcal_slope" else (v,)):
            if not log or w > 0:
                marks.append((f"{name} {w:.3g}", math.log10(w) if log else w))
    lo, hi = float(x.min()), float(x.max())
    span = max(hi - lo, abs(hi) * 1e-3 if not log else 0.1, 1e-300)
    for _, m in marks:
        if lo - span <= m <= hi + span:
            lo, hi = min(lo, m), max(hi, m)
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
    for label_text, m in marks:
        if lo <= m <= hi:
            xm = left + pw * (m - lo) / (hi - lo)
            bars.append(f"<line x1=\"{xm:.1f}\" y1=\"{base - ph:.1f}\" x2=\"{xm:.1f}\" y2=\"{base}\" "
                        f"stroke=\"#c0392b\" stroke-dasharray=\"4,3\"><title>limit {_e(label_text)}"
                        f"</title></line>")
        else:
            # Named in the top line, the low one left and the high one
            # right of "max N units".
            end = m > hi
            bars.append(f"<text x=\"{left + pw if end else left}\" y=\"{24 if end else 12}\" "
                        f"fill=\"#c0392b\" "
                        f"text-anchor=\"{'end' if end else 'start'}\">limit {_e(label_text)} "
                        f"{'→' if end else '←'}</text>")
    label = (lambda v: f"{10 ** v:.3g}") if log else (lambda v: f"{v:.3g}")
    unit = units_mod.of(term, rows[0].get("si_unit"))
    svg = (f"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" "
           f"font-family=\"sans-serif\" font-size=\"11\">{''.join(bars)}"
           f"<line x1=\"{left}\" y1=\"{base}\" x2=\"{left + pw}\" y2=\"{base}\" stroke=\"#222\"/>"
           f"<text x=\"{left}\" y=\"{base + 14}\">{_e(label(lo))}</text>"
           f"<text x=\"{left + pw}\" y=\"{base + 14}\" text-anchor=\"end\">{_e(label(hi))}</text>"
           f"<text x=\"{left + pw}\" y=\"12\" text-anchor=\"end\">max {top} units</text></svg>")
    scale = ", log scale" if log else ""
    return (f"<figure class=\"plot\">{svg}<figcaption>{_e(channel)} {_e(term)} "
            f"[{_e(unit)}]{scale}</figcaption></figure>\n")


#: The unit page's table per sensor: column, heading, and whether the
#: figure has the row's unit (:mod:`.units`).
UNIT_TABLE = (("channel", "channel"), ("status", "status"), ("white_noise", "N"),
              ("white_noise_lo", "N low"), ("white_noise_hi", "N high"),
              ("bias_instability", "B"), ("rate_random_walk", "K"), ("tcal_order", "order"),
              ("tcal_slope", "mean slope"), ("tcal_residual_rms", "residual RMS"),
              ("held_out_bias_rms", "held-out RMS"))
#: Plots per row of the unit page (three fit in its 1100 px column).
PLOT_WIDTH = 330


def _bands(rows):
    """The fleet's band per channel: Allan deviation over tau and the bias
    before and after compensation over temperature, from every unit that
    is neither dead nor in error."""
    out = {}
    by_channel = {}
    for r in rows:
        if r.get("channel") and not r.get("error") and not dead(r):
            by_channel.setdefault(r["channel"], []).append(r)
    for ch, rs in by_channel.items():
        adev = [(r["adev_tau_s"], r["adev"]) for r in rs if r.get("adev_tau_s") and r.get("adev")]
        taus = [t for x, _ in adev for t in x if t and t > 0]
        temps = [t for r in rs for t in (r.get("bias_t_c") or [])]
        b = {}
        if taus:
            grid = np.geomspace(min(taus), max(taus), 40)
            b["adev"] = plots.band(adev, grid, log_x=True, log_y=True)
        if temps:
            grid = np.arange(math.floor(min(temps)), math.ceil(max(temps)) + 1.0, 1.0)
            for part in ("before", "after"):
                curves = [(r["bias_t_c"], r[f"bias_{part}"]) for r in rs
                          if r.get("bias_t_c") and r.get(f"bias_{part}")]
                b[part] = plots.band(curves, grid)
        out[ch] = b
    return out


def _unit_page(uid, rows, bands, limits):
    files = sorted({os.path.basename(p) for r in rows for p in (r.get("model_file"), r.get("params_file")) if p})
    links = " ".join(f"<a href=\"{_e(f)}\">{_e(f)}</a>" for f in files)
    status = min((r["status"] for r in rows), key=["fail", "error", "outlier", "pass"].index)
    parts = [f"<p><a href=\"../fleet.html\">The fleet</a>. Files: {links or '—'}</p>\n",
             f"<p class=\"status {status}\">{_e(status)}</p>\n"]
    reasons = [(r.get("channel"), x) for r in rows if r.get("reasons")
               for x in r["reasons"].split("; ")]
    if reasons:
        # A reason every channel shares (a run check, a reader problem of
        # the whole file) is said once.
        channels = {r.get("channel") for r in rows}
        shared = [x for x in dict.fromkeys(x for _, x in reasons)
                  if {c for c, y in reasons if y == x} == channels and len(channels) > 1]
        items = [f"<li>{_e(x)}</li>" for x in shared]
        items += [f"<li><strong>{_e(c)}</strong>: {_e(x)}</li>" if c else f"<li>{_e(x)}</li>"
                  for c, x in reasons if x not in shared]
        parts.append(f"<ul class=\"reasons\">{''.join(items)}</ul>\n")
    for sensor in ("gyro", "accel"):
        srows = [r for r in rows if (r.get("channel") or "").startswith(sensor)]
        if srows:
            parts.append(_unit_table(sensor, srows))
    measured = [r for r in rows if r.get("channel") and not r.get("error")]
    if measured:
        parts.append("<h2>Allan deviation</h2>\n<p>The unit (blue) over the fleet's "
                     f"{plots.BAND[0]:g}–{plots.BAND[1]:g} % band and median (grey); dashed red: "
                     "the white-noise limits as N/√τ.</p>\n")
        parts.extend(_allan(r, bands, limits) for r in measured)
        parts.append("<h2>Bias over temperature</h2>\n<p>The channel's mean per 1 °C of its "
                     "thermal runs, before and after the unit's temperature model, over the "
                     "fleet's band; dashed red: the limits on the residual (±) and on the "
                     "held-out RMS (±).</p>\n")
        for r in measured:
            parts.append("<div>" + _bias(r, bands, limits, "before") + _bias(r, bands, limits, "after")
                         + "</div>\n")
    err = "".join(f"<p>{_e(r['error'])}</p>\n" for r in rows if r.get("error"))
    return _doc(f"imutherm unit {uid}", "".join(parts[:2]) + err + "".join(parts[2:]))


def _unit_table(sensor, rows):
    si = rows[0].get("si_unit")
    head = "".join(f"<th>{_e(h)}" + (f"<br><small>{_e(units_mod.of(c, si))}</small>"
                                     if units_mod.of(c, si) not in ("", "1") else "") + "</th>"
                   for c, h in UNIT_TABLE)
    body = []
    for r in rows:
        cls = " class=\"outside\"" if r.get("flagged") else ""
        cells = []
        for c, _ in UNIT_TABLE:
            v = r.get(c)
            if c.startswith("white_noise") or c in ("bias_instability", "rate_random_walk"):
                how = r.get(f"{c.split('_lo')[0].split('_hi')[0]}_how")
                if how == "dead":
                    v = "dead"
                elif how == "upper_bound" and c in ("bias_instability", "rate_random_walk"):
                    v = f"≤ {_num(v)}"
            if r.get("instance") is not None and c == "channel":
                v = f"{v} (instance {r['instance']})"
            text = v if isinstance(v, str) else _num(v)
            cells.append(f"<td class=\"text\">{_e(text)}</td>" if c in ("channel", "status")
                         else f"<td>{_e(text)}</td>")
        body.append(f"<tr{cls}>{''.join(cells)}</tr>\n")
    name = "Gyroscope" if sensor == "gyro" else "Accelerometer"
    return (f"<table>\n<caption>{name}: noise terms (95 % interval of N) and temperature "
            f"model</caption>\n<tr>{head}</tr>\n{''.join(body)}</table>\n")


def _allan(r, bands, limits):
    ch, si = r["channel"], r.get("si_unit")
    if dead(r):
        return (f"<figure class=\"plot\"><figcaption>{_e(ch)}: a dead axis, no Allan deviation"
                f"</figcaption></figure>\n")
    lines = [(r["adev_tau_s"], r["adev"], "this unit")] if r.get("adev_tau_s") and r.get("adev") else []
    lim = []
    for bound, (lo, hi) in (("white_noise", limits.for_channel(ch).get("white_noise", (None, None))),):
        for name, v in (("max", hi), ("min", lo)):
            if v is not None:
                lim.append((f"{bound}_{name} = {v:g} {units_mod.of(bound, si)}",
                            lambda tau, v=v: v / math.sqrt(tau)))
    return plots.figure(f"{ch} OADEV", "τ [s]", f"σ(τ) [{si}]", lines,
                        bands.get(ch, {}).get("adev"), lim, log_x=True, log_y=True,
                        width=PLOT_WIDTH)


def _bias(r, bands, limits, part):
    ch, si = r["channel"], r.get("si_unit")
    if not r.get("bias_t_c") or not r.get(f"bias_{part}"):
        return ""
    lim = []
    if part == "after":
        table = limits.for_channel(ch)
        for metric in ("tcal_residual_rms", "held_out_bias_rms"):
            hi = table.get(metric, (None, None))[1]
            if hi is not None:
                lim += [(f"{metric}_max = {hi:g} {si}", hi), (f"-{metric}_max", -hi)]
    title = f"{ch} bias {part} compensation"
    return plots.figure(title, "temperature [°C]", f"bias [{si}]",
                        [(r["bias_t_c"], r[f"bias_{part}"], "this unit")],
                        bands.get(ch, {}).get(part), lim, width=PLOT_WIDTH)
