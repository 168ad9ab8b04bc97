"""Line plots as inline SVG for the fleet's pages: a unit's curve over the
fleet's band (its 5-95 % range and median), and the limits as dashed
lines. No script, no network: the page is one file."""

import html
import math

import numpy as np

UNIT = "#1f4e9c"
FLEET = "#c9d6ea"
MEDIAN = "#7d93b5"
LIMIT = "#c0392b"
#: The fleet's band: this share of the units lies inside it.
BAND = (5.0, 95.0)


def band(curves, grid, log_x=False, log_y=False):
    """The fleet's band on ``grid``: ``(low, median, high)`` over
    ``curves`` (pairs of x and y arrays), each interpolated on the grid
    (in logs where asked) and NaN outside its own range."""
    if not curves:
        return None
    fx = np.log10 if log_x else (lambda v: v)
    g = fx(np.asarray(grid, dtype=float))
    stack = []
    for x, y in curves:
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        ok = np.isfinite(x) & np.isfinite(y) & ((x > 0) if log_x else True) & \
            ((y > 0) if log_y else True)
        if ok.sum() < 2:
            continue
        xs, ys = fx(x[ok]), (np.log10(y[ok]) if log_y else y[ok])
        order = np.argsort(xs)
        xs, ys = xs[order], ys[order]
        v = np.interp(g, xs, ys, left=np.nan, right=np.nan)
        stack.append(10 ** v if log_y else v)
    if len(stack) < 3:
        return None
    a = np.vstack(stack)
    enough = np.sum(np.isfinite(a), axis=0) >= 3
    # Grid points fewer than 3 units reach have no band (NaN): only
    # their columns would warn of an all-NaN slice.
    a = np.where(enough, a, 0.0)
    lo, mid, hi = (np.where(enough, np.nanpercentile(a, q, axis=0), np.nan)
                   for q in (BAND[0], 50.0, BAND[1]))
    return np.asarray(grid, dtype=float), lo, mid, hi


def figure(title, x_label, y_label, lines=(), fleet=None, limits=(), log_x=False, log_y=False,
           width=380, height=250):
    """An SVG figure: ``lines`` are ``(x, y, label)`` of the unit,
    ``fleet`` a :func:`band`, ``limits`` ``(label, f)`` with ``f(x)`` the
    limit's y (a number for a level)."""
    left, right, top, bottom = 62, 10, 10, 36
    pw, ph = width - left - right, height - top - bottom
    xs, ys = [], []
    for x, y, _ in lines:
        xs.extend(x)
        ys.extend(y)
    if fleet is not None:
        xs.extend(fleet[0])
        ys.extend(v for part in fleet[1:] for v in part)
    xs = np.array([v for v in xs if v is not None and math.isfinite(v) and (v > 0 or not log_x)])
    if not len(xs):
        return ""
    x0, x1 = float(xs.min()), float(xs.max())
    limit_curves = []
    for label, f in limits:
        grid = np.geomspace(x0, x1, 40) if log_x and x0 > 0 else np.linspace(x0, x1, 40)
        lv = np.array([f(g) if callable(f) else f for g in grid], dtype=float)
        limit_curves.append((grid, lv, label))
        ys.extend(lv)
    ys = np.array([v for v in ys if v is not None and math.isfinite(v) and (v > 0 or not log_y)])
    if not len(ys):
        return ""
    y0, y1 = float(ys.min()), float(ys.max())
    tx = (lambda v: math.log10(v)) if log_x else float
    ty = (lambda v: math.log10(v)) if log_y else float
    a0, a1, b0, b1 = tx(x0), tx(x1), ty(y0), ty(y1)
    if a1 == a0:
        a0, a1 = a0 - 0.5, a1 + 0.5
    if b1 == b0:
        b0, b1 = b0 - 0.5, b1 + 0.5
    pad = 0.05 * (b1 - b0)
    b0, b1 = b0 - pad, b1 + pad

    def px(v):
        return left + pw * (tx(v) - a0) / (a1 - a0)

    def py(v):
        return top + ph * (1 - (ty(v) - b0) / (b1 - b0))

    def ok(x, y):
        return (x is not None and y is not None and math.isfinite(x) and math.isfinite(y)
                and (x > 0 or not log_x) and (y > 0 or not log_y))

    def path(x, y):
        pts = [f"{px(a):.1f},{py(b):.1f}" for a, b in zip(x, y) if ok(a, b)]
        return " ".join(pts)

    parts = [f"<rect x=\"{left}\" y=\"{top}\" width=\"{pw}\" height=\"{ph}\" fill=\"none\" "
             f"stroke=\"#bbb\"/>"]
    if fleet is not None:
        g, lo, mid, hi = fleet
        keep = [i for i in range(len(g)) if ok(g[i], lo[i]) and ok(g[i], hi[i])]
        if keep:
            up = [f"{px(g[i]):.1f},{py(hi[i]):.1f}" for i in keep]
            down = [f"{px(g[i]):.1f},{py(lo[i]):.1f}" for i in reversed(keep)]
            parts.append(f"<polygon points=\"{' '.join(up + down)}\" fill=\"{FLEET}\"/>")
            parts.append(f"<polyline points=\"{path(g, mid)}\" fill=\"none\" stroke=\"{MEDIAN}\" "
                         f"stroke-width=\"1\"/>")
    for x, y, label in limit_curves:
        parts.append(f"<polyline points=\"{path(x, y)}\" fill=\"none\" stroke=\"{LIMIT}\" "
                     f"stroke-dasharray=\"5,3\" stroke-width=\"1.2\"><title>{_e(label)}</title>"
                     f"</polyline>")
    for x, y, label in lines:
        parts.append(f"<polyline points=\"{path(x, y)}\" fill=\"none\" stroke=\"{UNIT}\" "
                     f"stroke-width=\"1.8\"><title>{_e(label)}</title></polyline>")
        parts.extend(f"<circle cx=\"{px(a):.1f}\" cy=\"{py(b):.1f}\" r=\"2\" fill=\"{UNIT}\"/>"
                     for a, b in zip(x, y) if ok(a, b))
    back = (lambda v: 10 ** v) if log_x else (lambda v: v)
    backy = (lambda v: 10 ** v) if log_y else (lambda v: v)
    for v in (a0, a1):
        parts.append(f"<text x=\"{left + pw * (v - a0) / (a1 - a0):.1f}\" y=\"{top + ph + 13}\" "
                     f"text-anchor=\"{'start' if v == a0 else 'end'}\">{_e(_g(back(v)))}</text>")
    for v in (b0, b1):
        parts.append(f"<text x=\"{left - 4}\" y=\"{top + ph * (1 - (v - b0) / (b1 - b0)) + 4:.1f}\" "
                     f"text-anchor=\"end\">{_e(_g(backy(v)))}</text>")
    parts.append(f"<text x=\"{left + pw / 2:.1f}\" y=\"{height - 6}\" text-anchor=\"middle\">"
                 f"{_e(x_label)}</text>")
    parts.append(f"<text x=\"12\" y=\"{top + ph / 2:.1f}\" text-anchor=\"middle\" transform=\""
                 f"rotate(-90 12 {top + ph / 2:.1f})\">{_e(y_label)}</text>")
    svg = (f"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{width}\" height=\"{height}\" "
           f"font-family=\"sans-serif\" font-size=\"11\">{''.join(parts)}</svg>")
    return f"<figure class=\"plot\">{svg}<figcaption>{_e(title)}</figcaption></figure>\n"


def _e(x):
    return html.escape(str(x), quote=True)


def _g(x):
    return f"{x:.3g}"
