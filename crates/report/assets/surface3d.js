// imutherm's 3D ADEV view: σ(τ, T) as a surface on a 2D canvas (no WebGL,
// so that it draws anywhere, headless and without a GPU included).
// x = log10 τ, y = temperature, z = log10 σ; each cell of the grid is
// projected, sorted back to front and filled by its height. Axes carry
// decade ticks on τ and σ and plain ticks on T; a colour bar gives σ;
// the vertex nearest the pointer is read out; dragging turns the view.
// The canvas says what it drew: data-rendered (cells), data-labels (every
// text drawn, as JSON) and data-hover (the value read out), and
// window.imuthermSurfaces holds {id, labels(), hover()} per view.
function imuthermSurface(id) {
  var c = document.getElementById(id), g = c.getContext('2d');
  var rows = JSON.parse(document.getElementById(id + '-data').textContent);
  var unit = c.dataset.unit, W = c.width, H = c.height;
  var SUP = {'-': '⁻', '0': '⁰', '1': '¹', '2': '²', '3': '³', '4': '⁴',
    '5': '⁵', '6': '⁶', '7': '⁷', '8': '⁸', '9': '⁹'};
  function decade(k) {
    return '10' + String(k).split('').map(function (ch) { return SUP[ch]; }).join('');
  }
  function fmt(v) {
    var a = Math.abs(v);
    if (a !== 0 && (a < 1e-3 || a >= 1e5)) {
      return v.toExponential(2).replace(/\.?0+e/, 'e');
    }
    return String(Number(v.toPrecision(3)));
  }
  var xs = [], ys = [], zs = [];
  rows.forEach(function (r) {
    ys.push(r.t);
    r.p.forEach(function (q) { xs.push(q[0]); zs.push(q[1]); });
  });
  function range(a) {
    var lo = Math.min.apply(null, a), hi = Math.max.apply(null, a);
    return hi > lo ? [lo, hi] : [lo - 0.5, lo + 0.5];
  }
  if (!xs.length) { c.dataset.rendered = '0'; c.dataset.labels = '[]'; return; }
  // Views meant to be compared (raw beside compensated) carry one σ range,
  // data-zrange = "lo,hi" in log10 σ, so that a colour means one σ in both.
  var zr = (c.dataset.zrange || '').split(',').map(Number);
  var Z = zr.length === 2 && zr[1] > zr[0] ? zr : range(zs);
  var X = range(xs), Y = range(ys), yaw = -0.45, pitch = 0.5;
  function n(v, r) { return (v - r[0]) / (r[1] - r[0]) - 0.5; }
  function heat(v) {
    var s = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
    var x = Math.max(0, Math.min(1, v)) * 4, i = Math.min(3, Math.floor(x)), f = x - i;
    var a = s[i], b = s[i + 1];
    return 'rgb(' + [0, 1, 2].map(function (k) { return Math.round(a[k] + (b[k] - a[k]) * f); }).join(',') + ')';
  }
  // The plot's box leaves room for the colour bar on the right.
  var CX = (W - 90) / 2 + 10, CY = H / 2 + 10, SX = 0.52 * (W - 90), SZ = 0.5 * H;
  function proj(x, y, z) {
    var cy = Math.cos(yaw), sy = Math.sin(yaw), cp = Math.cos(pitch), sp = Math.sin(pitch);
    var x1 = x * cy - y * sy, y1 = x * sy + y * cy, z1 = z * cp - y1 * sp, d = y1 * cp + z * sp;
    return [CX + x1 * SX, CY - z1 * SZ, d];
  }
  function at(x, y, z) { return proj(n(x, X), n(y, Y), n(z, Z)); }
  // Decade ticks, and 2 and 5 between them where a range spans little.
  function logTicks(r) {
    var t = [];
    for (var k = Math.ceil(r[0] - 1e-9); k <= Math.floor(r[1] + 1e-9); k++) { t.push([k, decade(k)]); }
    if (t.length < 2) {
      t = [];
      for (var e = Math.floor(r[0]); e <= Math.ceil(r[1]); e++) {
        [1, 2, 5].forEach(function (m) {
          var v = e + Math.log10(m);
          if (v >= r[0] - 1e-9 && v <= r[1] + 1e-9) { t.push([v, m === 1 ? decade(e) : m + '·' + decade(e)]); }
        });
      }
    }
    return t;
  }
  function linTicks(r) {
    var span = r[1] - r[0], raw = span / 5, p = Math.pow(10, Math.floor(Math.log10(raw)));
    var step = [1, 2, 5, 10].map(function (m) { return m * p; }).find(function (s) { return s >= raw; });
    var t = [];
    for (var v = Math.ceil(r[0] / step) * step; v <= r[1] + 1e-9; v += step) { t.push([v, fmt(v)]); }
    return t;
  }
  var labels = [], verts = [], hover = null, boxes = [];
  // A text's box; a tick label that would overlap a text already drawn is
  // left out (the axis names and titles go first), so that no two run
  // into each other (`2·10⁻³10⁻¹`).
  function box(s, x, y, align) {
    var w = g.measureText(s).width, x0 = align === 'center' ? x - w / 2 : align === 'right' ? x - w : x;
    return [x0 - 2, y - 11, x0 + w + 2, y + 3];
  }
  function overlaps(b) {
    return boxes.some(function (o) { return b[0] < o[2] && o[0] < b[2] && b[1] < o[3] && o[1] < b[3]; });
  }
  function text(s, x, y, align, tick) {
    g.textAlign = align || 'left';
    var b = box(s, x, y, g.textAlign);
    if (tick && overlaps(b)) { return; }
    boxes.push(b);
    g.fillText(s, x, y);
    labels.push(s);
  }
  // Axis texts wait until the surface is drawn, so that it hides none.
  var later = [];
  function textLater(s, x, y, align, font, tick) { later.push([s, x, y, align, font, tick]); }
  function line(a, b, colour) {
    g.strokeStyle = colour; g.beginPath(); g.moveTo(a[0], a[1]); g.lineTo(b[0], b[1]); g.stroke();
  }
  // An axis along one edge of the box, its ticks pushed out by `out`.
  function axis(from, to, ticks, place, name, out) {
    line(at.apply(null, from), at.apply(null, to), '#333');
    g.fillStyle = '#222'; g.font = '11px sans-serif';
    ticks.forEach(function (t) {
      var p = at.apply(null, place(t[0])), q = at.apply(null, place(t[0]).map(function (v, i) { return v + out[i]; }));
      line(p, q, '#333');
      textLater(t[1], q[0] + (q[0] - p[0]) * 1.5, q[1] + (q[1] - p[1]) * 1.5 + 4, 'center', '11px sans-serif', true);
    });
    if (name) {
      // The name below the middle of the axis, past its tick labels.
      var mid = from.map(function (v, i) { return (v + to[i]) / 2 + out[i] * 7; });
      var m = at.apply(null, mid);
      textLater(name, m[0], m[1] + 4, 'center', 'bold 12px sans-serif');
    }
  }
  function draw() {
    labels = []; verts = []; boxes = [];
    g.fillStyle = '#fff'; g.fillRect(0, 0, W, H);
    var quads = [];
    for (var i = 0; i + 1 < rows.length; i++) {
      var a = rows[i], b = rows[i + 1];
      for (var j = 0; j + 1 < Math.min(a.p.length, b.p.length); j++) {
        var pts = [[a.p[j][0], a.t, a.p[j][1]], [a.p[j + 1][0], a.t, a.p[j + 1][1]],
          [b.p[j + 1][0], b.t, b.p[j + 1][1]], [b.p[j][0], b.t, b.p[j][1]]];
        var pr = pts.map(function (p) { return at(p[0], p[1], p[2]); });
        var h = pts.reduce(function (s, p) { return s + n(p[2], Z) + 0.5; }, 0) / 4;
        quads.push({p: pr, d: pr.reduce(function (s, q) { return s + q[2]; }, 0), h: h});
      }
    }
    rows.forEach(function (r) {
      r.p.forEach(function (q) { var s = at(q[0], r.t, q[1]); verts.push({s: s, tau: q[0], t: r.t, sig: q[1]}); });
    });
    // The axes behind the surface, on the edges of its base nearest the
    // viewer (τ and T) and up its leftmost corner (σ), ticks pushed out of
    // the box so that the surface does not hide them.
    g.lineWidth = 1;
    var dx = 0.05 * (X[1] - X[0]), dy = 0.05 * (Y[1] - Y[0]);
    var yFront = at(X[0], Y[0], Z[0])[2] < at(X[0], Y[1], Z[0])[2] ? Y[0] : Y[1];
    var xFront = at(X[0], Y[0], Z[0])[2] < at(X[1], Y[0], Z[0])[2] ? X[0] : X[1];
    var oy = yFront === Y[0] ? -dy : dy, ox = xFront === X[0] ? -dx : dx;
    axis([X[0], yFront, Z[0]], [X[1], yFront, Z[0]], logTicks(X),
      function (v) { return [v, yFront, Z[0]]; }, 'τ [s]', [0, oy, 0]);
    axis([xFront, Y[0], Z[0]], [xFront, Y[1], Z[0]], linTicks(Y),
      function (v) { return [xFront, v, Z[0]]; }, 'T [°C]', [ox, 0, 0]);
    var corners = [[X[0], Y[0]], [X[0], Y[1]], [X[1], Y[0]], [X[1], Y[1]]];
    var left = corners.reduce(function (best, k) {
      return at(k[0], k[1], Z[0])[0] < at(best[0], best[1], Z[0])[0] ? k : best;
    });
    var oz = left[0] === X[0] ? -dx : dx;
    axis([left[0], left[1], Z[0]], [left[0], left[1], Z[1]], logTicks(Z),
      function (v) { return [left[0], left[1], v]; }, null, [oz, 0, 0]);
    var top = at(left[0], left[1], Z[1]);
    textLater('σ [' + unit + ']', top[0], top[1] - 12, 'center', 'bold 12px sans-serif');
    quads.sort(function (u, v) { return v.d - u.d; });
    quads.forEach(function (q) {
      g.beginPath(); g.moveTo(q.p[0][0], q.p[0][1]);
      for (var k = 1; k < 4; k++) { g.lineTo(q.p[k][0], q.p[k][1]); }
      g.closePath(); g.fillStyle = heat(q.h); g.fill();
      g.strokeStyle = 'rgba(0,0,0,0.15)'; g.stroke();
    });
    g.fillStyle = '#222';
    // Titles and axis names first, then the colour bar's name: a tick label
    // gives way to them.
    g.font = '14px sans-serif';
    text(c.dataset.title, 10, 20);
    g.font = 'bold 12px sans-serif';
    text('σ [' + unit + ']', W - 76, 40 - 10);
    later.sort(function (a, b) { return (a[5] ? 1 : 0) - (b[5] ? 1 : 0); });
    later.forEach(function (l) { g.font = l[4]; text(l[0], l[1], l[2], l[3], l[5]); });
    later = [];
    // The colour bar: σ on a log scale, its ticks those of the σ axis.
    var bx = W - 70, btop = 40, bot = H - 40;
    for (var y = btop; y < bot; y++) {
      g.fillStyle = heat((bot - y) / (bot - btop)); g.fillRect(bx, y, 14, 1);
    }
    g.strokeStyle = '#333'; g.strokeRect(bx, btop, 14, bot - btop);
    g.fillStyle = '#222'; g.font = '11px sans-serif';
    logTicks(Z).forEach(function (t) {
      var y = bot - (t[0] - Z[0]) / (Z[1] - Z[0]) * (bot - btop);
      line([bx + 14, y], [bx + 18, y], '#333');
      text(t[1], bx + 20, y + 4, 'left', true);
    });
    if (hover) {
      g.fillStyle = '#d00'; g.beginPath(); g.arc(hover.s[0], hover.s[1], 4, 0, 2 * Math.PI); g.fill();
      var msg = 'τ = ' + fmt(Math.pow(10, hover.tau)) + ' s, T = ' + fmt(hover.t) + ' °C, σ = ' +
        fmt(Math.pow(10, hover.sig)) + ' ' + unit;
      g.font = '12px sans-serif';
      var w = g.measureText(msg).width;
      g.fillStyle = 'rgba(255,255,255,0.9)'; g.fillRect(8, H - 26, w + 8, 18);
      g.fillStyle = '#000'; g.textAlign = 'left'; g.fillText(msg, 12, H - 13);
      c.dataset.hover = msg;
    }
    c.dataset.labels = JSON.stringify(labels);
    c.dataset.rendered = String(quads.length);
  }
  function nearest(e) {
    var box = c.getBoundingClientRect(), x = (e.clientX - box.left) * W / box.width, y = (e.clientY - box.top) * H / box.height;
    var best = null, bd = 400;
    verts.forEach(function (v) {
      var d = (v.s[0] - x) * (v.s[0] - x) + (v.s[1] - y) * (v.s[1] - y);
      if (d < bd) { bd = d; best = v; }
    });
    return best;
  }
  var drag = null;
  c.addEventListener('mousedown', function (e) { drag = [e.clientX, e.clientY]; });
  window.addEventListener('mouseup', function () { drag = null; });
  c.addEventListener('mouseleave', function () { if (hover) { hover = null; draw(); } });
  c.addEventListener('mousemove', function (e) {
    if (drag) {
      yaw += (e.clientX - drag[0]) * 0.01;
      pitch = Math.max(-1.5, Math.min(1.5, pitch + (e.clientY - drag[1]) * 0.01));
      drag = [e.clientX, e.clientY];
      hover = null;
    } else {
      var v = nearest(e);
      if (v === hover || (v && hover && v.tau === hover.tau && v.t === hover.t)) { return; }
      hover = v;
    }
    draw();
  });
  draw();
  (window.imuthermSurfaces = window.imuthermSurfaces || []).push({
    id: id,
    labels: function () { return labels.slice(); },
    hover: function () { return c.dataset.hover || null; }
  });
}
