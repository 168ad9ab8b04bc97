// The report's interactive charts. Each figure holding chart data (a
// <script type="application/json" class="chart-data">, written by
// crates/report/src/charts.rs) gets a uPlot chart in place of its static
// SVG on screen; the SVG stays for print and for a browser without
// scripts. The charts are listed in window.imuthermCharts ({u, spec, figure})
// so that a test can find a point's pixel with u.valToPos.
(function () {
  'use strict';
  var charts = [];
  window.imuthermCharts = charts;

  // A number as the legend shows it: four significant digits, no float
  // noise, exponents below 0.001 and from 100 000 on (as the SVG ticks).
  function num(v) {
    if (v == null || !isFinite(v)) return '—';
    if (v === 0) return '0';
    var a = Math.abs(v);
    if (a < 1e-3 || a >= 1e5) {
      return v.toExponential(3).replace(/\.?0+e/, 'e').replace('e+', 'e');
    }
    return String(Number(v.toPrecision(4)));
  }

  // Log axis ticks: the decades labelled, the steps between them left
  // blank; all of them labelled when the axis spans less than two decades.
  function logTicks(u, splits) {
    var decade = function (v) {
      var l = Math.log10(v);
      return Math.abs(l - Math.round(l)) < 1e-6;
    };
    var all = splits.filter(decade).length < 2;
    return splits.map(function (v) { return all || decade(v) ? num(v) : ''; });
  }

  // Linear ticks with as many decimals as their step needs (no 1000.0,
  // no 6.9e-18 where 0 is meant).
  function linTicks(u, splits, axis, space, step) {
    var d = Math.max(0, Math.min(9, -Math.floor(Math.log10(step) + 1e-9)));
    return splits.map(function (v) {
      return Math.abs(v) < step * 1e-6 ? '0' : v.toFixed(d);
    });
  }

  // The band under a trace (confidence interval, min..max of a column),
  // drawn before the lines and only for the traces shown.
  function drawBands(spec) {
    return function (u) {
      var ctx = u.ctx, b = u.bbox;
      ctx.save();
      ctx.beginPath();
      ctx.rect(b.left, b.top, b.width, b.height);
      ctx.clip();
      spec.series.forEach(function (s, k) {
        var shown = u.series[k + 1].show;
        if (!s.lo || !shown) return;
        var key = s.right ? 'T' : 'y', floor = u.scales[key].min;
        var px = function (i) { return u.valToPos(spec.xs[i], 'x', true); };
        var py = function (v) { return u.valToPos(Math.max(v, floor), key, true); };
        ctx.fillStyle = s.colour + '2e';
        var run = [];
        var flush = function () {
          if (run.length > 1) {
            ctx.beginPath();
            run.forEach(function (i, j) { (j ? ctx.lineTo : ctx.moveTo).call(ctx, px(i), py(s.hi[i])); });
            run.slice().reverse().forEach(function (i) { ctx.lineTo(px(i), py(s.lo[i])); });
            ctx.closePath();
            ctx.fill();
          }
          run = [];
        };
        spec.xs.forEach(function (x, i) {
          if (s.lo[i] != null && s.hi[i] != null) run.push(i); else flush();
        });
        flush();
      });
      ctx.restore();
    };
  }

  function options(spec, width) {
    var series = [{
      label: spec.x.label,
      value: function (u, v) { return num(v); },
    }];
    spec.series.forEach(function (s) {
      var one = {
        label: s.label,
        stroke: s.colour,
        width: s.dash ? 1 : 2,
        scale: s.right ? 'T' : 'y',
        spanGaps: true,
        // The value under the cursor and, for a trace with a band, the
        // band's edges there.
        value: function (u, v, si, i) {
          var text = num(v);
          if (v != null && s.lo && i != null && s.lo[i] != null) {
            text += ' [' + num(s.lo[i]) + ', ' + num(s.hi[i]) + ']';
          }
          return text;
        },
      };
      if (s.dash) one.dash = [6, 4];
      if (s.marker) {
        one.paths = function () { return null; };
        one.points = { show: true, size: 11, fill: s.colour, stroke: s.colour };
      }
      series.push(one);
    });
    var axis = function (a, scale, side) {
      return {
        scale: scale,
        side: side,
        label: a.label,
        size: 70,
        values: a.log ? logTicks : linTicks,
        grid: { show: side !== 1 },
      };
    };
    var scales = {
      x: { time: false, distr: spec.x.log ? 3 : 1 },
      y: { distr: spec.y.log ? 3 : 1 },
    };
    var axes = [axis(spec.x, 'x', 2), axis(spec.y, 'y', 3)];
    axes[0].size = 50;
    if (spec.y2) {
      scales.T = { distr: 1 };
      axes.push(axis(spec.y2, 'T', 1));
    }
    return {
      title: spec.title,
      width: width,
      height: 380,
      scales: scales,
      axes: axes,
      series: series,
      cursor: { drag: { x: true, y: spec.y.log } },
      legend: { live: true },
      hooks: { drawAxes: [drawBands(spec)] },
    };
  }

  document.querySelectorAll('figure.plot').forEach(function (figure) {
    var data = figure.querySelector('script.chart-data');
    if (!data || typeof uPlot === 'undefined') return;
    var spec = JSON.parse(data.textContent);
    var holder = document.createElement('div');
    holder.className = 'chart';
    figure.insertBefore(holder, figure.querySelector('figcaption'));
    var note = document.createElement('p');
    note.className = 'chart-note';
    note.textContent = 'Under the cursor: value [' + spec.band + ']. Drag to zoom, double-click to reset, ' +
      'click a legend entry to hide or show its trace.';
    var columns = [spec.xs].concat(spec.series.map(function (s) { return s.y; }));
    var u = new uPlot(options(spec, 720), columns, holder);
    holder.appendChild(note);
    figure.classList.add('live');
    charts.push({ u: u, spec: spec, figure: figure });
  });
})();
