/* asperity2d player: draws one run (asperity scene or belt chain) with synchronised meters.
   Plain JavaScript on canvases; the run is the JSON in #asperity-data (arrays as base64
   little-endian typed arrays). Exposes window.asperityPlayer (state(), seek(t), play(), pause(),
   step(n), setSpeed(x)) for scripts and tests. Everything in SI unless a name says px. */
"use strict";
(function () {
  const root = document.getElementById("asperity-player");
  const D = JSON.parse(document.getElementById("asperity-data").textContent);
  const $ = (sel) => root.querySelector(sel);

  // ---- data ------------------------------------------------------------------------------
  const TYPES = { f8: Float64Array, f4: Float32Array, i1: Int8Array };
  function decode(entry) {
    const bin = atob(entry.data);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new TYPES[entry.dtype](bytes.buffer);
  }
  const T = decode(D.t);
  const N = T.length;
  const S = {};
  for (const name in D.series) S[name] = { values: decode(D.series[name]), shape: D.series[name].shape };
  const t0 = T[0], t1 = T[N - 1];

  // ---- numbers as people read them (the same rule as asperity2d._format.si) ---------------
  const PREFIX = { "-18": "a", "-15": "f", "-12": "p", "-9": "n", "-6": "\u00b5", "-3": "m", "0": "",
                   "3": "k", "6": "M", "9": "G", "12": "T" };
  function exponent(v) {
    if (!isFinite(v) || v === 0) return 0;
    return Math.max(-18, Math.min(12, 3 * Math.floor(Math.log10(Math.abs(v)) / 3)));
  }
  function si(value, unit, digits) {
    digits = digits || 3;
    const sep = unit ? " " : "";
    if (value === null || !isFinite(value)) return "\u2013" + sep + unit;
    if (value === 0) return "0" + sep + unit;
    let base = unit, shift = 0;
    if (unit === "kg") { base = "g"; shift = 3; }
    const scaled = value * Math.pow(10, shift);
    let e = exponent(scaled);
    let m = scaled / Math.pow(10, e);
    let text = m.toFixed(Math.max(0, digits - 1 - Math.floor(Math.log10(Math.abs(m)))));
    if (Math.abs(parseFloat(text)) >= 1000 && e < 12) {
      e += 3; m = scaled / Math.pow(10, e); text = m.toFixed(Math.max(0, digits - 1));
    }
    return text + sep + PREFIX[e] + base;
  }
  function niceStep(span, count) {
    const raw = span / Math.max(count, 1);
    const e = Math.floor(Math.log10(raw));
    for (const m of [1, 2, 2.5, 5, 10]) if (m * Math.pow(10, e) >= raw) return m * Math.pow(10, e);
    return Math.pow(10, e + 1);
  }
  function ticks(lo, hi, factor, count) {
    const a = lo / factor, b = hi / factor, step = niceStep(b - a, count);
    const out = [];
    const lead = Math.floor(Math.log10(step) + 1e-9);
    const decimals = Math.max(0, -lead) + (lead <= 0 && Math.round(step / Math.pow(10, lead) * 1e6) === 2.5e6 ? 1 : 0);
    for (let k = Math.ceil(a / step - 1e-9); k <= Math.floor(b / step + 1e-9); k++) {
      const v = k * step;
      out.push([v * factor, Math.abs(v) < 1e-12 * step ? "0" : v.toFixed(decimals)]);
    }
    return out;
  }
  function prefixed(scale, unit) {
    let base = unit, shift = 0;
    if (unit === "kg") { base = "g"; shift = 3; }
    const e = exponent(scale * Math.pow(10, shift));
    return [Math.pow(10, e - shift), PREFIX[e] + base];
  }

  // ---- time and playback ---------------------------------------------------------------
  function indexAt(t) { // nearest kept sample
    let lo = 0, hi = N - 1;
    if (t <= T[0]) return 0;
    if (t >= T[hi]) return hi;
    while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (T[mid] <= t) lo = mid; else hi = mid; }
    return (t - T[lo] <= T[hi] - t) ? lo : hi;
  }
  function slowAt(t) {
    if (!ui.slowmo.checked) return 1;
    for (const [a, b, s] of D.slow) if (t >= a && t <= b) return s;
    return 1;
  }
  const state = { index: 0, t: t0, playing: false, speed: 1, zoom: 1, panX: 0, panY: 0,
                  camera: D.kind === "asperity" ? D.scene.camera : "whole",
                  exaggeration: D.kind === "asperity" ? D.scene.exaggeration : 1, arrows: true };

  // ---- the page ---------------------------------------------------------------------------
  const ui = {
    title: $(".ap-title"), play: $(".ap-play"), speed: $('[data-ctl="speed"]'),
    slowmo: $('[data-ctl="slowmo"]'), camera: $('[data-ctl="camera"]'), exag: $('[data-ctl="exag"]'),
    arrows: $('[data-ctl="arrows"]'), time: $(".ap-time"), stateBadge: $(".ap-state"), slow: $(".ap-slow"),
    frame: $(".ap-frame"), scene: $(".ap-scene"), track: $(".ap-track"), scrub: $(".ap-scrub"),
    meters: $(".ap-meters"), events: $(".ap-events"), tip: $(".ap-tip"), foot: $(".ap-foot"),
  };
  ui.title.textContent = D.title;
  if (D.kind === "chain") ui.meters.classList.add("chain");
  ui.scrub.max = String(N - 1);
  ui.foot.textContent = "asperity2d " + D.version + " \u00b7 " + N + " of " + D.recorded +
    " recorded samples (every sample inside a slip kept) \u00b7 keys: space play/pause, \u2190 \u2192 step, Home/End";
  if (D.kind !== "asperity") for (const el of root.querySelectorAll(".ap-asperity")) el.style.display = "none";
  else {
    for (const v of [1, 2, 5, 10, 20, 50]) {
      const o = document.createElement("option"); o.value = String(v); o.textContent = "\u00d7" + v;
      ui.exag.appendChild(o);
    }
    if (![1, 2, 5, 10, 20, 50].includes(state.exaggeration)) {
      const o = document.createElement("option"); o.value = String(state.exaggeration);
      o.textContent = "\u00d7" + state.exaggeration; ui.exag.appendChild(o);
    }
    ui.exag.value = String(state.exaggeration);
    ui.camera.value = state.camera;
  }

  function fitCanvas(canvas) { // backing store in device pixels; drawing in CSS px
    const r = canvas.getBoundingClientRect();
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(r.width)), h = Math.max(1, Math.round(r.height));
    if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
      canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
    }
    const ctx = canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    return [ctx, w, h];
  }

  const C = {
    lower: "#7a96be", touching: "#2e9678", outline: "#2d2d32", track: "#787882", ground: "#d6d2c8",
    hatch: "#a09687", substrate: "#5a5046", sliderStick: "#465064", tipsStick: "#ecaa46",
    sliderSlip: "#c82d2d", tipsSlip: "#f6785a", spring: "#961e1e", arrow: "#b41ea0",
    belt: "#5f5f64", beltMark: "#ebebeb", wall: "#6e645a", massStick: "#4678c8", massFast: "#d73c2d",
    massSlow: "#f0a028", damper: "#464650", band: "#ffe4e0", cursor: "#141414",
  };

  // ---- the asperity scene ---------------------------------------------------------------
  const G = D.scene;
  function sceneCamera(W, H) {
    let left, width;
    if (D.kind === "asperity") {
      if (state.camera === "follow") { left = S.camera_left.values[state.index]; width = G.view_width; }
      else { left = G.whole_left; width = G.whole_width; }
    } else { left = 0; width = 1; }
    const scale = W / width;
    const vscale = scale * state.exaggeration;
    let topPx = 40, yRef = 0;
    if (D.kind === "asperity") {
      const bar = Math.max(8, Math.min(0.3 * G.base * scale, 18));
      const content = (G.y_top - G.floor) * vscale;
      topPx = Math.max(12 + bar, 0.5 * (H - content - 26) + bar * 0.5);
      yRef = G.y_top;
    }
    return { left, scale, vscale, topPx, yRef, W, H, zoom: state.zoom, panX: state.panX, panY: state.panY };
  }
  function toPx(cam, X, Y) { // world (m) -> canvas CSS px, the user's zoom and pan applied
    const bx = (X - cam.left) * cam.scale, by = cam.topPx - (Y - cam.yRef) * cam.vscale;
    return [(bx - cam.W / 2) * cam.zoom + cam.W / 2 + cam.panX, (by - cam.H / 2) * cam.zoom + cam.H / 2 + cam.panY];
  }
  function poly(ctx, pts, fill, stroke) {
    ctx.beginPath(); ctx.moveTo(pts[0][0], pts[0][1]);
    for (let i = 1; i < pts.length; i++) ctx.lineTo(pts[i][0], pts[i][1]);
    ctx.closePath(); ctx.fillStyle = fill; ctx.fill();
    if (stroke) { ctx.strokeStyle = stroke; ctx.lineWidth = 1; ctx.stroke(); }
  }
  function zigzag(ctx, x0, y0, x1, y1, coils, amp) {
    const dx = x1 - x0, dy = y1 - y0, len = Math.hypot(dx, dy);
    ctx.beginPath(); ctx.moveTo(x0, y0);
    if (len > 0) {
      const ux = dx / len, uy = dy / len, nx = -uy, ny = ux, a = 0.12 * len, b = 0.88 * len;
      ctx.lineTo(x0 + ux * a, y0 + uy * a);
      for (let i = 0; i < 2 * coils; i++) {
        const s = a + (b - a) * (i + 0.5) / (2 * coils), side = i % 2 ? -amp : amp;
        ctx.lineTo(x0 + ux * s + nx * side, y0 + uy * s + ny * side);
      }
      ctx.lineTo(x0 + ux * b, y0 + uy * b);
    }
    ctx.lineTo(x1, y1); ctx.stroke();
  }
  function arrow(ctx, x0, y0, x1, y1, colour, width) {
    const len = Math.hypot(x1 - x0, y1 - y0);
    if (len < 1) return;
    const ux = (x1 - x0) / len, uy = (y1 - y0) / len, head = Math.min(8, 0.6 * len + 2);
    const bx = x1 - ux * head, by = y1 - uy * head;
    ctx.strokeStyle = colour; ctx.lineWidth = width; ctx.beginPath(); ctx.moveTo(x0, y0); ctx.lineTo(bx, by);
    ctx.stroke();
    ctx.fillStyle = colour; ctx.beginPath(); ctx.moveTo(x1, y1);
    ctx.lineTo(bx - uy * 0.45 * head, by + ux * 0.45 * head); ctx.lineTo(bx + uy * 0.45 * head, by - ux * 0.45 * head);
    ctx.closePath(); ctx.fill();
  }
  function forceShares(i) { // share of the contact force on each touching lower asperity (as the GIF)
    const n = G.n_lower, shares = new Float64Array(n);
    let total = 0, count = 0;
    for (let j = 0; j < n; j++) {
      if (!S.lower_contact.values[j * N + i]) continue;
      count++;
      const load = G.stiffness[j] * Math.max(-S.lower_dy.values[j * N + i], 0);
      shares[j] = load; total += load;
    }
    for (let j = 0; j < n; j++) {
      if (!S.lower_contact.values[j * N + i]) continue;
      shares[j] = total > 0 ? shares[j] / total : 1 / count;
    }
    return shares;
  }

  let drawn = {};
  function drawAsperity(ctx, W, H) {
    const i = state.index, cam = sceneCamera(W, H);
    const x = S.x.values[i], y = S.y.values[i];
    const slipping = !!S.slipping.values[i];
    const bar = Math.max(8, Math.min(0.3 * G.base * cam.scale, 18)) * cam.zoom;
    // world x at the canvas's left and right edges (zoom and pan undone), plus a base of margin
    const viewLo = cam.left + ((-cam.W / 2 - cam.panX) / cam.zoom + cam.W / 2) / cam.scale - G.base;
    const viewHi = cam.left + ((cam.W / 2 - cam.panX) / cam.zoom + cam.W / 2) / cam.scale + G.base;
    // ground and its hatching (world-fixed, so camera motion shows)
    const g = toPx(cam, 0, G.floor)[1];
    ctx.fillStyle = C.ground; ctx.fillRect(0, g, W, H - g);
    ctx.strokeStyle = C.hatch; ctx.lineWidth = 1; ctx.beginPath();
    const step = 0.5 * G.pitch;
    for (let k = Math.floor(viewLo / step); k * step < viewHi; k++) {
      const px = toPx(cam, k * step, 0)[0];
      ctx.moveTo(px, g + 2); ctx.lineTo(px - 6, g + 10);
    }
    ctx.stroke();
    ctx.strokeStyle = C.outline; ctx.beginPath(); ctx.moveTo(0, g); ctx.lineTo(W, g); ctx.stroke();
    ctx.strokeStyle = C.substrate; ctx.lineWidth = 2;
    for (const line of G.substrate) {
      ctx.beginPath();
      line.forEach((p, k) => { const q = toPx(cam, p[0], p[1]); if (k) ctx.lineTo(q[0], q[1]); else ctx.moveTo(q[0], q[1]); });
      ctx.stroke();
    }
    const lower = [];
    const n = G.n_lower;
    for (let j = 0; j < n; j++) {
      const dx = S.lower_dx ? S.lower_dx.values[j * N + i] : 0;
      const dy = S.lower_dy.values[j * N + i];
      const cx = G.lower_x[j] + dx;
      const touching = !!S.lower_contact.values[j * N + i];
      lower.push({ x: cx, y: dy + G.summits[j], dy: dy, contact: touching });
      if (cx < viewLo - G.base || cx > viewHi + G.base) continue;
      const foot = toPx(cam, cx, dy + G.levels[j]);
      ctx.strokeStyle = C.track; ctx.lineWidth = 1;
      zigzag(ctx, foot[0], g, foot[0], foot[1], 4, Math.max(2, Math.min(0.12 * G.base * cam.scale * cam.zoom, 5)));
      poly(ctx, G.lower_polys[j].map((p) => toPx(cam, cx + p[0], dy + p[1])), touching ? C.touching : C.lower, C.outline);
    }
    for (let j = 0; j < G.upper_x.length; j++)
      poly(ctx, G.upper_polys[j].map((p) => toPx(cam, x + G.upper_x[j] + p[0], y + p[1])),
           slipping ? C.tipsSlip : C.tipsStick, C.outline);
    const b0 = toPx(cam, x + G.rear, y), b1 = toPx(cam, x + G.front, y);
    ctx.fillStyle = slipping ? C.sliderSlip : C.sliderStick;
    ctx.fillRect(b0[0], b0[1] - bar, b1[0] - b0[0], bar);
    ctx.strokeStyle = C.outline; ctx.lineWidth = 1; ctx.strokeRect(b0[0], b0[1] - bar, b1[0] - b0[0], bar);
    drawn = { slider_bar: [b0[0], b0[1] - bar, b1[0], b0[1]], lower_px: [] };
    if (G.has_drive) {
      const end = toPx(cam, S.drive_x.values[i] + G.front + G.pitch, 0)[0], sy = b0[1] - 0.5 * bar;
      ctx.strokeStyle = C.spring; ctx.lineWidth = 2;
      zigzag(ctx, b1[0], sy, end, sy, 8, Math.max(3, 0.3 * bar));
      ctx.fillStyle = C.spring; ctx.fillRect(end, sy - 0.6 * bar, 0.72 * bar, 1.2 * bar);
      drawn.drive_end_px = end;
    }
    if (state.arrows && G.force_scale > 0) {
      const shares = forceShares(i), k = G.arrow_px / G.force_scale;
      const fx = -S.friction_force.values[i] * k, fy = S.normal_force.values[i] * k;
      for (let j = 0; j < n; j++) {
        if (!(shares[j] > 0)) continue;
        const tip = toPx(cam, lower[j].x, lower[j].y);
        arrow(ctx, tip[0], tip[1], tip[0] + fx * shares[j], tip[1] - fy * shares[j], C.arrow, 2);
      }
    }
    for (const l of lower) drawn.lower_px.push(toPx(cam, l.x, l.y));
    // scale bar and the key
    const scalePx = cam.scale * cam.zoom, len = niceLength(90 / scalePx);
    ctx.fillStyle = "rgba(255,255,255,0.85)"; ctx.fillRect(0, H - 22, W, 22);
    ctx.fillStyle = "#000"; ctx.fillRect(10, H - 13, len * scalePx, 4);
    ctx.font = "12px system-ui, sans-serif"; ctx.textBaseline = "middle";
    const vert = state.exaggeration > 1 ? "   vertical \u00d7" + state.exaggeration : "";
    ctx.fillText(si(len, "m", 1) + vert, 16 + len * scalePx, H - 11);
    if (state.arrows && G.force_scale > 0) {
      const k = G.arrow_px / G.force_scale, f = niceLength(30 / k);
      arrow(ctx, W - 10 - f * k, H - 11, W - 10, H - 11, C.arrow, 2);
      ctx.fillStyle = C.arrow; ctx.textAlign = "right";
      ctx.fillText("contact force on the slider " + si(f, "N", 1), W - 16 - f * k, H - 11);
      ctx.textAlign = "left";
    }
    return { slider: { x: x, y: y }, drive_end: G.has_drive ? S.drive_x.values[i] : null, lower: lower,
             slipping: slipping, camera: cam };
  }
  function niceLength(target) {
    const e = Math.floor(Math.log10(target));
    for (const m of [5, 2, 1]) if (m * Math.pow(10, e) <= target) return m * Math.pow(10, e);
    return Math.pow(10, e);
  }

  // ---- the belt chain ---------------------------------------------------------------------
  function drawChain(ctx, W, H) {
    const i = state.index, n = G.n, wall = 16, cam = { zoom: state.zoom, panX: state.panX, panY: state.panY, W, H };
    const Z = (px, py) => [(px - W / 2) * cam.zoom + W / 2 + cam.panX, (py - H / 2) * cam.zoom + H / 2 + cam.panY];
    const pitch = (W - 2 * wall) / (n + 1), boxW = Math.min(0.42 * pitch, 90);
    const scale = G.reach > 0 ? 0.28 * pitch / G.reach : 1;
    const beltTop = H - 60, boxH = Math.min(0.42 * (beltTop - 30), 70), boxTop = beltTop - boxH;
    const z = cam.zoom;
    ctx.fillStyle = C.wall;
    for (const x0 of [0, W - wall]) { const p = Z(x0, boxTop - 16); ctx.fillRect(p[0], p[1], wall * z, (beltTop - boxTop + 16) * z); }
    const b0 = Z(wall, beltTop);
    ctx.fillStyle = C.belt; ctx.fillRect(b0[0], b0[1], (W - 2 * wall) * z, 18 * z);
    const off = ((S.belt_s.values[i] * scale) % 24 + 24) % 24;
    ctx.strokeStyle = C.beltMark; ctx.lineWidth = 2; ctx.beginPath();
    for (let m = off - 24; m < W; m += 24) {
      if (m <= wall || m >= W - wall - 8) continue;
      const p = Z(m, beltTop + 4), q = Z(m + 7, beltTop + 9), r = Z(m, beltTop + 14);
      ctx.moveTo(p[0], p[1]); ctx.lineTo(q[0], q[1]); ctx.lineTo(r[0], r[1]);
    }
    ctx.stroke();
    const centres = [], masses = [];
    for (let j = 0; j < n; j++) {
      const xj = S["x" + j].values[i];
      centres.push(wall + pitch * (j + 1) + xj * scale);
      masses.push({ x: xj, state: S.state.values[j * N + i] });
    }
    const anchors = [wall].concat(centres, [W - wall]);
    const ys = boxTop + 0.3 * boxH, yd = boxTop + 0.72 * boxH;
    for (let j = 0; j <= n; j++) {
      const a = anchors[j] + (j > 0 ? boxW / 2 : 0), b = anchors[j + 1] - (j < n ? boxW / 2 : 0);
      if (G.k[j] > 0) {
        const y = G.c[j] > 0 ? ys : 0.5 * (ys + yd), p = Z(a, y), q = Z(b, y);
        ctx.strokeStyle = C.spring; ctx.lineWidth = 2; zigzag(ctx, p[0], p[1], q[0], q[1], 6, Math.min(6, 0.12 * boxH) * z);
      }
      if (G.c[j] > 0) {
        const p = Z(a, yd), q = Z(b, yd), mid = 0.5 * (p[0] + q[0]), half = Math.min(7, 0.12 * boxH) * z;
        ctx.strokeStyle = C.damper; ctx.lineWidth = 2; ctx.beginPath();
        ctx.moveTo(p[0], p[1]); ctx.lineTo(mid, p[1]); ctx.moveTo(mid, p[1] - 0.7 * half); ctx.lineTo(mid, p[1] + 0.7 * half);
        const c0 = mid - 0.18 * (q[0] - p[0]), c1 = mid + 0.12 * (q[0] - p[0]);
        ctx.moveTo(c0, p[1] - half); ctx.lineTo(c1, p[1] - half); ctx.lineTo(c1, p[1] + half); ctx.lineTo(c0, p[1] + half);
        ctx.moveTo(c1, p[1]); ctx.lineTo(q[0], q[1]); ctx.stroke();
      }
    }
    const colours = { 0: C.massStick, 1: C.massFast, "-1": C.massSlow };
    ctx.textAlign = "center";
    drawn = { masses_px: [] };
    for (let j = 0; j < n; j++) {
      const p = Z(centres[j] - boxW / 2, boxTop);
      ctx.fillStyle = colours[masses[j].state] || C.massStick;
      ctx.fillRect(p[0], p[1], boxW * z, (boxH - 1) * z);
      ctx.strokeStyle = C.outline; ctx.lineWidth = 1; ctx.strokeRect(p[0], p[1], boxW * z, (boxH - 1) * z);
      ctx.fillStyle = "#fff"; ctx.font = "bold 13px system-ui, sans-serif"; ctx.textBaseline = "top";
      ctx.fillText("m" + (j + 1), p[0] + boxW * z / 2, p[1] + 4);
      ctx.fillStyle = "#000"; ctx.font = "12px system-ui, sans-serif"; ctx.textBaseline = "bottom";
      ctx.fillText(masses[j].state === 0 ? "STICK" : "SLIP", p[0] + boxW * z / 2, p[1] - 3);
      drawn.masses_px.push(Z(centres[j], boxTop + boxH / 2));
      if (G.force_scale > 0) {
        const k = 0.3 * pitch / G.force_scale, a = Z(centres[j], beltTop + 9), f = S["f" + j].values[i];
        arrow(ctx, a[0], a[1], a[0] + f * k * z, a[1], C.arrow, 3);
      }
    }
    ctx.textAlign = "left"; ctx.textBaseline = "middle";
    const len = niceLength(60 / scale);
    ctx.fillStyle = "#000"; ctx.fillRect(10, H - 13, len * scale, 4);
    ctx.font = "12px system-ui, sans-serif";
    ctx.fillText(si(len, "m", 1) + " displacement (rest spacing not to scale)", 16 + len * scale, H - 11);
    return { masses: masses, belt_s: S.belt_s.values[i], camera: { scale: scale, pitch: pitch, wall: wall, W, H } };
  }

  // ---- meters ----------------------------------------------------------------------------
  const meters = D.meters.map((spec) => {
    const canvas = document.createElement("canvas");
    canvas.setAttribute("aria-label", spec.title);
    ui.meters.appendChild(canvas);
    const traces = spec.traces.map((tr) => ({ ...tr, values: S[tr.series].values }));
    const [tfactor, tunit] = prefixed(Math.max(Math.abs(t0), Math.abs(t1)), "s");
    return { spec, canvas, traces, tfactor, tunit, cache: null, plot: null };
  });
  function meterPlot(W, H, m) {
    return { x0: 46, y0: m.traces.length > 1 ? 38 : 24, x1: W - 10, y1: H - 20 };
  }
  function meterX(p, t) { return p.x0 + (t - t0) / ((t1 - t0) || 1) * (p.x1 - p.x0); }
  function meterY(p, m, v) {
    const [lo, hi] = m.spec.limits;
    return Math.min(p.y1, Math.max(p.y0, p.y1 - (v - lo) / (hi - lo) * (p.y1 - p.y0)));
  }
  function drawMeterStatic(m, W, H) { // axes, slip bands and whole traces, cached per size
    const dpr = window.devicePixelRatio || 1;
    const off = document.createElement("canvas");
    off.width = Math.round(W * dpr); off.height = Math.round(H * dpr);
    const ctx = off.getContext("2d"); ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    const p = meterPlot(W, H, m); m.plot = p;
    ctx.fillStyle = "#fafafc"; ctx.fillRect(0, 0, W, H);
    ctx.fillStyle = "#fff"; ctx.fillRect(p.x0, p.y0, p.x1 - p.x0, p.y1 - p.y0);
    if (D.kind === "asperity") {
      ctx.fillStyle = C.band;
      for (const [a, b] of D.slips) {
        const xa = meterX(p, a), xb = Math.max(meterX(p, b), xa + 1);
        ctx.fillRect(xa, p.y0, xb - xa, p.y1 - p.y0);
      }
    }
    ctx.font = "11px system-ui, sans-serif"; ctx.fillStyle = "#777"; ctx.strokeStyle = "#e6e6ea"; ctx.lineWidth = 1;
    ctx.textAlign = "right"; ctx.textBaseline = "middle";
    const count = Math.max(3, Math.min(5, Math.floor((p.y1 - p.y0) / 24)));
    for (const [v, label] of ticks(m.spec.limits[0], m.spec.limits[1], m.spec.factor, count)) {
      const y = Math.round(meterY(p, m, v)) + 0.5;
      ctx.beginPath(); ctx.moveTo(p.x0, y); ctx.lineTo(p.x1, y); ctx.stroke();
      ctx.fillText(label, p.x0 - 4, y);
    }
    ctx.textAlign = "center"; ctx.textBaseline = "top";
    for (const [v, label] of ticks(t0, t1, m.tfactor, 6)) {
      const x = Math.round(meterX(p, v)) + 0.5;
      ctx.beginPath(); ctx.moveTo(x, p.y1); ctx.lineTo(x, p.y1 + 3); ctx.stroke();
      if (x < p.x1 - 24) ctx.fillText(label, x, p.y1 + 4);
    }
    ctx.textAlign = "right"; ctx.fillText(m.tunit, p.x1, p.y1 + 4);
    ctx.strokeStyle = "#888"; ctx.strokeRect(p.x0 - 0.5, p.y0 - 0.5, p.x1 - p.x0 + 1, p.y1 - p.y0 + 1);
    ctx.save(); ctx.beginPath(); ctx.rect(p.x0, p.y0, p.x1 - p.x0, p.y1 - p.y0); ctx.clip();
    for (const tr of m.traces) {
      ctx.strokeStyle = tr.colour; ctx.lineWidth = 1.2; ctx.setLineDash(tr.dashed ? [4, 4] : []);
      ctx.beginPath();
      let started = false;
      for (let i = 0; i < N; i++) {
        const v = tr.values[i];
        if (!isFinite(v)) { started = false; continue; }
        const x = meterX(p, T[i]), y = meterY(p, m, v);
        if (started) ctx.lineTo(x, y); else { ctx.moveTo(x, y); started = true; }
      }
      ctx.stroke();
    }
    ctx.restore(); ctx.setLineDash([]);
    ctx.fillStyle = "#000"; ctx.font = "bold 12px system-ui, sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "top";
    ctx.fillText(m.spec.title + " (" + m.spec.unit_label + ")", 6, 5);
    m.cache = off; m.cacheSize = W + "x" + H + "@" + dpr;
  }
  function drawMeter(m, hoverT) {
    const [ctx, W, H] = fitCanvas(m.canvas);
    const dpr = window.devicePixelRatio || 1;
    if (!m.cache || m.cacheSize !== W + "x" + H + "@" + dpr) drawMeterStatic(m, W, H);
    ctx.setTransform(1, 0, 0, 1, 0, 0); ctx.drawImage(m.cache, 0, 0); ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    const p = m.plot, i = state.index;
    const x = meterX(p, T[i]);
    // the future faded: the trace grows with time, as on the GIF
    ctx.fillStyle = "rgba(250,250,252,0.72)"; ctx.fillRect(x + 1, p.y0, p.x1 - x - 1, p.y1 - p.y0);
    ctx.strokeStyle = C.cursor; ctx.lineWidth = 1; ctx.beginPath(); ctx.moveTo(Math.round(x) + 0.5, p.y0);
    ctx.lineTo(Math.round(x) + 0.5, p.y1); ctx.stroke();
    ctx.font = "12px system-ui, sans-serif"; ctx.textBaseline = "top";
    let lx = m.traces.length > 1 ? 8 : W - 10;
    ctx.textAlign = m.traces.length > 1 ? "left" : "right";
    for (const tr of m.traces) {
      const v = tr.values[i];
      if (isFinite(v)) {
        ctx.fillStyle = tr.colour; ctx.strokeStyle = C.cursor;
        ctx.beginPath(); ctx.arc(x, meterY(p, m, v), 3.5, 0, 2 * Math.PI); ctx.fill(); ctx.stroke();
      }
      const text = (m.traces.length > 1 ? tr.label + " " : "") + si(v, m.spec.unit);
      ctx.fillStyle = tr.colour;
      if (m.traces.length > 1) {
        ctx.fillRect(lx, 25, 12, 3); ctx.fillText(text, lx + 16, 20); lx += ctx.measureText(text).width + 34;
      } else { ctx.font = "bold 12px system-ui, sans-serif"; ctx.fillText(text, lx, 5); }
    }
    if (hoverT !== undefined && hoverT !== null) {
      const hx = meterX(p, hoverT);
      ctx.strokeStyle = "rgba(0,0,0,0.35)"; ctx.setLineDash([3, 3]); ctx.beginPath();
      ctx.moveTo(hx, p.y0); ctx.lineTo(hx, p.y1); ctx.stroke(); ctx.setLineDash([]);
    }
    return Math.round(x);
  }

  // ---- timeline --------------------------------------------------------------------------
  function drawTrack() {
    const [ctx, W, H] = fitCanvas(ui.track);
    const x0 = 6, x1 = W - 6, X = (t) => x0 + (t - t0) / ((t1 - t0) || 1) * (x1 - x0);
    ctx.fillStyle = "#f3f4f6"; ctx.fillRect(0, 0, W, H);
    ctx.fillStyle = "#fff"; ctx.fillRect(x0, 8, x1 - x0, H - 16);
    ctx.fillStyle = "#f19a92";
    for (const [a, b] of D.slips) ctx.fillRect(X(a), 8, Math.max(2, X(b) - X(a)), H - 16);
    ctx.fillStyle = "#c82d2d";
    for (const e of D.events) {
      const te = e.t_slip !== undefined ? e.t_slip : e.t;
      if (e.kind === "stick") continue;
      const x = X(te); ctx.beginPath(); ctx.moveTo(x, 8); ctx.lineTo(x - 5, 0); ctx.lineTo(x + 5, 0); ctx.fill();
    }
    const x = X(T[state.index]);
    ctx.fillStyle = C.cursor; ctx.fillRect(Math.round(x) - 1, 4, 2, H - 8);
    ctx.font = "11px system-ui, sans-serif"; ctx.fillStyle = "#555"; ctx.textBaseline = "bottom";
    ctx.textAlign = "left"; ctx.fillText(si(t0, "s"), x0, H); ctx.textAlign = "right"; ctx.fillText(si(t1, "s"), x1, H);
    return { x0, x1, X };
  }
  function buildEvents() {
    const list = D.kind === "asperity" ? D.events.map((e, k) => ({
      t: e.t_slip, label: "slip " + (k + 1) + " at " + si(e.t_slip, "s") + ": peak " + si(e.force_peak, "N") +
        ", drop " + si(e.force_drop, "N") + ", " + si(e.slip_distance, "m") + (e.complete ? "" : " (run ended)") })) :
      D.events.filter((e) => e.kind !== "graze").map((e) => ({ t: e.t, label: "m" + (e.mass + 1) + " " + e.kind + " at " + si(e.t, "s") }));
    if (!list.length) { ui.events.textContent = D.kind === "asperity" ? "no stick\u2013slip events" : "no events"; return; }
    for (const ev of list) {
      const b = document.createElement("button");
      b.type = "button"; b.textContent = ev.label; b.title = "jump to this event";
      b.addEventListener("click", () => { pause(); seek(ev.t); });
      ui.events.appendChild(b);
    }
  }

  // ---- one frame -------------------------------------------------------------------------
  let sceneState = {}, cursors = [], hover = null;
  function render() {
    const [ctx, W, H] = fitCanvas(ui.scene);
    ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, W, H);
    sceneState = D.kind === "asperity" ? drawAsperity(ctx, W, H) : drawChain(ctx, W, H);
    cursors = meters.map((m) => drawMeter(m, hover));
    drawTrack();
    const t = T[state.index];
    ui.time.textContent = "t = " + si(t, "s", 4);
    if (D.kind === "asperity" && G.has_drive) {
      ui.stateBadge.textContent = sceneState.slipping ? "SLIP" : "STICK";
      ui.stateBadge.className = "ap-state " + (sceneState.slipping ? "slip" : "stick");
    } else ui.stateBadge.textContent = "";
    const s = slowAt(t);
    ui.slow.textContent = state.playing && s > 1 ? "\u00d7" + s + " slow" : (s > 1 ? "slip: \u00d7" + s + " slow when playing" : "");
    ui.frame.textContent = "sample " + (state.index + 1) + " / " + N;
    ui.scrub.value = String(state.index);
    ui.play.textContent = state.playing ? "\u275A\u275A pause" : "\u25B6 play";
  }
  let pending = false;
  function requestRender() { if (!pending) { pending = true; requestAnimationFrame(() => { pending = false; render(); }); } }

  function seek(t) { state.t = Math.min(t1, Math.max(t0, t)); state.index = indexAt(state.t); render(); }
  function step(n) {
    pause();
    const dir = n < 0 ? -1 : 1;
    for (let k = 0; k < Math.abs(n); k++) {
      const t = T[state.index], dt = D.frame_step / slowAt(t);
      let j = indexAt(t + dir * dt);
      if (j === state.index) j = Math.min(N - 1, Math.max(0, j + dir));
      state.index = j; state.t = T[j];
    }
    render();
  }
  let last = null;
  function tick(now) {
    if (!state.playing) { last = null; return; }
    if (last !== null) {
      const wall = Math.min(0.1, (now - last) / 1000);
      state.t += wall * D.fps * D.frame_step * state.speed / slowAt(state.t);
      if (state.t >= t1) { state.t = t1; state.playing = false; }
      state.index = indexAt(state.t);
      render();
    }
    last = now;
    requestAnimationFrame(tick);
  }
  function play() { if (state.index >= N - 1) seek(t0); if (!state.playing) { state.playing = true; last = null; requestAnimationFrame(tick); } render(); }
  function pause() { state.playing = false; }

  // ---- controls --------------------------------------------------------------------------
  root.querySelector('[data-act="play"]').addEventListener("click", () => (state.playing ? (pause(), render()) : play()));
  root.querySelector('[data-act="start"]').addEventListener("click", () => { pause(); seek(t0); });
  root.querySelector('[data-act="back"]').addEventListener("click", () => step(-1));
  root.querySelector('[data-act="fwd"]').addEventListener("click", () => step(1));
  root.querySelector('[data-act="reset"]').addEventListener("click", () => { state.zoom = 1; state.panX = 0; state.panY = 0; render(); });
  ui.speed.addEventListener("change", () => { state.speed = parseFloat(ui.speed.value); });
  ui.slowmo.addEventListener("change", render);
  ui.camera.addEventListener("change", () => { state.camera = ui.camera.value; state.zoom = 1; state.panX = 0; state.panY = 0; render(); });
  ui.exag.addEventListener("change", () => { state.exaggeration = parseFloat(ui.exag.value); render(); });
  ui.arrows.addEventListener("change", () => { state.arrows = ui.arrows.checked; render(); });
  ui.scrub.addEventListener("input", () => { pause(); state.index = parseInt(ui.scrub.value, 10); state.t = T[state.index]; render(); });
  ui.track.addEventListener("click", (ev) => { // a click within 6 px of an event's marker jumps to it
    const r = ui.track.getBoundingClientRect(), x0 = 6, x1 = r.width - 6;
    let t = t0 + (ev.clientX - r.left - x0) / (x1 - x0) * (t1 - t0);
    for (const e of D.events) {
      const te = e.t_slip !== undefined ? e.t_slip : e.t;
      if (e.kind !== "stick" && Math.abs(te - t) / (t1 - t0) * (x1 - x0) <= 6) { t = te; break; }
    }
    pause(); seek(t);
  });
  document.addEventListener("keydown", (ev) => {
    if (ev.target && (ev.target.tagName === "INPUT" && ev.target.type !== "range" || ev.target.tagName === "SELECT")) return;
    if (ev.key === " ") { ev.preventDefault(); state.playing ? (pause(), render()) : play(); }
    else if (ev.key === "ArrowRight") { ev.preventDefault(); step(1); }
    else if (ev.key === "ArrowLeft") { ev.preventDefault(); step(-1); }
    else if (ev.key === "Home") { pause(); seek(t0); }
    else if (ev.key === "End") { pause(); seek(t1); }
  });
  // zoom (wheel, about the pointer) and pan (drag)
  ui.scene.addEventListener("wheel", (ev) => {
    ev.preventDefault();
    const r = ui.scene.getBoundingClientRect(), mx = ev.clientX - r.left, my = ev.clientY - r.top;
    const f = Math.exp(-ev.deltaY * 0.0015), z = Math.min(40, Math.max(0.25, state.zoom * f)), k = z / state.zoom;
    state.panX = (mx - r.width / 2) * (1 - k) + state.panX * k;
    state.panY = (my - r.height / 2) * (1 - k) + state.panY * k;
    state.zoom = z; requestRender();
  }, { passive: false });
  let drag = null;
  ui.scene.addEventListener("pointerdown", (ev) => { drag = [ev.clientX, ev.clientY, state.panX, state.panY]; ui.scene.classList.add("dragging"); ui.scene.setPointerCapture(ev.pointerId); });
  ui.scene.addEventListener("pointerup", () => { drag = null; ui.scene.classList.remove("dragging"); });
  ui.scene.addEventListener("pointermove", (ev) => {
    if (drag) { state.panX = drag[2] + ev.clientX - drag[0]; state.panY = drag[3] + ev.clientY - drag[1]; requestRender(); return; }
    if (D.kind !== "asperity") return;
    const r = ui.scene.getBoundingClientRect(), cam = sceneState.camera;
    const bx = (ev.clientX - r.left - cam.W / 2 - cam.panX) / cam.zoom + cam.W / 2;
    const by = (ev.clientY - r.top - cam.H / 2 - cam.panY) / cam.zoom + cam.H / 2;
    const X = cam.left + bx / cam.scale, Y = cam.yRef - (by - cam.topPx) / cam.vscale;
    showTip(ev, "x = " + si(X, "m") + "\ny = " + si(Y, "m") + "\nslider at " + si(S.x.values[state.index], "m"));
  });
  ui.scene.addEventListener("pointerleave", () => hideTip());
  function showTip(ev, text) {
    ui.tip.hidden = false; ui.tip.textContent = text;
    ui.tip.style.left = (ev.clientX + 14) + "px"; ui.tip.style.top = (ev.clientY + 10) + "px";
  }
  function hideTip() { ui.tip.hidden = true; }
  for (const m of meters) {
    m.canvas.addEventListener("mousemove", (ev) => {
      const r = m.canvas.getBoundingClientRect(), p = m.plot;
      if (!p) return;
      const t = t0 + (ev.clientX - r.left - p.x0) / (p.x1 - p.x0) * (t1 - t0);
      if (t < t0 || t > t1) { hover = null; hideTip(); requestRender(); return; }
      const j = indexAt(t);
      hover = T[j];
      showTip(ev, "t = " + si(T[j], "s", 4) + "\n" + m.traces.map((tr) => tr.label + ": " + si(tr.values[j], m.spec.unit, 4)).join("\n") +
              "\nclick to go there");
      requestRender();
    });
    m.canvas.addEventListener("mouseleave", () => { hover = null; hideTip(); requestRender(); });
    m.canvas.addEventListener("click", () => { if (hover !== null) { pause(); seek(hover); } });
  }
  window.addEventListener("resize", requestRender);

  // ---- for scripts and tests -------------------------------------------------------------
  window.asperityPlayer = {
    kind: D.kind, samples: N, t0: t0, t1: t1,
    state: () => ({ t: T[state.index], index: state.index, playing: state.playing, speed: state.speed,
                    zoom: state.zoom, camera_mode: state.camera, exaggeration: state.exaggeration,
                    slow: slowAt(T[state.index]), ...sceneState, drawn: drawn, meter_cursor_px: cursors,
                    meter_plots: meters.map((m) => m.plot) }),
    seek: (t) => { pause(); seek(t); return T[state.index]; },
    play: play, pause: () => { pause(); render(); }, step: step,
    setSpeed: (v) => { state.speed = v; ui.speed.value = String(v); },
    si: si,
  };
  buildEvents();
  render();
})();
