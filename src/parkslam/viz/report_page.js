// parkslam report: draws the map and the plots of the embedded data as SVG,
// links them by time, and checks itself when opened with #selftest.
// Embedded into report.html by viz/report_html.cc; no external code.
'use strict';
(function () {
  const data = JSON.parse(document.getElementById('report-data').textContent);
  const NS = 'http://www.w3.org/2000/svg';
  const pageErrors = [];
  window.addEventListener('error', (e) => pageErrors.push(String(e.message)));

  function el(name, attrs, parent) {
    const node = document.createElementNS(NS, name);
    for (const k in attrs) node.setAttribute(k, attrs[k]);
    if (parent) parent.appendChild(node);
    return node;
  }

  // ---- time selection shared by the map and the plots ----
  const loc = data.localization;
  const listeners = [];
  let selected = null;
  function nearestIndex(ts, t) {
    let lo = 0, hi = ts.length - 1;
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (ts[mid] < t) lo = mid; else hi = mid;
    }
    return Math.abs(ts[lo] - t) <= Math.abs(ts[hi] - t) ? lo : hi;
  }
  function select(t) {
    if (!loc || loc.t.length === 0) return;
    const i = nearestIndex(loc.t, t);
    selected = i;
    for (const f of listeners) f(i);
  }

  // ---- the map ----
  function drawMap() {
    const host = document.getElementById('map');
    if (!data.map && !data.trajectories) { host.textContent = 'no map in this run'; return; }
    const svg = el('svg', {id: 'map-svg', width: '100%', height: '100%'}, host);
    const root = el('g', {}, svg);
    let xmin = Infinity, xmax = -Infinity, ymin = Infinity, ymax = -Infinity;
    const grow = (p) => {
      xmin = Math.min(xmin, p[0]); xmax = Math.max(xmax, p[0]);
      ymin = Math.min(ymin, p[1]); ymax = Math.max(ymax, p[1]);
    };
    const P = (p) => p[0].toFixed(3) + ',' + (-p[1]).toFixed(3);
    const m = data.map || {};
    for (const s of m.truth_slots || []) s.c.forEach(grow);
    for (const s of m.slots || []) s.c.forEach(grow);
    for (const tr of data.trajectories || []) tr.xy.forEach(grow);
    if (!isFinite(xmin)) { xmin = ymin = 0; xmax = ymax = 1; }
    const pad = 3;
    let view = {x: xmin - pad, y: -ymax - pad, w: xmax - xmin + 2 * pad, h: ymax - ymin + 2 * pad};
    const setView = () => svg.setAttribute('viewBox', [view.x, view.y, view.w, view.h].join(' '));
    setView();
    const unit = Math.max(view.w, view.h) / 800;  // about a screen pixel

    const missed = new Set(m.missed || []);
    (m.truth_slots || []).forEach((s, k) => {
      el('polygon', {points: s.c.map(P).join(' '), fill: 'none',
                     stroke: missed.has(k) ? '#d62728' : '#b0b0b0',
                     'stroke-width': missed.has(k) ? 3 * unit : unit,
                     'stroke-dasharray': missed.has(k) ? 6 * unit : 'none',
                     class: missed.has(k) ? 'slot-missed' : 'slot-truth'}, root);
    });
    const errColour = (e) => {
      const f = Math.max(0, Math.min(1, e / 0.1));  // 0 m green .. 0.10 m red
      return 'rgb(' + Math.round(44 + f * (214 - 44)) + ',' + Math.round(160 - f * (160 - 39)) +
             ',' + Math.round(44 - f * (44 - 40)) + ')';
    };
    for (const s of m.slots || []) {
      const fill = s.verdict === 'matched' ? errColour(s.err_m) : 'none';
      const stroke = s.verdict === 'spurious' ? '#e377c2' : s.verdict === 'duplicate' ? '#9467bd' : '#555';
      const poly = el('polygon', {points: s.c.map(P).join(' '), fill: fill, 'fill-opacity': 0.55,
                                  stroke: stroke, 'stroke-width': unit, class: 'slot-' + s.verdict}, root);
      el('title', {}, poly).textContent = 'slot ' + s.id + ' (' + s.verdict +
          (s.verdict === 'matched' ? ', corner error ' + (100 * s.err_m).toFixed(1) + ' cm' +
           (s.id_right ? (s.id_worn_read ? ', ID read from worn paint' : '') : ', wrong ID') : '') + ')';
      // Corners a camera saw as dots coloured by their error; corners only
      // guessed (placed by the depth prior) as hollow rings.
      s.c.forEach((c, k) => {
        const seen = !s.observed || s.observed[k];
        const err = s.corner_err_m ? s.corner_err_m[k] : null;
        const dot = el('circle', {cx: c[0], cy: -c[1], r: 0.18,
                                  fill: seen ? (err === null ? '#555' : errColour(err)) : '#fff',
                                  stroke: seen ? 'none' : '#777', 'stroke-width': unit,
                                  class: seen ? 'corner-observed' : 'corner-guessed'}, root);
        el('title', {}, dot).textContent = 'slot ' + s.id + ' corner ' + k +
            (seen ? ' (observed' : ' (guessed, never observed') +
            (err === null ? ')' : ', error ' + (100 * err).toFixed(1) + ' cm)');
      });
      const cx = (s.c[0][0] + s.c[1][0] + s.c[2][0] + s.c[3][0]) / 4;
      const cy = (s.c[0][1] + s.c[1][1] + s.c[2][1] + s.c[3][1]) / 4;
      const label = el('text', {x: cx, y: -cy, 'font-size': 0.8, 'text-anchor': 'middle',
                                'dominant-baseline': 'middle',
                                fill: s.verdict === 'matched' && !s.id_right ? '#d62728' :
                                      s.temporary ? '#e07b00' : '#222',
                                'font-weight': s.verdict === 'matched' && !s.id_right ? 'bold' : 'normal'},
                        root);
      label.textContent = (s.verdict === 'matched' && !s.id_right ? '\u2717' : '') + s.id;
    }
    for (const t of m.truth_tags || []) {
      el('rect', {x: t.p[0] - 0.3, y: -t.p[1] - 0.3, width: 0.6, height: 0.6, fill: '#000',
                  class: 'tag-truth'}, root);
    }
    for (const t of m.tags || []) {
      const r = el('rect', {x: t.p[0] - 0.2, y: -t.p[1] - 0.2, width: 0.4, height: 0.4, fill: '#17becf',
                            class: 'tag-map'}, root);
      el('title', {}, r).textContent = 'tag ' + t.id;
    }
    const lines = [];
    for (const tr of data.trajectories || []) {
      const line = el('polyline', {points: tr.xy.map(P).join(' '), fill: 'none', stroke: tr.colour,
                                   'stroke-width': (tr.width || 1.5) * unit, 'stroke-linejoin': 'round',
                                   class: 'trajectory'}, root);
      lines.push([tr, line]);
    }
    // Legend with toggles.
    const legend = document.getElementById('map-legend');
    for (const [tr, line] of lines) {
      const label = document.createElement('label');
      const box = document.createElement('input');
      box.type = 'checkbox'; box.checked = !tr.hidden;
      if (tr.hidden) line.style.display = 'none';
      box.addEventListener('change', () => { line.style.display = box.checked ? '' : 'none'; });
      const swatch = document.createElement('span');
      swatch.className = 'swatch'; swatch.style.background = tr.colour;
      label.append(box, swatch, ' ' + tr.name);
      legend.appendChild(label);
    }
    // The car: a circle and its heading, at the true (green) and estimated (blue) pose.
    const marker = el('g', {id: 'marker', visibility: 'hidden'}, root);
    const truthDot = el('circle', {r: 0.6, fill: 'none', stroke: '#2a9d2a', 'stroke-width': 3 * unit}, marker);
    const estDot = el('circle', {r: 0.35, fill: '#1f77b4'}, marker);
    const heading = el('line', {stroke: '#1f77b4', 'stroke-width': 3 * unit}, marker);
    listeners.push((i) => {
      marker.setAttribute('visibility', 'visible');
      truthDot.setAttribute('cx', loc.tx[i]); truthDot.setAttribute('cy', -loc.ty[i]);
      estDot.setAttribute('cx', loc.x[i]); estDot.setAttribute('cy', -loc.y[i]);
      heading.setAttribute('x1', loc.x[i]); heading.setAttribute('y1', -loc.y[i]);
      heading.setAttribute('x2', loc.x[i] + 1.5 * Math.cos(loc.yaw[i]));
      heading.setAttribute('y2', -(loc.y[i] + 1.5 * Math.sin(loc.yaw[i])));
      marker.dataset.t = loc.t[i];
      marker.dataset.x = loc.tx[i];
      marker.dataset.y = loc.ty[i];
    });
    // Pan (drag), zoom (wheel) and click (nearest localized pose).
    const toWorld = (evt) => {
      const r = svg.getBoundingClientRect();
      const s = Math.max(view.w / r.width, view.h / r.height);  // preserveAspectRatio meet
      const ox = view.x + view.w / 2 - s * r.width / 2, oy = view.y + view.h / 2 - s * r.height / 2;
      return [ox + s * (evt.clientX - r.left), -(oy + s * (evt.clientY - r.top))];
    };
    svg.addEventListener('wheel', (evt) => {
      evt.preventDefault();
      const p = toWorld(evt), k = evt.deltaY > 0 ? 1.2 : 1 / 1.2;
      view = {x: p[0] - (p[0] - view.x) * k, y: -p[1] - (-p[1] - view.y) * k, w: view.w * k, h: view.h * k};
      setView();
    }, {passive: false});
    let drag = null, moved = false;
    svg.addEventListener('mousedown', (evt) => { drag = [evt.clientX, evt.clientY, view.x, view.y]; moved = false; });
    window.addEventListener('mouseup', () => { drag = null; });
    svg.addEventListener('mousemove', (evt) => {
      if (!drag) return;
      const r = svg.getBoundingClientRect();
      const s = Math.max(view.w / r.width, view.h / r.height);
      if (Math.abs(evt.clientX - drag[0]) + Math.abs(evt.clientY - drag[1]) > 3) moved = true;
      view.x = drag[2] - s * (evt.clientX - drag[0]);
      view.y = drag[3] - s * (evt.clientY - drag[1]);
      setView();
    });
    svg.addEventListener('click', (evt) => {
      if (moved || !loc) return;
      const p = toWorld(evt);
      let best = -1, bestD = Infinity;
      for (let i = 0; i < loc.t.length; ++i) {
        const d = (loc.tx[i] - p[0]) ** 2 + (loc.ty[i] - p[1]) ** 2;
        if (d < bestD) { bestD = d; best = i; }
      }
      if (best >= 0 && bestD < 25) select(loc.t[best]);
    });
    document.getElementById('map-reset').addEventListener('click', () => {
      view = {x: xmin - pad, y: -ymax - pad, w: xmax - xmin + 2 * pad, h: ymax - ymin + 2 * pad};
      setView();
    });
    return {svg: svg, toScreen: (x, y) => {
      const r = svg.getBoundingClientRect();
      const s = Math.max(view.w / r.width, view.h / r.height);
      const ox = view.x + view.w / 2 - s * r.width / 2, oy = view.y + view.h / 2 - s * r.height / 2;
      return [r.left + (x - ox) / s, r.top + (-y - oy) / s];
    }};
  }

  // ---- plots ----
  // spec: {id, series: [{x, y, colour, name, dots}], xlabel, ylabel, band: [lo, hi],
  //        log: bool, time: bool (linked to the map)}
  const plots = {};
  function plot(spec) {
    const host = document.getElementById(spec.id);
    if (!host) return;
    const W = 1000, H = 200, L = 60, R = 10, T = 10, B = 30;
    const svg = el('svg', {viewBox: '0 0 ' + W + ' ' + H, width: '100%', class: 'plot'}, host);
    const tf = spec.log ? (v) => Math.log10(Math.max(v, 1e-3)) : (v) => v;
    let x0 = Infinity, x1 = -Infinity, y0 = spec.ymin === undefined ? Infinity : spec.ymin, y1 = -Infinity;
    for (const s of spec.series) {
      for (let i = 0; i < s.x.length; ++i) {
        if (s.y[i] === null || !isFinite(s.y[i])) continue;
        x0 = Math.min(x0, s.x[i]); x1 = Math.max(x1, s.x[i]);
        y0 = Math.min(y0, tf(s.y[i])); y1 = Math.max(y1, tf(s.y[i]));
      }
    }
    if (spec.band) { y0 = Math.min(y0, tf(spec.band[0])); y1 = Math.max(y1, tf(spec.band[1])); }
    if (!isFinite(x0)) { host.append('no data'); return; }
    if (x1 === x0) x1 = x0 + 1;
    if (y1 === y0) y1 = y0 + 1;
    const sx = (x) => L + (x - x0) / (x1 - x0) * (W - L - R);
    const sy = (y) => T + (1 - (tf(y) - y0) / (y1 - y0)) * (H - T - B);
    el('rect', {x: L, y: T, width: W - L - R, height: H - T - B, fill: '#fafafa', stroke: '#ccc'}, svg);
    if (spec.band) {
      el('rect', {x: L, y: sy(spec.band[1]), width: W - L - R, height: sy(spec.band[0]) - sy(spec.band[1]),
                  fill: '#d8ecd8', class: 'band'}, svg);
    }
    for (let k = 0; k <= 4; ++k) {
      const yv = y0 + (y1 - y0) * k / 4, xv = x0 + (x1 - x0) * k / 4;
      const ty = el('text', {x: L - 4, y: T + (1 - k / 4) * (H - T - B) + 4, 'text-anchor': 'end',
                             'font-size': 11}, svg);
      ty.textContent = spec.log ? (10 ** yv).toPrecision(2) : (Math.abs(yv) < 10 ? yv.toFixed(2) : yv.toFixed(0));
      const tx = el('text', {x: L + k / 4 * (W - L - R), y: H - B + 14, 'text-anchor': 'middle', 'font-size': 11}, svg);
      tx.textContent = xv.toFixed(0);
    }
    el('text', {x: W - R, y: H - 4, 'text-anchor': 'end', 'font-size': 11}, svg).textContent = spec.xlabel;
    el('text', {x: 4, y: T + 10, 'font-size': 11}, svg).textContent = spec.ylabel;
    for (const s of spec.series) {
      if (s.dots) {
        const g = el('g', {fill: s.colour, class: 'series'}, svg);
        for (let i = 0; i < s.x.length; ++i) {
          if (s.y[i] === null || !isFinite(s.y[i])) continue;
          el('rect', {x: sx(s.x[i]) - 2, y: sy(s.y[i]) - 2, width: 4, height: 4}, g);
        }
        continue;
      }
      let d = '', pen = false;
      for (let i = 0; i < s.x.length; ++i) {
        if (s.y[i] === null || !isFinite(s.y[i])) { pen = false; continue; }
        d += (pen ? 'L' : 'M') + sx(s.x[i]).toFixed(1) + ' ' + sy(s.y[i]).toFixed(1);
        pen = true;
      }
      el('path', {d: d, fill: 'none', stroke: s.colour, 'stroke-width': 1.5, class: 'series'}, svg);
    }
    const legend = document.createElement('div');
    legend.className = 'plot-legend';
    for (const s of spec.series) {
      const sw = document.createElement('span');
      sw.className = 'swatch'; sw.style.background = s.colour;
      legend.append(sw, ' ' + s.name + '  ');
    }
    host.appendChild(legend);
    const cursor = el('line', {y1: T, y2: H - B, stroke: '#000', 'stroke-dasharray': '4 3', visibility: 'hidden',
                               class: 'cursor'}, svg);
    const info = {svg: svg, cursor: cursor, toScreenX: null};
    if (spec.time && loc) {
      listeners.push((i) => {
        cursor.setAttribute('x1', sx(loc.t[i])); cursor.setAttribute('x2', sx(loc.t[i]));
        cursor.setAttribute('visibility', 'visible');
        cursor.dataset.t = loc.t[i];
      });
      svg.style.cursor = 'crosshair';
      svg.addEventListener('click', (evt) => {
        const r = svg.getBoundingClientRect();
        const px = (evt.clientX - r.left) / r.width * W;
        if (px < L || px > W - R) return;
        select(x0 + (px - L) / (W - L - R) * (x1 - x0));
      });
      info.timeToClientX = (t) => { const r = svg.getBoundingClientRect(); return r.left + sx(t) / W * r.width; };
      info.clientY = () => { const r = svg.getBoundingClientRect(); return r.top + r.height * 0.5; };
    }
    plots[spec.id] = info;
  }

  let map = null;
  try {
    map = drawMap();
    if (loc) {
      const tracked = (i) => loc.state[i] === 1;
      plot({id: 'plot-error', time: true, xlabel: 'time (s)', ylabel: 'error', ymin: 0, series: [
        {name: 'translation error (m)', colour: '#1f77b4', x: loc.t, y: loc.err_m.map((v, i) => tracked(i) ? v : null)},
        {name: 'yaw error (deg / 10)', colour: '#ff7f0e', x: loc.t,
         y: loc.yaw_err_deg.map((v, i) => tracked(i) ? Math.abs(v) / 10 : null)}]});
      plot({id: 'plot-state', time: true, xlabel: 'time (s)', ylabel: 'state', ymin: 0, series: [
        {name: 'tracking', colour: '#2ca02c', dots: true, x: loc.t, y: loc.state.map((s) => s === 1 ? 2 : null)},
        {name: 'lost', colour: '#d62728', dots: true, x: loc.t, y: loc.state.map((s) => s === 2 ? 1 : null)},
        {name: 'uninitialized', colour: '#7f7f7f', dots: true, x: loc.t, y: loc.state.map((s) => s === 0 ? 0 : null)},
        {name: '(re)localized', colour: '#ff7f0e', dots: true, x: loc.t, y: loc.reloc.map((r) => r ? 2.5 : null)}]});
      plot({id: 'plot-seen', time: true, xlabel: 'time (s)', ylabel: 'landmarks', ymin: 0, series: [
        {name: 'slots used', colour: '#2ca02c', x: loc.t, y: loc.slots},
        {name: 'tags used', colour: '#9467bd', x: loc.t, y: loc.tags}]});
      plot({id: 'plot-nees', time: true, xlabel: 'time (s)', ylabel: 'NEES (log)', log: true,
            band: data.nees_band, series: [
        {name: 'localizer NEES per frame', colour: '#d62728', x: loc.t, y: loc.nees.map((v, i) => tracked(i) ? v : null)}]});
    }
    if (data.ekf) {
      plot({id: 'plot-anees', xlabel: 'time (s)', ylabel: 'ANEES', band: data.ekf.band, ymin: 0, series: [
        {name: 'dead-reckoning EKF: average NEES over ' + data.ekf.runs + ' drives', colour: '#8c564b',
         x: data.ekf.t, y: data.ekf.anees}]});
    }
    if (data.follow) {
      plot({id: 'plot-lateral', xlabel: 'distance along the trace (m)', ylabel: 'lateral (m)',
            series: data.follow.runs.map((r) => ({name: r.name, colour: r.colour,
                                                      x: data.follow.s, y: r.offsets}))});
    }
    if (loc && loc.t.length > 0) select(loc.t[0]);
  } catch (e) {
    pageErrors.push(String(e && e.stack || e));
  }

  // Time from the start of navigation until everything is drawn.
  const drawnMs = performance.now();

  // ---- self-test (#selftest) ----
  function selfTest() {
    const checks = {};
    const marker = document.getElementById('marker');
    checks.map_drawn = !!map && map.svg.querySelectorAll('polygon').length > 0;
    checks.plots_drawn = Object.keys(plots).length > 0 &&
        Object.values(plots).every((p) => p.svg.querySelectorAll('.series').length > 0);
    const rects = {};
    for (const [id, p] of Object.entries(plots)) {
      const r = p.svg.getBoundingClientRect();
      rects[id] = [r.left, r.top, r.width, r.height];
    }
    const r = map ? map.svg.getBoundingClientRect() : null;
    if (r) rects.map = [r.left, r.top, r.width, r.height];
    const error = plots['plot-error'];
    if (error && loc && marker) {
      // A real click event at the place of the plot that shows 40 % of the drive.
      const t = loc.t[0] + 0.4 * (loc.t[loc.t.length - 1] - loc.t[0]);
      const before = marker.dataset.t;
      const x = error.timeToClientX(t), y = error.clientY();
      const target = document.elementFromPoint(x, y);
      target.dispatchEvent(new MouseEvent('click', {clientX: x, clientY: y, bubbles: true}));
      // The marker moved to the pose of the time clicked, to within two
      // screen pixels of the plot's time axis.
      const markerT = Number(marker.dataset.t);
      const i = nearestIndex(loc.t, markerT);
      const pixelS = (loc.t[loc.t.length - 1] - loc.t[0]) / error.svg.getBoundingClientRect().width;
      checks.plot_click_moves_marker = marker.dataset.t !== before && Math.abs(markerT - t) <= 2 * pixelS &&
          loc.t[i] === markerT && Number(marker.dataset.x) === loc.tx[i] && Number(marker.dataset.y) === loc.ty[i];
      // And the reverse: a click on the map at the true pose 70 % into the drive.
      const j = Math.floor(0.7 * (loc.t.length - 1));
      const s = map.toScreen(loc.tx[j], loc.ty[j]);
      const mapTarget = document.elementFromPoint(s[0], s[1]);
      mapTarget.dispatchEvent(new MouseEvent('click', {clientX: s[0], clientY: s[1], bubbles: true}));
      const cursorT = Number(error.cursor.dataset.t);
      const k = nearestIndex(loc.t, cursorT);
      checks.map_click_moves_cursor = cursorT !== loc.t[i] &&
          Math.hypot(loc.tx[k] - loc.tx[j], loc.ty[k] - loc.ty[j]) < 0.5;
    }
    const result = {checks: checks, rects: rects, errors: pageErrors, drawn_ms: drawnMs,
                    ok: pageErrors.length === 0 && Object.values(checks).every((v) => v === true)};
    document.getElementById('selftest-result').textContent = JSON.stringify(result);
  }
  if (location.hash === '#selftest') selfTest();
})();
