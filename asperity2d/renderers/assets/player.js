/* asperity2d player: draws one run (asperity scene or belt chain) with synchronised meters.
   Plain JavaScript on canvases, no library, no build step. Everything in SI unless a name says px.

   A reusable component
   --------------------
     const player = window.AsperityPlayer.create(rootElement, payload, options);
   builds the player inside rootElement (an empty <div>; the offline run.html passes its own)
   and draws `payload` (asperity2d.renderers.player.payload / scene_payload: the JSON with the
   arrays as base64 little-endian typed arrays: {dtype: "f8"|"f4"|"i1", shape, data}).
     player.append(chunk)     add streamed samples: chunk = {start, t, series} with the same
                              per-sample keys and encoding as the payload (player.chunk_payload);
                              a 2-D series has shape [rows, k]. `start` (optional) must equal
                              the number of samples held, or the chunk is refused (an Error).
     player.finish(final)     the run is complete: final = player.final_payload(result) (events,
                              slips, slow-motion intervals, meter limits, title).
     player.onCursor(cb)      cb(t) whenever the user moves this player's time cursor (seek,
                              scrub, play, step, event jump); returns a function that unsubscribes.
     player.setCursor(t)      move the cursor to the sample nearest t without calling back
                              (link several players: a.onCursor(t => b.setCursor(t)) and back).
     player.onView(cb) / player.setView([t0, t1] | null)   the same for the meters' time window
                              (box zoom; null: the whole run), to zoom compared runs together.
     player.destroy()         stop playing, remove listeners and observers, empty rootElement.
     player.api               the scripting/test interface (state(), seek(t), play(), pause(),
                              step(n), setSpeed(x), meters(), zoomMeter(...), exportMeter(...),
                              jumpToEvent(k), ...), also window.asperityPlayer for the page's
                              first player.
   options: {keys: true (keyboard shortcuts on the document), linkName: a label for linked
   players, duration: the expected run length (s) for the time axes while streaming}.
   The offline page boots itself from <script id="asperity-data"> into #asperity-player. */
"use strict";
(function () {
  // ---- data ------------------------------------------------------------------------------
  const TYPES = { f8: Float64Array, f4: Float32Array, i1: Int8Array };
  function decode(entry) {
    const bin = atob(entry.data);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new TYPES[entry.dtype](bytes.buffer);
  }

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
    if (value === null || value === undefined || !isFinite(value)) return "\u2013" + sep + unit;
    if (value === 0) return "0" + sep + unit;
    if (fixedExponent(unit) !== null) { // the units menu's choice: always this prefix
      const f = value / Math.pow(10, fixedExponent(unit));
      return f.toPrecision(digits).replace(/(\.\d*?[1-9])0+$|\.0+$/, "$1").replace(/e\+?/, "e") + sep + PREFIX[fixedExponent(unit)] + unit;
    }
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
    const a = lo / factor, b = hi / factor;
    if (!(b > a)) return [];
    const step = niceStep(b - a, count);
    const out = [];
    const lead = Math.floor(Math.log10(step) + 1e-9);
    const decimals = Math.max(0, -lead) + (lead <= 0 && Math.round(step / Math.pow(10, lead) * 1e6) === 2.5e6 ? 1 : 0);
    for (let k = Math.ceil(a / step - 1e-9); k <= Math.floor(b / step + 1e-9); k++) {
      const v = k * step;
      out.push([v * factor, Math.abs(v) < 1e-12 * step ? "0" : v.toFixed(Math.min(20, decimals))]);
    }
    return out;
  }
  // fixed prefixes per unit (the units menu: {"m": -6, "N": -3, "s": -6, "m/s": 0}); absent: automatic
  const UNITS = {};
  function fixedExponent(unit) { const e = UNITS[unit]; return e === undefined || e === null ? null : e; }
  function prefixed(scale, unit) {
    if (fixedExponent(unit) !== null) return [Math.pow(10, fixedExponent(unit)), PREFIX[fixedExponent(unit)] + unit];
    let base = unit, shift = 0;
    if (unit === "kg") { base = "g"; shift = 3; }
    if (unit === "J" || unit === "m/s" || unit === "N/m") { base = unit; }
    const e = exponent(scale * Math.pow(10, shift));
    return [Math.pow(10, e - shift), PREFIX[e] + base];
  }
  function niceLength(target) {
    const e = Math.floor(Math.log10(target));
    for (const m of [5, 2, 1]) if (m * Math.pow(10, e) <= target) return m * Math.pow(10, e);
    return Math.pow(10, e);
  }
  function robustLimits(arrays, includeZero) { // the 0.5th-99.5th percentiles, padded (as meters.limits)
    const vals = [];
    for (const a of arrays) {
      const stride = Math.max(1, Math.floor(a.length / 20000));
      for (let i = 0; i < a.length; i += stride) if (isFinite(a[i])) vals.push(a[i]);
    }
    if (!vals.length) return [-1, 1];
    vals.sort((p, q) => p - q);
    const at = (q) => vals[Math.min(vals.length - 1, Math.max(0, Math.round(q * (vals.length - 1))))];
    let lo = at(0.005), hi = at(0.995);
    if (includeZero && ((lo > 0 && lo < 0.5 * hi) || (hi < 0 && hi > 0.5 * lo))) { lo = Math.min(lo, 0); hi = Math.max(hi, 0); }
    const span = hi - lo;
    if (!(span > 1e-12 * Math.max(Math.abs(lo), Math.abs(hi), 1e-300))) {
      const half = hi !== 0 ? 0.5 * Math.abs(hi) : 1; return [lo - half, hi + half];
    }
    return [lo - 0.08 * span, hi + 0.08 * span];
  }

  const C = {
    lower: "#7a96be", touching: "#2e9678", outline: "#2d2d32", track: "#787882", ground: "#d6d2c8",
    hatch: "#a09687", substrate: "#5a5046", sliderStick: "#465064", tipsStick: "#ecaa46",
    sliderSlip: "#c82d2d", tipsSlip: "#f6785a", spring: "#961e1e", arrow: "#b41ea0",
    belt: "#5f5f64", beltMark: "#ebebeb", wall: "#6e645a", massStick: "#4678c8", massFast: "#d73c2d",
    massSlow: "#f0a028", damper: "#464650", band: "#ffe4e0", cursor: "#141414", ruler: "#0a6e9a",
    clip: "#000000",
  };
  const PALETTE = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                   "#bcbd22", "#17becf"];
  const STATE_COLOURS = { 0: C.massStick, 1: C.massFast, "-1": C.massSlow };

  const TEMPLATE = `
  <div class="ap-title"></div>
  <div class="ap-bar">
    <button type="button" data-act="start" title="first frame (Home)">|&#x25C0;&#x25C0;</button>
    <button type="button" data-act="back" title="previous frame (&#x2190;)">&#x25C0;|</button>
    <button type="button" data-act="play" class="ap-play" title="play / pause (space)">&#x25B6; play</button>
    <button type="button" data-act="fwd" title="next frame (&#x2192;)">|&#x25B6;</button>
    <label>speed <select data-ctl="speed">
      <option value="0.25">&#xD7;0.25</option><option value="0.5">&#xD7;0.5</option>
      <option value="1" selected>&#xD7;1</option><option value="2">&#xD7;2</option>
      <option value="4">&#xD7;4</option><option value="10">&#xD7;10</option></select></label>
    <label title="play the slips slower, as the GIF does"><input type="checkbox" data-ctl="slowmo" checked> slow motion in slips</label>
    <label class="ap-asperity">view <select data-ctl="camera">
      <option value="follow">follow the slider</option><option value="whole">whole surface</option></select></label>
    <label class="ap-asperity">vertical <select data-ctl="exag"></select></label>
    <label class="ap-asperity"><input type="checkbox" data-ctl="arrows" checked> contact forces</label>
    <button type="button" data-act="ruler" class="ap-asperity" aria-pressed="false" title="measure a distance: drag on the scene">&#x2194; ruler</button>
    <button type="button" data-act="reset" title="undo zoom and pan (wheel zooms, drag pans)">reset view</button>
    <span class="ap-export">frame: <button type="button" data-act="png">PNG</button><button type="button" data-act="svg">SVG</button></span>
  </div>
  <div class="ap-status">
    <span class="ap-time"></span><span class="ap-state"></span><span class="ap-slow"></span>
    <span class="ap-live"></span><span class="ap-frame"></span>
  </div>
  <div class="ap-body">
    <div class="ap-main">
      <div class="ap-stage"><canvas class="ap-scene" aria-label="the scene"></canvas>
        <div class="ap-hint">wheel: zoom &#xB7; drag: pan &#xB7; hover: position, a contact's force</div></div>
      <div class="ap-timeline">
        <canvas class="ap-track" aria-label="timeline: slips shaded, events marked; click to jump"></canvas>
        <input type="range" class="ap-scrub" min="0" max="1" step="1" value="0" aria-label="scrub">
      </div>
      <div class="ap-meters"></div>
    </div>
    <div class="ap-side">
      <div class="ap-legend"></div>
      <div class="ap-events-head">events <span class="ap-events-count"></span></div>
      <div class="ap-events"></div>
    </div>
  </div>
  <div class="ap-tip" hidden></div>
  <div class="ap-foot"></div>`;

  // ---- an SVG drawing context: the subset of CanvasRenderingContext2D the player uses -----
  function SvgContext(W, H) {
    const measure = document.createElement("canvas").getContext("2d");
    const out = [], stack = [];
    let path = [], clipId = 0, clip = null;
    const self = {
      fillStyle: "#000", strokeStyle: "#000", lineWidth: 1, font: "12px sans-serif", textAlign: "left",
      textBaseline: "alphabetic", dash: [],
      setTransform() {}, setLineDash(d) { this.dash = d || []; },
      save() { stack.push([this.fillStyle, this.strokeStyle, this.lineWidth, this.font, this.textAlign, this.textBaseline, this.dash, clip]); },
      restore() { const s = stack.pop(); if (s) [this.fillStyle, this.strokeStyle, this.lineWidth, this.font, this.textAlign, this.textBaseline, this.dash, clip] = s; },
      beginPath() { path = []; }, moveTo(x, y) { path.push("M" + f(x) + " " + f(y)); },
      lineTo(x, y) { path.push("L" + f(x) + " " + f(y)); }, closePath() { path.push("Z"); },
      rect(x, y, w, h) { path.push("M" + f(x) + " " + f(y) + "h" + f(w) + "v" + f(h) + "h" + f(-w) + "Z"); },
      arc(x, y, r) { path.push("M" + f(x - r) + " " + f(y) + "a" + f(r) + " " + f(r) + " 0 1 0 " + f(2 * r) + " 0a" + f(r) + " " + f(r) + " 0 1 0 " + f(-2 * r) + " 0"); },
      clip() { clipId++; out.push('<clipPath id="c' + clipId + '"><path d="' + path.join("") + '"/></clipPath>'); clip = "c" + clipId; },
      fill() { if (path.length) out.push('<path d="' + path.join("") + '" fill="' + this.fillStyle + '"' + cl() + "/>"); },
      stroke() { if (path.length) out.push('<path d="' + path.join("") + '" fill="none" stroke="' + this.strokeStyle + '" stroke-width="' + this.lineWidth + '"' + (this.dash.length ? ' stroke-dasharray="' + this.dash.join(" ") + '"' : "") + cl() + "/>"); },
      fillRect(x, y, w, h) { out.push('<rect x="' + f(x) + '" y="' + f(y) + '" width="' + f(w) + '" height="' + f(h) + '" fill="' + this.fillStyle + '"' + cl() + "/>"); },
      strokeRect(x, y, w, h) { out.push('<rect x="' + f(x) + '" y="' + f(y) + '" width="' + f(w) + '" height="' + f(h) + '" fill="none" stroke="' + this.strokeStyle + '" stroke-width="' + this.lineWidth + '"' + cl() + "/>"); },
      measureText(text) { measure.font = this.font; return measure.measureText(text); },
      fillText(text, x, y) {
        const anchor = { left: "start", right: "end", center: "middle" }[this.textAlign] || "start";
        const base = { top: "hanging", middle: "central", bottom: "text-after-edge" }[this.textBaseline] || "auto";
        const m = /(bold )?(\d+)px/.exec(this.font) || [null, null, "12"];
        out.push('<text x="' + f(x) + '" y="' + f(y) + '" font-size="' + m[2] + '"' + (m[1] ? ' font-weight="bold"' : "") +
                 ' text-anchor="' + anchor + '" dominant-baseline="' + base + '" fill="' + this.fillStyle + '"' + cl() + ">" +
                 String(text).replace(/&/g, "&amp;").replace(/</g, "&lt;") + "</text>");
      },
      drawImage() {},
      document() {
        return '<svg xmlns="http://www.w3.org/2000/svg" width="' + W + '" height="' + H + '" viewBox="0 0 ' + W + " " + H +
          '" font-family="system-ui, DejaVu Sans, sans-serif">\n' + out.join("\n") + "\n</svg>\n";
      },
    };
    function f(v) { return (Math.round(v * 100) / 100).toString(); }
    function cl() { return clip ? ' clip-path="url(#' + clip + ')"' : ""; }
    return self;
  }

  function download(name, blob) {
    const a = document.createElement("a");
    a.download = name; a.href = URL.createObjectURL(blob);
    a.style.display = "none"; document.body.appendChild(a); a.click();
    setTimeout(() => { URL.revokeObjectURL(a.href); a.remove(); }, 1000);
  }
  function slug(text) { return String(text).toLowerCase().replace(/[^a-z0-9]+/g, "-").replace(/^-|-$/g, "") || "meter"; }

  // ==========================================================================================
  function create(root, payload, options) {
    options = options || {};
    const D = payload;
    if (!root.querySelector(".ap-bar")) root.innerHTML = TEMPLATE;
    root.classList.add("ap");
    const $ = (sel) => root.querySelector(sel);
    const cleanups = [];
    function listen(target, type, fn, opts) { target.addEventListener(type, fn, opts); cleanups.push(() => target.removeEventListener(type, fn, opts)); }

    // ---- the samples: growable (streamed runs append chunks) ------------------------------
    let T = new Float64Array(0), N = 0;
    const S = {}; // name -> typed array (1-D) or array of typed arrays (one per row)
    let derivedCache = {};
    function concat(a, b) { const out = new a.constructor(a.length + b.length); out.set(a); out.set(b, a.length); return out; }
    function addSamples(tEntry, series) {
      const t = decode(tEntry), k = t.length;
      for (const name in series) {
        const e = series[name], v = decode(e);
        if (e.shape.length === 2) {
          const rows = e.shape[0];
          const split = []; for (let j = 0; j < rows; j++) split.push(v.subarray(j * k, (j + 1) * k));
          // earlier chunks without it: lower_dx is sent only once some peak has moved in x, so it was 0 (not unknown)
          if (!S[name]) S[name] = split.map((r) => new r.constructor(N).fill(r.constructor === Int8Array || name === "lower_dx" ? 0 : NaN));
          S[name] = S[name].map((r, j) => concat(r, split[j]));
        } else {
          if (!S[name]) S[name] = new v.constructor(N).fill(v.constructor === Int8Array ? 0 : NaN);
          S[name] = concat(S[name], v);
        }
      }
      T = concat(T, t); N = T.length;
      for (const name in S) { // a series the chunk did not carry: padded so indices stay aligned
        if (Array.isArray(S[name])) S[name] = S[name].map((r) => r.length < N ? concat(r, new r.constructor(N - r.length).fill(NaN)) : r);
        else if (S[name].length < N) S[name] = concat(S[name], new S[name].constructor(N - S[name].length).fill(NaN));
      }
      derivedCache = {};
    }
    if (D.t && D.t.shape[0] > 0) addSamples(D.t, D.series || {});
    let finished = D.complete !== false;
    const tStart = () => (N ? T[0] : 0);
    const tEnd = () => {
      const last = N ? T[N - 1] : 0;
      return finished ? last : Math.max(last, options.duration || D.duration || 0, tStart() + 1e-12);
    };

    // ---- derived channels (asperity): per-tip contact force, the energy book -------------
    const G = D.scene;
    function forceShares(i, shares) { // share of the contact force on each touching lower asperity (as the GIF)
      const n = G.n_lower;
      let total = 0, count = 0;
      for (let j = 0; j < n; j++) {
        shares[j] = 0;
        if (!S.lower_contact[j][i]) continue;
        count++;
        const load = G.stiffness[j] * Math.max(-S.lower_dy[j][i], 0);
        shares[j] = load; total += load;
      }
      for (let j = 0; j < n; j++) if (S.lower_contact[j][i]) shares[j] = total > 0 ? shares[j] / total : 1 / count;
      return shares;
    }
    let liveScale = { n: -1, value: 0 };
    function liveForceScale() { // while a run streams: the arrows' scale from the samples held (as tip_force_scale)
      if (liveScale.n === N) return liveScale.value;
      const rows = derived("tip_force"), vals = [];
      const stride = Math.max(1, Math.floor(N / 4000));
      for (let i = 0; i < N; i += stride) { let big = 0; for (const r of rows) big = Math.max(big, r[i]); if (big > 0) vals.push(big); }
      vals.sort((p1, p2) => p1 - p2);
      liveScale = { n: N, value: vals.length ? vals[Math.min(vals.length - 1, Math.round(0.99 * (vals.length - 1)))] : 0 };
      return liveScale.value;
    }
    function derived(name) {
      if (derivedCache[name]) return derivedCache[name];
      if (name === "tip_force") {
        const n = G.n_lower, rows = []; for (let j = 0; j < n; j++) rows.push(new Float64Array(N));
        const shares = new Float64Array(n);
        for (let i = 0; i < N; i++) {
          const f = Math.hypot(S.friction_force[i], S.normal_force[i]);
          forceShares(i, shares);
          for (let j = 0; j < n; j++) rows[j][i] = shares[j] * f;
        }
        derivedCache[name] = rows;
      } else if (name === "energy") {
        const kin = new Float64Array(N), drv = new Float64Array(N), trk = new Float64Array(N);
        const work = new Float64Array(N), rest = new Float64Array(N);
        const m = G.slider_mass, k = G.drive_stiffness || 0, n = G.n_lower;
        for (let i = 0; i < N; i++) {
          const vy = S.vy ? S.vy[i] : 0;
          kin[i] = 0.5 * m * (S.v[i] * S.v[i] + (isFinite(vy) ? vy * vy : 0));
          const s = S.drive_x[i] - S.x[i];
          drv[i] = k > 0 && isFinite(s) ? 0.5 * k * s * s : 0;
          let e = 0; for (let j = 0; j < n; j++) { const d = S.lower_dy[j][i]; e += 0.5 * G.stiffness[j] * d * d; }
          trk[i] = e;
          if (i > 0 && k > 0) work[i] = work[i - 1] + 0.5 * (S.drive_force[i] + S.drive_force[i - 1]) * (S.drive_x[i] - S.drive_x[i - 1]);
          rest[i] = work[i] - (kin[i] + drv[i] + trk[i] - kin[0] - drv[0] - trk[0]);
        }
        derivedCache[name] = { work, kin, drive: drv, track: trk, rest };
      }
      return derivedCache[name];
    }
    let slipCache = { n: -1, list: [] };
    function slipsNow() { // the slips: the run's (once finished), else read off the samples' slip flags
      if (finished || (D.slips && D.slips.length) || !S.slipping) return D.slips || [];
      if (slipCache.n === N) return slipCache.list;
      const list = [];
      let start = -1;
      for (let i = 0; i <= N; i++) {
        const on = i < N && S.slipping[i] > 0;
        if (on && start < 0) start = i;
        if (!on && start >= 0) { list.push([T[Math.max(0, start - 1)], T[i - 1]]); start = -1; }
      }
      slipCache = { n: N, list };
      return list;
    }
    function traceValues(tr) {
      if (tr.derived) { const d = derived(tr.derived); return tr.row !== undefined && tr.row !== null ? d[tr.row] : d[tr.key]; }
      const s = S[tr.series];
      if (!s) return new Float64Array(N).fill(NaN);
      return tr.row !== undefined && tr.row !== null ? s[tr.row] : s;
    }

    // ---- channels: what a meter can show ---------------------------------------------------
    const channels = (D.channels || []).slice();
    if (D.kind === "asperity") {
      const n = G.n_lower;
      channels.push({ id: "tip_force_all", title: "contact force on each lower tip", unit: "N", group: "per tip",
                      note: "the recorded total shared by track-spring load, as the arrows",
                      traces: Array.from({ length: n }, (_, j) => ({ label: "tip " + (j + 1), derived: "tip_force", row: j, colour: PALETTE[j % 10] })) });
      for (let j = 0; j < n; j++)
        channels.push({ id: "tip_force_" + j, title: "contact force on lower tip " + (j + 1), unit: "N", group: "per tip",
                        note: "the recorded total shared by track-spring load, as the arrows",
                        traces: [{ label: "tip " + (j + 1), derived: "tip_force", row: j, colour: PALETTE[j % 10] }] });
      if (G.slider_mass) channels.push({ id: "energy", title: "energy book", unit: "J", group: "energy",
        note: "from the kept samples: drive work (trapezoid rule), slider kinetic, drive spring, vertical track springs; the rest is dissipated, or in the lower asperities' motion and lateral springs",
        traces: [{ label: "drive work", derived: "energy", key: "work", colour: "#000000" },
                 { label: "slider kinetic", derived: "energy", key: "kin", colour: PALETTE[3] },
                 { label: "drive spring", derived: "energy", key: "drive", colour: PALETTE[1] },
                 { label: "track springs", derived: "energy", key: "track", colour: PALETTE[2] },
                 { label: "dissipated + rest", derived: "energy", key: "rest", colour: PALETTE[4], dashed: true }] });
    }
    const channelById = {}; for (const c of channels) channelById[c.id] = c;

    // ---- the page --------------------------------------------------------------------------
    const ui = {
      title: $(".ap-title"), play: $(".ap-play"), speed: $('[data-ctl="speed"]'),
      slowmo: $('[data-ctl="slowmo"]'), camera: $('[data-ctl="camera"]'), exag: $('[data-ctl="exag"]'),
      arrows: $('[data-ctl="arrows"]'), time: $(".ap-time"), stateBadge: $(".ap-state"), slow: $(".ap-slow"),
      live: $(".ap-live"), frame: $(".ap-frame"), scene: $(".ap-scene"), track: $(".ap-track"), scrub: $(".ap-scrub"),
      meters: $(".ap-meters"), events: $(".ap-events"), eventsCount: $(".ap-events-count"), legend: $(".ap-legend"),
      tip: $(".ap-tip"), foot: $(".ap-foot"), ruler: $('[data-act="ruler"]'),
    };
    const state = { selected: null, preview: null, index: 0, playing: false, speed: 1, zoom: 1, panX: 0, panY: 0, view: null,
                    camera: D.kind === "asperity" ? G.camera : "whole",
                    exaggeration: D.kind === "asperity" ? G.exaggeration : 1, arrows: true, ruler: false,
                    measure: null };
    state.t = tStart();
    ui.title.textContent = D.title;
    if (D.kind === "chain") { ui.meters.classList.add("chain"); ui.track.style.height = (18 + 8 * G.n) + "px"; }
    function foot() {
      ui.foot.textContent = "asperity2d " + D.version + " \u00b7 " + N + (finished ? " of " + D.recorded : "") +
        " recorded samples" + (finished && D.recorded > N ? " (every sample inside a slip kept)" : "") +
        " \u00b7 keys: space play/pause, \u2190 \u2192 step, Home/End \u00b7 meters: drag a box to zoom, double-click to reset";
    }
    if (D.kind !== "asperity") for (const el of root.querySelectorAll(".ap-asperity")) el.style.display = "none";
    else {
      for (const v of [1, 2, 5, 10, 20, 50]) {
        const o = document.createElement("option"); o.value = String(v); o.textContent = "\u00d7" + v; ui.exag.appendChild(o);
      }
      if (![1, 2, 5, 10, 20, 50].includes(state.exaggeration)) {
        const o = document.createElement("option"); o.value = String(state.exaggeration);
        o.textContent = "\u00d7" + state.exaggeration; ui.exag.appendChild(o);
      }
      ui.exag.value = String(state.exaggeration);
      ui.camera.value = state.camera;
    }
    function legend() {
      const items = D.kind === "asperity" ?
        [[C.sliderStick, "slider sticking"], [C.sliderSlip, "slider slipping"], [C.touching, "lower tip touching"],
         [C.lower, "lower tip free"], [C.arrow, "contact force on the slider"], [C.band, "slip (meters, timeline)"]] :
        [[C.massStick, "stuck to the belt"], [C.massFast, "slipping, faster than the belt"],
         [C.massSlow, "slipping, slower than the belt"], [C.arrow, "friction force on the mass"]];
      ui.legend.innerHTML = "";
      for (const [colour, text] of items) {
        const row = document.createElement("div"); row.className = "ap-key";
        const sw = document.createElement("span"); sw.className = "ap-swatch"; sw.style.background = colour;
        row.appendChild(sw); row.appendChild(document.createTextNode(text)); ui.legend.appendChild(row);
      }
      if (D.kind === "chain") {
        const note = document.createElement("div"); note.className = "ap-key-note";
        note.textContent = "timeline and meters: one strip per mass (m1 on top), coloured while it slips";
        ui.legend.appendChild(note);
      }
    }
    legend();

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

    // ---- time and playback ---------------------------------------------------------------
    function indexAt(t) { // nearest kept sample
      if (!N) return 0;
      let lo = 0, hi = N - 1;
      if (t <= T[0]) return 0;
      if (t >= T[hi]) return hi;
      while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (T[mid] <= t) lo = mid; else hi = mid; }
      return (t - T[lo] <= T[hi] - t) ? lo : hi;
    }
    function firstAfter(t) { // first kept sample strictly after t
      let lo = 0, hi = N;
      while (lo < hi) { const mid = (lo + hi) >> 1; if (T[mid] <= t) lo = mid + 1; else hi = mid; }
      return Math.min(lo, N - 1);
    }
    function slowAt(t) {
      if (!ui.slowmo.checked) return 1;
      for (const [a, b, s] of D.slow || []) if (t >= a && t <= b) return s;
      return 1;
    }
    function advance(t, dtau, dir) { // t moved by playback time dtau through the slow-motion pieces
      const segs = ui.slowmo.checked ? (D.slow || []) : [];
      let rem = dtau, guard = 0;
      while (rem > 0 && guard++ < 100000) {
        let rate = 1, bound = dir > 0 ? Infinity : -Infinity;
        for (const [a, b, sl] of segs) {
          if (dir > 0 ? (t >= a && t < b) : (t > a && t <= b)) { rate = sl; bound = dir > 0 ? b : a; break; }
          if (dir > 0 && a > t && a < bound) bound = a;
          if (dir < 0 && b < t && b > bound) bound = b;
        }
        const span = Math.abs(bound - t) * rate;
        if (!isFinite(span) || span >= rem) return t + dir * rem / rate;
        rem -= span; t = bound;
      }
      return t;
    }
    function frameStep() { return D.frame_step || (tEnd() - tStart()) / 600 || 1e-9; }

    // ---- the asperity scene ---------------------------------------------------------------
    let lazyCentre = null, lazyIndex = -1;
    function followLeft(i) { // the lazy camera, when the payload has none (a streamed run)
      if (S.camera_left && isFinite(S.camera_left[i])) return S.camera_left[i];
      const span = G.view_width, margin = 0.6 * G.pitch;
      const need = (k) => {
        const left = S.x[k] + G.rear - margin;
        let right = S.x[k] + G.front + margin;
        if (G.has_drive && isFinite(S.drive_x[k])) right = Math.max(right, S.drive_x[k] + G.front + 1.8 * G.pitch);
        return [left, right];
      };
      if (lazyIndex < 0 || i < lazyIndex) { const [l, r] = need(0); lazyCentre = 0.5 * (l + r); lazyIndex = 0; }
      const step = Math.max(1, Math.floor((i - lazyIndex) / 400));
      for (let k = lazyIndex; k <= i; k += (k + step <= i ? step : Math.max(1, i - k))) {
        const [l, r] = need(k);
        lazyCentre = Math.min(Math.max(lazyCentre, r - 0.5 * span), l + 0.5 * span);
        if (k === i) break;
      }
      lazyIndex = i;
      return lazyCentre - 0.5 * span;
    }
    function sceneCamera(W, H) {
      let left, width;
      if (D.kind === "asperity") {
        if (state.camera === "follow" && N) { left = followLeft(state.index); width = G.view_width; }
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
    function toWorld(cam, px, py) { // canvas CSS px -> world (m), the true height (exaggeration undone)
      const bx = (px - cam.W / 2 - cam.panX) / cam.zoom + cam.W / 2;
      const by = (py - cam.H / 2 - cam.panY) / cam.zoom + cam.H / 2;
      return [cam.left + bx / cam.scale, cam.yRef - (by - cam.topPx) / cam.vscale];
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

    let drawn = {};
    function drawAsperity(ctx, W, H) {
      const i = state.index, cam = sceneCamera(W, H);
      const x = S.x[i], y = S.y[i];
      const slipping = !!(S.slipping && S.slipping[i] > 0);
      const bar = Math.max(8, Math.min(0.3 * G.base * cam.scale, 18)) * cam.zoom;
      const viewLo = cam.left + ((-cam.W / 2 - cam.panX) / cam.zoom + cam.W / 2) / cam.scale - G.base;
      const viewHi = cam.left + ((cam.W / 2 - cam.panX) / cam.zoom + cam.W / 2) / cam.scale + G.base;
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
      const lower = [], lowerBox = [];
      const n = G.n_lower;
      for (let j = 0; j < n; j++) {
        const dx = S.lower_dx ? S.lower_dx[j][i] : 0;
        const dy = S.lower_dy[j][i];
        const cx = G.lower_x[j] + dx + (state.preview && state.preview.index === j ? state.preview.dx : 0);
        const touching = !!S.lower_contact[j][i];
        lower.push({ x: cx, y: dy + G.summits[j], dy: dy, contact: touching });
        if (cx < viewLo - G.base || cx > viewHi + G.base) continue;
        const footPx = toPx(cam, cx, dy + G.levels[j]);
        ctx.strokeStyle = C.track; ctx.lineWidth = 1;
        zigzag(ctx, footPx[0], g, footPx[0], footPx[1], 4, Math.max(2, Math.min(0.12 * G.base * cam.scale * cam.zoom, 5)));
        const outline = G.lower_polys[j].map((p) => toPx(cam, cx + p[0], dy + p[1]));
        poly(ctx, outline, touching ? C.touching : C.lower, C.outline);
        lowerBox[j] = [Math.min(...outline.map((q) => q[0])), Math.min(...outline.map((q) => q[1])),
                       Math.max(...outline.map((q) => q[0])), Math.max(...outline.map((q) => q[1]))];
        if (state.selected && state.selected.kind === "lower" && state.selected.index === j) {
          ctx.save(); ctx.strokeStyle = C.ruler; ctx.lineWidth = 3; ctx.setLineDash([5, 3]);
          ctx.beginPath(); outline.forEach((q, k) => (k ? ctx.lineTo(q[0], q[1]) : ctx.moveTo(q[0], q[1]))); ctx.closePath(); ctx.stroke();
          ctx.restore();
        }
      }
      for (let j = 0; j < G.upper_x.length; j++)
        poly(ctx, G.upper_polys[j].map((p) => toPx(cam, x + G.upper_x[j] + p[0], y + p[1])),
             slipping ? C.tipsSlip : C.tipsStick, C.outline);
      const b0 = toPx(cam, x + G.rear, y), b1 = toPx(cam, x + G.front, y);
      ctx.fillStyle = slipping ? C.sliderSlip : C.sliderStick;
      ctx.fillRect(b0[0], b0[1] - bar, b1[0] - b0[0], bar);
      ctx.strokeStyle = C.outline; ctx.lineWidth = 1; ctx.strokeRect(b0[0], b0[1] - bar, b1[0] - b0[0], bar);
      drawn = { slider_bar: [b0[0], b0[1] - bar, b1[0], b0[1]], lower_px: [], lower_box: lowerBox,
                slider_box: [b0[0], b0[1] - bar, b1[0], b0[1]] };
      if (state.selected && state.selected.kind === "slider") {
        ctx.strokeStyle = C.ruler; ctx.lineWidth = 3; ctx.setLineDash([5, 3]);
        ctx.strokeRect(b0[0] - 2, b0[1] - bar - 2, b1[0] - b0[0] + 4, bar + 4); ctx.setLineDash([]);
      }
      if (G.has_drive && isFinite(S.drive_x[i])) {
        const end = toPx(cam, S.drive_x[i] + G.front + G.pitch, 0)[0], sy = b0[1] - 0.5 * bar;
        ctx.strokeStyle = C.spring; ctx.lineWidth = 2;
        zigzag(ctx, b1[0], sy, end, sy, 8, Math.max(3, 0.3 * bar));
        ctx.fillStyle = C.spring; ctx.fillRect(end, sy - 0.6 * bar, 0.72 * bar, 1.2 * bar);
        drawn.drive_end_px = end;
      }
      const forceScale = G.force_scale || liveForceScale();
      if (state.arrows && forceScale > 0) {
        const shares = forceShares(i, new Float64Array(n)), k = G.arrow_px / forceScale;
        const fx = -S.friction_force[i] * k, fy = S.normal_force[i] * k;
        for (let j = 0; j < n; j++) {
          if (!(shares[j] > 0)) continue;
          const tip = toPx(cam, lower[j].x, lower[j].y);
          arrow(ctx, tip[0], tip[1], tip[0] + fx * shares[j], tip[1] - fy * shares[j], C.arrow, 2);
        }
      }
      for (const l of lower) drawn.lower_px.push(toPx(cam, l.x, l.y));
      if (state.measure) { // the ruler
        const a = toPx(cam, state.measure.a[0], state.measure.a[1]), b = toPx(cam, state.measure.b[0], state.measure.b[1]);
        ctx.strokeStyle = C.ruler; ctx.lineWidth = 2; ctx.setLineDash([6, 3]);
        ctx.beginPath(); ctx.moveTo(a[0], a[1]); ctx.lineTo(b[0], b[1]); ctx.stroke(); ctx.setLineDash([]);
        ctx.fillStyle = C.ruler;
        for (const p of [a, b]) { ctx.beginPath(); ctx.arc(p[0], p[1], 3, 0, 2 * Math.PI); ctx.fill(); }
        const m = state.measure;
        const text = "\u0394x " + si(m.dx, "m") + "  \u0394y " + si(m.dy, "m") + "  distance " + si(m.distance, "m") +
          (m.pitches !== null ? "  (" + m.pitches.toFixed(2) + " pitches)" : "");
        ctx.font = "bold 12px system-ui, sans-serif"; ctx.textBaseline = "bottom"; ctx.textAlign = "left";
        const tx = Math.min(Math.max(4, Math.min(a[0], b[0])), W - ctx.measureText(text).width - 8);
        const ty = Math.max(16, Math.min(a[1], b[1]) - 6);
        ctx.fillStyle = "rgba(255,255,255,0.9)"; ctx.fillRect(tx - 3, ty - 15, ctx.measureText(text).width + 6, 17);
        ctx.fillStyle = C.ruler; ctx.fillText(text, tx, ty);
      }
      const scalePx = cam.scale * cam.zoom, len = niceLength(90 / scalePx);
      ctx.fillStyle = "rgba(255,255,255,0.85)"; ctx.fillRect(0, H - 22, W, 22);
      ctx.fillStyle = "#000"; ctx.fillRect(10, H - 13, len * scalePx, 4);
      ctx.font = "12px system-ui, sans-serif"; ctx.textBaseline = "middle"; ctx.textAlign = "left";
      const vert = state.exaggeration > 1 ? "   vertical \u00d7" + state.exaggeration : "";
      ctx.fillText(si(len, "m", 1) + vert, 16 + len * scalePx, H - 11);
      if (state.arrows && forceScale > 0) {
        const k = G.arrow_px / forceScale, f = niceLength(30 / k);
        const label = "contact force on the slider " + si(f, "N", 1);
        // a narrow stage (a notebook cell): the force key goes a row up rather than over the scale bar
        const scaleEnd = 16 + len * scalePx + ctx.measureText(si(len, "m", 1) + vert).width + 12;
        const row = W - 16 - f * k - ctx.measureText(label).width < scaleEnd ? H - 33 : H - 11;
        if (row !== H - 11) { ctx.fillStyle = "rgba(255,255,255,0.85)"; ctx.fillRect(0, H - 44, W, 22); }
        arrow(ctx, W - 10 - f * k, row, W - 10, row, C.arrow, 2);
        ctx.fillStyle = C.arrow; ctx.textAlign = "right";
        ctx.fillText(label, W - 16 - f * k, row);
        ctx.textAlign = "left";
      }
      return { slider: { x: x, y: y }, drive_end: G.has_drive ? S.drive_x[i] : null, lower: lower,
               slipping: slipping, camera: cam };
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
      const off = ((S.belt_s[i] * scale) % 24 + 24) % 24;
      ctx.strokeStyle = C.beltMark; ctx.lineWidth = 2; ctx.beginPath();
      for (let m = off - 24; m < W; m += 24) {
        if (m <= wall || m >= W - wall - 8) continue;
        const p = Z(m, beltTop + 4), q = Z(m + 7, beltTop + 9), r = Z(m, beltTop + 14);
        ctx.moveTo(p[0], p[1]); ctx.lineTo(q[0], q[1]); ctx.lineTo(r[0], r[1]);
      }
      ctx.stroke();
      const centres = [], masses = [];
      for (let j = 0; j < n; j++) {
        const xj = S["x" + j][i];
        centres.push(wall + pitch * (j + 1) + xj * scale);
        masses.push({ x: xj, state: S.state[j][i] });
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
      ctx.textAlign = "center";
      drawn = { masses_px: [] };
      for (let j = 0; j < n; j++) {
        const p = Z(centres[j] - boxW / 2, boxTop);
        ctx.fillStyle = STATE_COLOURS[masses[j].state] || C.massStick;
        ctx.fillRect(p[0], p[1], boxW * z, (boxH - 1) * z);
        ctx.strokeStyle = C.outline; ctx.lineWidth = 1; ctx.strokeRect(p[0], p[1], boxW * z, (boxH - 1) * z);
        ctx.fillStyle = "#fff"; ctx.font = "bold 13px system-ui, sans-serif"; ctx.textBaseline = "top";
        ctx.fillText("m" + (j + 1), p[0] + boxW * z / 2, p[1] + 4);
        ctx.fillStyle = "#000"; ctx.font = "12px system-ui, sans-serif"; ctx.textBaseline = "bottom";
        const st = masses[j].state;
        ctx.fillText(st === 0 ? "STICK" : (st > 0 ? "SLIP (faster)" : "SLIP (slower)"), p[0] + boxW * z / 2, p[1] - 3);
        drawn.masses_px.push(Z(centres[j], boxTop + boxH / 2));
        if (G.force_scale > 0) {
          const k = 0.3 * pitch / G.force_scale, a = Z(centres[j], beltTop + 9), f = S["f" + j][i];
          arrow(ctx, a[0], a[1], a[0] + f * k * z, a[1], C.arrow, 3);
        }
      }
      ctx.textAlign = "left"; ctx.textBaseline = "middle";
      const len = niceLength(60 / scale);
      ctx.fillStyle = "#000"; ctx.fillRect(10, H - 13, len * scale, 4);
      ctx.font = "12px system-ui, sans-serif";
      ctx.fillText(si(len, "m", 1) + " displacement (rest spacing not to scale)", 16 + len * scale, H - 11);
      return { masses: masses, belt_s: S.belt_s[i], camera: { scale: scale, pitch: pitch, wall: wall, W, H } };
    }

    // ---- meters ----------------------------------------------------------------------------
    const meters = [];
    function makeMeter(channelId) {
      const box = document.createElement("div"); box.className = "ap-meter";
      const head = document.createElement("div"); head.className = "ap-meter-head";
      const select = document.createElement("select"); select.title = "channel"; select.setAttribute("aria-label", "channel");
      const groups = {};
      for (const c of channels) {
        const g = c.group || "run";
        if (!groups[g]) { groups[g] = document.createElement("optgroup"); groups[g].label = g; select.appendChild(groups[g]); }
        const o = document.createElement("option"); o.value = c.id; o.textContent = c.title; if (c.note) o.title = c.note; groups[g].appendChild(o);
      }
      head.appendChild(select);
      const tools = document.createElement("span"); tools.className = "ap-meter-tools";
      for (const [act, label, title] of [["csv", "CSV", "this meter's samples as a CSV table (units in the header)"],
                                         ["png", "PNG", "this meter as a PNG picture"], ["svg", "SVG", "this meter as an SVG drawing"],
                                         ["unzoom", "\u21BA", "undo the zoom (or double-click the meter)"]]) {
        const b = document.createElement("button"); b.type = "button"; b.dataset.act = act; b.textContent = label; b.title = title;
        tools.appendChild(b);
      }
      head.appendChild(tools);
      const canvas = document.createElement("canvas");
      box.appendChild(head); box.appendChild(canvas); ui.meters.appendChild(box);
      const m = { box, select, canvas, cache: null, plot: null, zoomY: null, band: null };
      setChannel(m, channelId);
      select.addEventListener("change", () => { setChannel(m, select.value); requestRender(); });
      tools.querySelector('[data-act="csv"]').addEventListener("click", () => download(slug(m.spec.title) + ".csv", new Blob([meterCsv(m)], { type: "text/csv" })));
      tools.querySelector('[data-act="png"]').addEventListener("click", () => m.canvas.toBlob((b) => download(slug(m.spec.title) + ".png", b), "image/png"));
      tools.querySelector('[data-act="svg"]').addEventListener("click", () => download(slug(m.spec.title) + ".svg", new Blob([meterSvg(m)], { type: "image/svg+xml" })));
      tools.querySelector('[data-act="unzoom"]').addEventListener("click", () => { resetZoom(m); });
      bindMeter(m);
      meters.push(m);
      return m;
    }
    function setChannel(m, id) {
      const spec = channelById[id] || channels[0];
      m.spec = spec; m.select.value = spec.id; m.zoomY = null; m.cache = null; m.autoLimits = null;
      m.canvas.setAttribute("aria-label", spec.title); m.select.title = spec.note || "channel";
    }
    // ---- kept runs drawn over this one (overlays) and the difference channel -----------------
    let overlays = [], difference = null, overlayVersion = 0;
    function rawValues(store, tr) { // a series of a kept run's store (derived channels are not kept)
      if (tr.derived) return null;
      const v = store[tr.series];
      if (!v) return null;
      return Array.isArray(v) ? (tr.row !== undefined && tr.row !== null ? v[tr.row] : null) : v;
    }
    function interp(Tk, Vk, t) { // Vk at t, linear between Tk's samples (NaN outside)
      const n = Tk.length;
      if (!n || t < Tk[0] || t > Tk[n - 1]) return NaN;
      let lo = 0, hi = n - 1;
      while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (Tk[mid] <= t) lo = mid; else hi = mid; }
      if (Tk[hi] === Tk[lo]) return Vk[lo];
      const f = (t - Tk[lo]) / (Tk[hi] - Tk[lo]);
      return Vk[lo] + f * (Vk[hi] - Vk[lo]);
    }
    function overlayTraces(m) {
      if (difference !== null) return [];
      const out = [];
      for (const ov of overlays) for (const tr of m.spec.traces) {
        const v = rawValues(ov.S, tr);
        if (v) out.push({ label: ov.label + (m.spec.traces.length > 1 ? " " + tr.label : ""), colour: ov.colour, T: ov.T, values: v });
      }
      return out;
    }
    function meterTraces(m) {
      const traces = m.spec.traces.map((tr) => ({ ...tr, values: traceValues(tr) }));
      if (difference === null || !overlays[difference]) return traces;
      const ov = overlays[difference];
      return traces.map((tr) => {
        const kept = rawValues(ov.S, tr), out = new Float64Array(N).fill(NaN);
        if (kept) for (let i = 0; i < N; i++) out[i] = tr.values[i] - interp(ov.T, kept, T[i]);
        return { ...tr, label: tr.label + " \u2212 " + ov.label, values: out };
      });
    }
    function meterLimits(m, traces) {
      if (m.zoomY) return m.zoomY;
      if (m.spec.limits && finished && !overlays.length) return m.spec.limits;
      if (!m.autoLimits || m.autoN !== N || m.autoV !== overlayVersion) {
        const zero = m.spec.include_zero !== false;
        // this run's axis as its meter has it alone (the difference channel: the difference's own) ...
        let lim = !N ? null : difference === null && m.spec.limits && finished ? m.spec.limits.slice()
          : robustLimits(traces.map((t) => t.values), zero);
        // ... widened by each kept run's, as its own meter had it: a kept trace is never clipped
        // more here than it was in its own run (one robust range over the runs pooled would clip
        // the run whose extremes are the rarer ones)
        if (difference === null) for (const ov of overlays) {
          const vs = m.spec.traces.map((tr) => rawValues(ov.S, tr)).filter((v) => v);
          if (!vs.length) continue;
          const own = ov.limits && ov.limits[m.spec.id] ? ov.limits[m.spec.id] : robustLimits(vs, zero);
          lim = lim ? [Math.min(lim[0], own[0]), Math.max(lim[1], own[1])] : own.slice();
        }
        m.autoLimits = lim || [-1, 1];
        m.autoN = N; m.autoV = overlayVersion;
      }
      return m.autoLimits;
    }
    function timeView() {
      if (state.view) return state.view;
      const a = tStart(), b = tEnd();
      return [a, b > a ? b : a + 1e-12];
    }
    const LEGEND_MAX = 6; // legend entries at most (the largest values at the cursor when there are more)
    function legendLayout(ctx, m, W) { // slots of equal width, as many rows as they need
      const n = Math.min(m.spec.traces.length, LEGEND_MAX);
      if (m.spec.traces.length < 2) return { rows: 0, cols: 1, slot: 0 };
      ctx.font = "12px system-ui, sans-serif";
      const label = Math.max(...m.spec.traces.map((tr) => ctx.measureText(tr.label).width));
      const slot = 16 + label + 6 + ctx.measureText("▲ -888 mN").width + 10;
      const cols = Math.max(1, Math.min(n, Math.floor((W - 12) / slot)));
      return { rows: Math.ceil(n / cols), cols, slot };
    }
    function meterPlot(W, H, m, legend) { return { x0: 52, y0: 24 + (legend.rows ? 15 * legend.rows : 0), x1: W - 10, y1: H - 20 }; }
    function meterX(p, t, view) { view = view || timeView(); return p.x0 + (t - view[0]) / ((view[1] - view[0]) || 1) * (p.x1 - p.x0); }
    function meterY(p, lim, v) { return p.y1 - (v - lim[0]) / (lim[1] - lim[0]) * (p.y1 - p.y0); }
    function meterStatic(ctx, m, W, H) { // axes, slip bands and whole traces, clipped values marked
      const traces = meterTraces(m), lim = meterLimits(m, traces), view = timeView();
      const [factor, unitLabel] = prefixed(Math.max(Math.abs(lim[0]), Math.abs(lim[1])), m.spec.unit);
      const [tfactor, tunit] = prefixed(Math.max(Math.abs(view[0]), Math.abs(view[1])), "s");
      m.legend = legendLayout(ctx, m, W);
      const p = meterPlot(W, H, m, m.legend); m.plot = p; m.limits = lim; m.unitLabel = unitLabel; m.factor = factor;
      ctx.fillStyle = "#fafafc"; ctx.fillRect(0, 0, W, H);
      ctx.fillStyle = "#fff"; ctx.fillRect(p.x0, p.y0, p.x1 - p.x0, p.y1 - p.y0);
      ctx.fillStyle = C.band;
      for (const [a, b] of D.kind === "chain" ? [] : slipsNow()) {
        if (b < view[0] || a > view[1]) continue;
        const xa = Math.max(p.x0, meterX(p, a, view)), xb = Math.min(p.x1, Math.max(meterX(p, b, view), xa + 1));
        ctx.fillRect(xa, p.y0, xb - xa, p.y1 - p.y0);
      }
      ctx.font = "11px system-ui, sans-serif"; ctx.fillStyle = "#777"; ctx.strokeStyle = "#e6e6ea"; ctx.lineWidth = 1;
      ctx.textAlign = "right"; ctx.textBaseline = "middle";
      const count = Math.max(3, Math.min(5, Math.floor((p.y1 - p.y0) / 24)));
      for (const [v, label] of ticks(lim[0], lim[1], factor, count)) {
        const y = Math.round(meterY(p, lim, v)) + 0.5;
        ctx.beginPath(); ctx.moveTo(p.x0, y); ctx.lineTo(p.x1, y); ctx.stroke();
        ctx.fillText(label, p.x0 - 4, y);
      }
      ctx.textAlign = "center"; ctx.textBaseline = "top";
      for (const [v, label] of ticks(view[0], view[1], tfactor, 6)) {
        const x = Math.round(meterX(p, v, view)) + 0.5;
        ctx.beginPath(); ctx.moveTo(x, p.y1); ctx.lineTo(x, p.y1 + 3); ctx.stroke();
        if (x < p.x1 - 24) ctx.fillText(label, x, p.y1 + 4);
      }
      ctx.textAlign = "right"; ctx.fillText(tunit, p.x1, p.y1 + 4);
      ctx.strokeStyle = "#888"; ctx.strokeRect(p.x0 - 0.5, p.y0 - 0.5, p.x1 - p.x0 + 1, p.y1 - p.y0 + 1);
      const i0 = Math.max(0, firstAfter(view[0]) - 1), i1 = Math.min(N - 1, firstAfter(view[1]));
      m.clipped = 0;
      const marks = [];
      ctx.save(); ctx.beginPath(); ctx.rect(p.x0, p.y0, p.x1 - p.x0, p.y1 - p.y0); ctx.clip();
      for (const ov of overlayTraces(m)) { // kept runs under this one, each in its colour
        ctx.strokeStyle = ov.colour; ctx.lineWidth = 1.4; ctx.setLineDash([]); ctx.beginPath();
        let on = false;
        const stride = Math.max(1, Math.floor(ov.T.length / 6000));
        for (let i = 0; i < ov.T.length; i += stride) {
          const v = ov.values[i];
          if (!isFinite(v) || ov.T[i] < view[0] - (view[1] - view[0]) || ov.T[i] > view[1] + (view[1] - view[0])) { on = false; continue; }
          const x = meterX(p, ov.T[i], view), y = Math.max(p.y0 - 1e4, Math.min(p.y1 + 1e4, meterY(p, lim, v)));
          if (on) ctx.lineTo(x, y); else { ctx.moveTo(x, y); on = true; }
        }
        ctx.stroke();
      }
      for (const tr of traces) {
        ctx.strokeStyle = tr.colour; ctx.lineWidth = 1.2; ctx.setLineDash(tr.dashed ? [4, 4] : []);
        ctx.beginPath();
        let started = false, lastCol = null;
        for (let i = i0; i <= i1 && N; i++) {
          const v = tr.values[i];
          if (!isFinite(v)) { started = false; continue; }
          const x = meterX(p, T[i], view), yRaw = meterY(p, lim, v), y = Math.max(p.y0 - 1e4, Math.min(p.y1 + 1e4, yRaw));
          if (started) ctx.lineTo(x, y); else { ctx.moveTo(x, y); started = true; }
          if ((v > lim[1] || v < lim[0]) && T[i] >= view[0] && T[i] <= view[1]) {
            m.clipped++;
            const col = Math.round(x / 4);
            if (col !== lastCol) { marks.push([x, v > lim[1] ? 1 : -1, tr.colour]); lastCol = col; }
          }
        }
        ctx.stroke();
      }
      ctx.restore(); ctx.setLineDash([]);
      if (D.kind === "chain" && N) { // each mass's state as a strip along the plot's foot (the legend's colours)
        const n = G.n, h = 4;
        for (let j = 0; j < n; j++) {
          const st = S.state[j], y = p.y1 - (n - j) * h;
          let start = i0;
          for (let i = i0 + 1; i <= i1 + 1; i++) {
            if (i <= i1 && st[i] === st[start]) continue;
            const xa = Math.max(p.x0, meterX(p, T[start], view)), xb = Math.min(p.x1, meterX(p, T[Math.min(i, i1)], view));
            if (st[start] !== 0 && xb > xa - 1) { ctx.fillStyle = STATE_COLOURS[st[start]]; ctx.fillRect(xa, y, Math.max(1, xb - xa), h - 1); }
            start = i;
          }
        }
      }
      for (const [x, dir, colour] of marks) { // a value off the axis: a triangle on the edge it left by
        const y = dir > 0 ? p.y0 : p.y1;
        ctx.fillStyle = colour; ctx.strokeStyle = C.clip; ctx.lineWidth = 0.8; ctx.beginPath();
        ctx.moveTo(x, y - dir * 1); ctx.lineTo(x - 3.5, y + dir * 6); ctx.lineTo(x + 3.5, y + dir * 6); ctx.closePath();
        ctx.fill(); ctx.stroke();
      }
      ctx.fillStyle = "#000"; ctx.font = "bold 12px system-ui, sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "top";
      const title = m.spec.title + " (" + unitLabel + ")";
      ctx.fillText(title, 6, 5);
      m.traces = traces;
    }
    function meterNow(ctx, m, W, hoverT) { // cursor, the future faded, the read-outs
      const p = m.plot, i = state.index, lim = m.limits, view = timeView();
      if (!N) return null;
      const x = meterX(p, T[i], view), inView = x >= p.x0 - 0.5 && x <= p.x1 + 0.5;
      const fadeFrom = Math.max(p.x0, Math.min(p.x1, x + 1));
      ctx.fillStyle = "rgba(250,250,252,0.72)"; ctx.fillRect(fadeFrom, p.y0, p.x1 - fadeFrom, p.y1 - p.y0);
      if (inView) {
        ctx.strokeStyle = C.cursor; ctx.lineWidth = 1; ctx.beginPath(); ctx.moveTo(Math.round(x) + 0.5, p.y0);
        ctx.lineTo(Math.round(x) + 0.5, p.y1); ctx.stroke();
      }
      ctx.font = "12px system-ui, sans-serif"; ctx.textBaseline = "top";
      const many = m.traces.length > 1;
      let shown = m.traces;
      if (m.traces.length > LEGEND_MAX) { // the largest at the cursor
        shown = m.traces.slice().sort((p1, p2) => (Math.abs(p2.values[i]) || 0) - (Math.abs(p1.values[i]) || 0)).slice(0, LEGEND_MAX);
      }
      let slotIndex = 0;
      ctx.textAlign = many ? "left" : "right";
      for (const tr of m.traces) {
        const v = tr.values[i], off = v > lim[1] ? 1 : (v < lim[0] ? -1 : 0);
        if (isFinite(v) && inView) {
          ctx.fillStyle = tr.colour; ctx.strokeStyle = C.cursor;
          if (off) { // the value left the axis: an arrowhead on the edge
            const y = off > 0 ? p.y0 : p.y1;
            ctx.beginPath(); ctx.moveTo(x, y - off * 2); ctx.lineTo(x - 5, y + off * 8); ctx.lineTo(x + 5, y + off * 8);
            ctx.closePath(); ctx.fill(); ctx.stroke();
          } else { ctx.beginPath(); ctx.arc(x, meterY(p, lim, v), 3.5, 0, 2 * Math.PI); ctx.fill(); ctx.stroke(); }
        }
        const text = (many ? tr.label + " " : "") + (off > 0 ? "\u25B2 " : off < 0 ? "\u25BC " : "") + axisText(m, v) +
          (off && !many ? " (off the axis)" : "");
        ctx.fillStyle = tr.colour;
        if (many) {
          if (!shown.includes(tr)) continue;
          const L = m.legend, c = slotIndex % L.cols, r = Math.floor(slotIndex / L.cols);
          const lx = 8 + c * L.slot, row = 21 + 15 * r;
          ctx.fillRect(lx, row + 5, 12, 3); ctx.fillText(text, lx + 16, row);
          slotIndex++;
        } else { ctx.font = "bold 12px system-ui, sans-serif"; ctx.fillText(text, W - 10, 5); }
      }
      if (m.clipped) { // inside the plot's top-left corner, over the faded future: the title row keeps the read-out
        const note = "\u25B2\u25BC " + m.clipped + " off the axis";
        ctx.font = "11px system-ui, sans-serif"; ctx.textAlign = "left"; ctx.textBaseline = "top";
        ctx.fillStyle = "rgba(255,255,255,0.9)"; ctx.fillRect(p.x0 + 1, p.y0 + 1, ctx.measureText(note).width + 8, 14);
        ctx.fillStyle = "#a01010"; ctx.fillText(note, p.x0 + 5, p.y0 + 2);
      }
      if (m.traces.length > LEGEND_MAX) {
        ctx.fillStyle = "#777"; ctx.font = "11px system-ui, sans-serif"; ctx.textAlign = "right";
        ctx.fillText(LEGEND_MAX + " of " + m.traces.length + " (largest)", W - 10, 6);
      }
      if (hoverT !== undefined && hoverT !== null) {
        const hx = meterX(p, hoverT, view);
        ctx.strokeStyle = "rgba(0,0,0,0.35)"; ctx.setLineDash([3, 3]); ctx.beginPath();
        ctx.moveTo(hx, p.y0); ctx.lineTo(hx, p.y1); ctx.stroke(); ctx.setLineDash([]);
      }
      if (m.band) { // the box being dragged
        const [ax, ay, bx, by] = m.band;
        ctx.fillStyle = "rgba(10,110,154,0.12)"; ctx.strokeStyle = C.ruler; ctx.lineWidth = 1;
        ctx.fillRect(Math.min(ax, bx), Math.min(ay, by), Math.abs(bx - ax), Math.abs(by - ay));
        ctx.strokeRect(Math.min(ax, bx), Math.min(ay, by), Math.abs(bx - ax), Math.abs(by - ay));
      }
      return Math.round(x);
    }
    function axisText(m, v) { // a read-out in its axis' unit (the axis says km/s: so does the read-out)
      if (!isFinite(v) || !m.factor) return si(v, m.spec.unit);
      const x = v / m.factor, digits = Math.abs(x) >= 1000 ? 4 : 3;
      return (x === 0 ? "0" : x.toPrecision(digits).replace(/(\.\d*?[1-9])0+$|\.0+$/, "$1")) + " " + m.unitLabel;
    }
    function drawMeter(m, hoverT) {
      const [ctx, W, H] = fitCanvas(m.canvas);
      const dpr = window.devicePixelRatio || 1;
      const key = W + "x" + H + "@" + dpr + ":" + timeView().join(",") + ":" + N + ":" + (m.zoomY || "") + ":" + m.spec.id + ":" + overlayVersion;
      if (!m.cache || m.cacheKey !== key) {
        const off = document.createElement("canvas");
        off.width = Math.round(W * dpr); off.height = Math.round(H * dpr);
        const octx = off.getContext("2d"); octx.setTransform(dpr, 0, 0, dpr, 0, 0);
        meterStatic(octx, m, W, H);
        m.cache = off; m.cacheKey = key;
      }
      ctx.setTransform(1, 0, 0, 1, 0, 0); ctx.drawImage(m.cache, 0, 0); ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      return meterNow(ctx, m, W, hoverT);
    }
    function meterSvg(m) {
      const r = m.canvas.getBoundingClientRect(), W = Math.max(320, Math.round(r.width)), H = Math.max(120, Math.round(r.height));
      const ctx = SvgContext(W, H);
      meterStatic(ctx, m, W, H); meterNow(ctx, m, W, null);
      return ctx.document();
    }
    function csvNumber(v) { return isFinite(v) ? v.toPrecision(17) : ""; }
    function meterCsv(m) { // every kept sample (in the zoomed time window if zoomed) at the precision stored
      const traces = meterTraces(m), view = state.view;
      const head = ["t (s)"].concat(traces.map((tr) => '"' + (traces.length > 1 || tr.label !== m.spec.title ? m.spec.title + ": " + tr.label : tr.label).replace(/"/g, "'") + " (" + m.spec.unit + ')"'));
      const lines = [head.join(",")];
      for (let i = 0; i < N; i++) {
        if (view && (T[i] < view[0] || T[i] > view[1])) continue;
        const row = [csvNumber(T[i])];
        for (const tr of traces) row.push(csvNumber(tr.values[i]));
        lines.push(row.join(","));
      }
      return lines.join("\n") + "\n";
    }
    function meterCsvAll(m) { // this run and every kept run: one row per sample, the run named in the first column
      const traces = m.spec.traces.map((tr) => ({ ...tr, values: traceValues(tr) }));
      const head = ["run", "t (s)"].concat(traces.map((tr) => '"' + (traces.length > 1 || tr.label !== m.spec.title ? m.spec.title + ": " + tr.label : tr.label).replace(/"/g, "'") + " (" + m.spec.unit + ')"'));
      const lines = [head.join(",")];
      const runs = [{ label: options.runLabel || "this run", T: T, values: traces.map((tr) => tr.values) }]
        .concat(overlays.map((ov) => ({ label: ov.label, T: ov.T, values: traces.map((tr) => rawValues(ov.S, tr)) })));
      for (const r of runs) for (let i = 0; i < r.T.length; i++)
        lines.push(['"' + String(r.label).replace(/"/g, "'") + '"', csvNumber(r.T[i])].concat(r.values.map((v) => (v ? csvNumber(v[i]) : ""))).join(","));
      return lines.join("\n") + "\n";
    }
    const viewListeners = [];
    function emitView() { for (const cb of viewListeners.slice()) { try { cb(state.view ? state.view.slice() : null); } catch (err) { setTimeout(() => { throw err; }); } } }
    function resetZoom(m) { state.view = null; if (m) m.zoomY = null; else for (const q of meters) q.zoomY = null; requestRender(); emitView(); }
    function zoomMeter(m, ta, tb, lo, hi) { // box zoom: time for every meter (linked), value for this one
      const timed = ta !== null && tb !== null && tb > ta;
      if (timed) state.view = [ta, tb];
      if (lo !== null && hi !== null && hi > lo) m.zoomY = [lo, hi];
      requestRender();
      if (timed) emitView();
    }

    // ---- timeline --------------------------------------------------------------------------
    function drawTrack() {
      const [ctx, W, H] = fitCanvas(ui.track);
      const a = tStart(), b = tEnd();
      const x0 = 6, x1 = W - 6, X = (t) => x0 + (t - a) / ((b - a) || 1) * (x1 - x0);
      ctx.fillStyle = "#f3f4f6"; ctx.fillRect(0, 0, W, H);
      ctx.fillStyle = "#fff"; ctx.fillRect(x0, 8, x1 - x0, H - 16);
      if (D.kind === "chain" && N) { // one strip per mass, coloured by its state
        const n = G.n, h = (H - 16) / n;
        for (let j = 0; j < n; j++) {
          const st = S.state[j];
          let start = 0;
          for (let i = 1; i <= N; i++) {
            if (i < N && st[i] === st[start]) continue;
            if (st[start] !== 0) { ctx.fillStyle = STATE_COLOURS[st[start]]; ctx.fillRect(X(T[start]), 8 + j * h, Math.max(1, X(T[Math.min(i, N - 1)]) - X(T[start])), h - 1); }
            start = i;
          }
        }
      } else {
        ctx.fillStyle = "#f19a92";
        for (const [sa, sb] of slipsNow()) ctx.fillRect(X(sa), 8, Math.max(2, X(sb) - X(sa)), H - 16);
      }
      if (state.view) { // the meters' zoomed window
        ctx.strokeStyle = C.ruler; ctx.lineWidth = 1.5; ctx.strokeRect(X(state.view[0]), 7, Math.max(2, X(state.view[1]) - X(state.view[0])), H - 14);
      }
      ctx.fillStyle = "#c82d2d";
      for (const e of D.events || []) {
        const te = e.t_slip !== undefined ? e.t_slip : e.t;
        if (e.kind === "stick" || e.kind === "graze") continue;
        const x = X(te); ctx.beginPath(); ctx.moveTo(x, 8); ctx.lineTo(x - 5, 0); ctx.lineTo(x + 5, 0); ctx.fill();
      }
      if (N) { const x = X(T[state.index]); ctx.fillStyle = C.cursor; ctx.fillRect(Math.round(x) - 1, 4, 2, H - 8); }
      ctx.font = "11px system-ui, sans-serif"; ctx.fillStyle = "#555"; ctx.textBaseline = "bottom";
      ctx.textAlign = "left"; ctx.fillText(si(a, "s"), x0, H); ctx.textAlign = "right"; ctx.fillText(si(b, "s"), x1, H);
    }
    function eventList() {
      return D.kind === "asperity" ? (D.events || []).map((e, k) => ({
        t: e.t_slip, end: e.t_end, label: "slip " + (k + 1) + " at " + si(e.t_slip, "s") + ": peak " + si(e.force_peak, "N") +
          ", drop " + si(e.force_drop, "N") + ", " + si(e.slip_distance, "m") + (e.complete ? "" : " (run ended)") })) :
        (D.events || []).filter((e) => e.kind !== "graze").map((e) => ({ t: e.t, end: null, label: "m" + (e.mass + 1) + " " + e.kind + " at " + si(e.t, "s") }));
    }
    function eventTime(ev) { // inside the slip: the first kept sample after its onset (not the last stick sample)
      if (ev.end === null || ev.end === undefined) return T[indexAt(ev.t)];
      const j = firstAfter(ev.t);
      return T[j] <= ev.end ? T[j] : T[indexAt(ev.t)];
    }
    function buildEvents() {
      ui.events.innerHTML = "";
      const list = eventList();
      ui.eventsCount.textContent = list.length ? "(" + list.length + ", click to jump into one)" : "";
      if (!list.length) { ui.events.textContent = finished ? (D.kind === "asperity" ? "no stick\u2013slip events" : "no events") : "running\u2026"; return; }
      list.forEach((ev, k) => {
        const b = document.createElement("button");
        b.type = "button"; b.textContent = ev.label; b.title = "jump into this event"; b.dataset.event = String(k);
        b.addEventListener("click", () => { pause(); userSeek(eventTime(ev)); });
        ui.events.appendChild(b);
      });
    }

    // ---- one frame -------------------------------------------------------------------------
    let sceneState = {}, cursors = [], hover = null;
    function render() {
      if (destroyed) return;
      const [ctx, W, H] = fitCanvas(ui.scene);
      ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, W, H);
      if (N) sceneState = D.kind === "asperity" ? drawAsperity(ctx, W, H) : drawChain(ctx, W, H);
      else { ctx.fillStyle = "#777"; ctx.font = "14px system-ui, sans-serif"; ctx.textAlign = "center"; ctx.fillText("waiting for the first samples\u2026", W / 2, H / 2); ctx.textAlign = "left"; }
      cursors = meters.map((m) => drawMeter(m, hover));
      drawTrack();
      const t = N ? T[state.index] : 0;
      ui.time.textContent = "t = " + si(t, "s", 4);
      if (D.kind === "asperity" && G.has_drive && N) {
        ui.stateBadge.textContent = sceneState.slipping ? "SLIP" : "STICK";
        ui.stateBadge.className = "ap-state " + (sceneState.slipping ? "slip" : "stick");
      } else { ui.stateBadge.textContent = ""; ui.stateBadge.className = "ap-state"; }
      const s = slowAt(t);
      ui.slow.textContent = state.playing && s > 1 ? "\u00d7" + s + " slow" : (s > 1 ? "slip: \u00d7" + s + " slow when playing" : "");
      ui.live.textContent = finished ? "" : "computing\u2026 " + si(N ? T[N - 1] : 0, "s") + " so far";
      ui.frame.textContent = "sample " + (N ? state.index + 1 : 0) + " / " + N;
      ui.scrub.max = String(Math.max(0, N - 1));
      ui.scrub.value = String(state.index);
      ui.play.textContent = state.playing ? "\u275A\u275A pause" : "\u25B6 play";
    }
    let pending = false;
    function requestRender() { if (!pending) { pending = true; requestAnimationFrame(() => { pending = false; render(); }); } }

    const cursorListeners = [];
    function emitCursor() { const t = N ? T[state.index] : 0; for (const cb of cursorListeners.slice()) { try { cb(t); } catch (err) { setTimeout(() => { throw err; }); } } }
    function seek(t) { state.t = Math.min(tEnd(), Math.max(tStart(), t)); state.index = indexAt(state.t); render(); }
    function userSeek(t) { seek(t); emitCursor(); }
    function step(n) {
      pause();
      const dir = n < 0 ? -1 : 1;
      for (let k = 0; k < Math.abs(n); k++) {
        let j = indexAt(advance(T[state.index], frameStep(), dir));
        if (j === state.index) j = Math.min(N - 1, Math.max(0, j + dir));
        state.index = j; state.t = T[j];
      }
      render(); emitCursor();
    }
    let last = null, rafId = null;
    function tick(now) {
      rafId = null;
      if (!state.playing || destroyed) { last = null; return; }
      if (last !== null) {
        const wall = Math.min(0.1, (now - last) / 1000);
        state.t = advance(state.t, wall * 20 * frameStep() * state.speed, 1);
        const end = N ? T[N - 1] : 0;
        if (state.t >= end) { state.t = end; if (finished) state.playing = false; }
        state.index = indexAt(state.t);
        render(); emitCursor();
      }
      last = now;
      rafId = requestAnimationFrame(tick);
    }
    function play() { if (!N) return; if (state.index >= N - 1 && finished) seek(tStart()); if (!state.playing) { state.playing = true; last = null; rafId = requestAnimationFrame(tick); } render(); }
    function pause() { state.playing = false; }

    // ---- controls --------------------------------------------------------------------------
    const act = (name, fn) => { const el = root.querySelector('[data-act="' + name + '"]'); if (el) listen(el, "click", fn); };
    act("play", () => (state.playing ? (pause(), render()) : play()));
    act("start", () => { pause(); userSeek(tStart()); });
    act("back", () => step(-1));
    act("fwd", () => step(1));
    act("reset", () => { state.zoom = 1; state.panX = 0; state.panY = 0; state.measure = null; render(); });
    act("ruler", () => { state.ruler = !state.ruler; ui.ruler.setAttribute("aria-pressed", String(state.ruler)); ui.ruler.classList.toggle("on", state.ruler); if (!state.ruler) state.measure = null; ui.scene.classList.toggle("measuring", state.ruler); render(); });
    act("png", () => ui.scene.toBlob((b) => download("frame.png", b), "image/png"));
    act("svg", () => download("frame.svg", new Blob([frameSvg()], { type: "image/svg+xml" })));
    listen(ui.speed, "change", () => { state.speed = parseFloat(ui.speed.value); });
    listen(ui.slowmo, "change", render);
    listen(ui.camera, "change", () => { state.camera = ui.camera.value; state.zoom = 1; state.panX = 0; state.panY = 0; render(); });
    listen(ui.exag, "change", () => { state.exaggeration = parseFloat(ui.exag.value); render(); });
    listen(ui.arrows, "change", () => { state.arrows = ui.arrows.checked; render(); });
    listen(ui.scrub, "input", () => { pause(); state.index = parseInt(ui.scrub.value, 10); state.t = T[state.index]; render(); emitCursor(); });
    listen(ui.track, "click", (ev) => { // a click within 6 px of an event's marker jumps into it
      const r = ui.track.getBoundingClientRect(), x0 = 6, x1 = r.width - 6, a = tStart(), b = tEnd();
      let t = a + (ev.clientX - r.left - x0) / (x1 - x0) * (b - a);
      for (const e of eventList()) if (Math.abs(e.t - t) / (b - a) * (x1 - x0) <= 6) { t = eventTime(e); break; }
      pause(); userSeek(t);
    });
    if (options.keys !== false) listen(document, "keydown", (ev) => {
      if (ev.target && (ev.target.tagName === "INPUT" && ev.target.type !== "range" || ev.target.tagName === "SELECT" || ev.target.tagName === "TEXTAREA")) return;
      if (ev.key === " ") { ev.preventDefault(); state.playing ? (pause(), render()) : play(); }
      else if (ev.key === "ArrowRight") { ev.preventDefault(); step(1); }
      else if (ev.key === "ArrowLeft") { ev.preventDefault(); step(-1); }
      else if (ev.key === "Home") { pause(); userSeek(tStart()); }
      else if (ev.key === "End") { pause(); userSeek(tEnd()); }
    });
    listen(ui.scene, "wheel", (ev) => { // zoom about the pointer
      ev.preventDefault();
      const r = ui.scene.getBoundingClientRect(), mx = ev.clientX - r.left, my = ev.clientY - r.top;
      const f = Math.exp(-ev.deltaY * 0.0015), z = Math.min(40, Math.max(0.25, state.zoom * f)), k = z / state.zoom;
      state.panX = (mx - r.width / 2) * (1 - k) + state.panX * k;
      state.panY = (my - r.height / 2) * (1 - k) + state.panY * k;
      state.zoom = z; requestRender();
    }, { passive: false });
    let drag = null;
    const selectListeners = [], editListeners = [];
    function emitSelect(sel) { for (const cb of selectListeners.slice()) { try { cb(sel); } catch (err) { setTimeout(() => { throw err; }); } } }
    function emitEdit(edit) { for (const cb of editListeners.slice()) { try { cb(edit); } catch (err) { setTimeout(() => { throw err; }); } } }
    function pick(px, py) { // the body under the pointer: a lower asperity, the slider, or null
      const hits = drawn.lower_box || [];
      for (let j = 0; j < hits.length; j++) {
        const b = hits[j];
        if (b && px >= b[0] - 3 && px <= b[2] + 3 && py >= b[1] - 3 && py <= b[3] + 3) return { kind: "lower", index: j };
      }
      const sb = drawn.slider_box;
      if (sb && px >= sb[0] - 3 && px <= sb[2] + 3 && py >= sb[1] - 3 && py <= sb[3] + 3) return { kind: "slider", index: null };
      return null;
    }
    function scenePoint(ev) { const r = ui.scene.getBoundingClientRect(); return [ev.clientX - r.left, ev.clientY - r.top]; }
    function setMeasure(a, b) {
      const dx = b[0] - a[0], dy = b[1] - a[1];
      state.measure = { a, b, dx, dy, distance: Math.hypot(dx, dy), pitches: D.kind === "asperity" ? Math.abs(dx) / G.pitch : null };
    }
    listen(ui.scene, "pointerdown", (ev) => {
      const hit = options.edit && D.kind === "asperity" && !state.ruler && N ? pick(...scenePoint(ev)) : null;
      if (hit) { // select it; a lower asperity also drags along the surface
        drag = { edit: hit, x: ev.clientX, moved: false };
        try { ui.scene.setPointerCapture(ev.pointerId); } catch (err) { /* synthetic events */ }
        return;
      }
      if (state.ruler && D.kind === "asperity" && sceneState.camera) {
        const p = scenePoint(ev), w = toWorld(sceneState.camera, p[0], p[1]);
        drag = { ruler: true, a: w }; setMeasure(w, w);
      } else { drag = { x: ev.clientX, y: ev.clientY, panX: state.panX, panY: state.panY }; ui.scene.classList.add("dragging"); }
      try { ui.scene.setPointerCapture(ev.pointerId); } catch (err) { /* synthetic events */ }
    });
    listen(ui.scene, "pointerup", (ev) => {
      const d = drag; drag = null; ui.scene.classList.remove("dragging");
      if (!d || !d.edit) return;
      state.selected = d.edit; render(); emitSelect({ ...d.edit });
      if (d.moved && sceneState.camera) { // a lower asperity moved along the surface, or the slider's start along its track
        const c = sceneState.camera, dx = (ev.clientX - d.x) / (c.scale * c.zoom);
        emitEdit(d.edit.kind === "lower" ? { kind: "lower", index: d.edit.index, dx: dx } : { kind: "slider", index: null, dx: dx });
      }
    });
    listen(ui.scene, "pointermove", (ev) => {
      if (drag && drag.edit) {
        if (Math.abs(ev.clientX - drag.x) > 3) drag.moved = true;
        if (drag.moved && drag.edit.kind === "lower" && sceneState.camera) {
          const c = sceneState.camera;
          state.preview = { index: drag.edit.index, dx: (ev.clientX - drag.x) / (c.scale * c.zoom) };
          requestRender();
        }
        return;
      }
      if (drag && drag.ruler) { const p = scenePoint(ev); setMeasure(drag.a, toWorld(sceneState.camera, p[0], p[1])); requestRender(); return; }
      if (drag) { state.panX = drag.panX + ev.clientX - drag.x; state.panY = drag.panY + ev.clientY - drag.y; requestRender(); return; }
      if (D.kind !== "asperity" || !N || !sceneState.camera) return;
      const p = scenePoint(ev), [X, Y] = toWorld(sceneState.camera, p[0], p[1]);
      const contact = contactAt(p[0], p[1]);
      if (contact) { showTip(ev, contact.text); return; }
      showTip(ev, "x = " + si(X, "m") + "\ny = " + si(Y, "m") + "\nslider at " + si(S.x[state.index], "m"));
    });
    function contactAt(px, py) { // the touching lower tip within 14 px of the pointer, and its force
      const i = state.index;
      let best = null, bestD = 14;
      (drawn.lower_px || []).forEach((q, j) => {
        const d = Math.hypot(q[0] - px, q[1] - py);
        if (S.lower_contact[j][i] && d < bestD) { best = j; bestD = d; }
      });
      if (best === null) return null;
      const shares = forceShares(i, new Float64Array(G.n_lower)), s = shares[best];
      const fx = s * S.friction_force[i], fy = s * S.normal_force[i];
      return { tip: best, force: Math.hypot(fx, fy), friction: fx, normal: fy,
               text: "lower tip " + (best + 1) + " touching the slider\ncontact force " + si(Math.hypot(fx, fy), "N", 4) +
                 "\n  friction " + si(fx, "N", 4) + ", normal " + si(fy, "N", 4) + "\n  (" + Math.round(100 * s) +
                 " % of the total, by track-spring load)\ndeflection " + si(S.lower_dy[best][i], "m", 4) };
    }
    listen(ui.scene, "pointerleave", () => hideTip());
    function showTip(ev, text) {
      ui.tip.hidden = false; ui.tip.textContent = text;
      ui.tip.style.left = (ev.clientX + 14) + "px"; ui.tip.style.top = (ev.clientY + 10) + "px";
    }
    function hideTip() { ui.tip.hidden = true; }
    function meterTime(m, clientX) {
      const r = m.canvas.getBoundingClientRect(), p = m.plot, view = timeView();
      return view[0] + (clientX - r.left - p.x0) / (p.x1 - p.x0) * (view[1] - view[0]);
    }
    function bindMeter(m) {
      let press = null;
      m.canvas.addEventListener("mousedown", (ev) => {
        if (!m.plot || ev.button !== 0) return;
        const r = m.canvas.getBoundingClientRect(), x = ev.clientX - r.left, y = ev.clientY - r.top, p = m.plot;
        if (x < p.x0 || x > p.x1 || y < p.y0 || y > p.y1) return;
        press = [x, y]; ev.preventDefault();
      });
      m.canvas.addEventListener("mousemove", (ev) => {
        if (!m.plot || !N) return;
        const r = m.canvas.getBoundingClientRect(), p = m.plot;
        if (press) {
          const x = Math.max(p.x0, Math.min(p.x1, ev.clientX - r.left)), y = Math.max(p.y0, Math.min(p.y1, ev.clientY - r.top));
          m.band = [press[0], press[1], x, y]; hideTip(); requestRender(); return;
        }
        const t = meterTime(m, ev.clientX), view = timeView();
        if (t < view[0] || t > view[1]) { hover = null; hideTip(); requestRender(); return; }
        const j = indexAt(t);
        hover = T[j];
        showTip(ev, "t = " + si(T[j], "s", 4) + "\n" + m.traces.map((tr) => tr.label + ": " + si(tr.values[j], m.spec.unit, 4)).join("\n") +
                "\nclick to go there \u00b7 drag a box to zoom \u00b7 double-click to reset");
        requestRender();
      });
      m.canvas.addEventListener("mouseup", (ev) => {
        if (!press) return;
        const r = m.canvas.getBoundingClientRect(), p = m.plot;
        const x = Math.max(p.x0, Math.min(p.x1, ev.clientX - r.left)), y = Math.max(p.y0, Math.min(p.y1, ev.clientY - r.top));
        const [ax, ay] = press; press = null; m.band = null;
        const view = timeView(), lim = m.limits;
        const tOf = (px) => view[0] + (px - p.x0) / (p.x1 - p.x0) * (view[1] - view[0]);
        const vOf = (py) => lim[0] + (p.y1 - py) / (p.y1 - p.y0) * (lim[1] - lim[0]);
        const wide = Math.abs(x - ax) > 5, tall = Math.abs(y - ay) > 5;
        if (wide || tall) {
          zoomMeter(m, wide ? tOf(Math.min(ax, x)) : null, wide ? tOf(Math.max(ax, x)) : null,
                    tall ? vOf(Math.max(ay, y)) : null, tall ? vOf(Math.min(ay, y)) : null);
        } else if (hover !== null) { pause(); userSeek(hover); }
        else requestRender();
      });
      m.canvas.addEventListener("dblclick", () => resetZoom(m));
      m.canvas.addEventListener("mouseleave", () => { hover = null; if (press) { press = null; m.band = null; } hideTip(); requestRender(); });
    }
    function frameSvg() {
      const r = ui.scene.getBoundingClientRect(), W = Math.round(r.width), H = Math.round(r.height);
      const ctx = SvgContext(W, H);
      ctx.fillStyle = "#fff"; ctx.fillRect(0, 0, W, H);
      if (N) (D.kind === "asperity" ? drawAsperity : drawChain)(ctx, W, H);
      ctx.fillStyle = "#000"; ctx.font = "bold 13px system-ui, sans-serif"; ctx.textBaseline = "top"; ctx.textAlign = "left";
      ctx.fillText("t = " + si(N ? T[state.index] : 0, "s", 4) + (ui.stateBadge.textContent ? "  " + ui.stateBadge.textContent : ""), 8, 6);
      return ctx.document();
    }

    // ---- streaming ---------------------------------------------------------------------------
    function append(chunk) {
      if (destroyed) return;
      if (chunk.start !== undefined && chunk.start !== null && chunk.start !== N)
        throw new Error("AsperityPlayer.append: chunk starts at sample " + chunk.start + " but " + N + " are held");
      const first = N === 0;
      addSamples(chunk.t, chunk.series || {});
      if (first) { state.index = 0; state.t = T[0]; }
      foot(); requestRender();
    }
    function finish(final) {
      if (destroyed) return;
      final = final || {};
      for (const key of ["events", "slips", "slow", "frame_step", "recorded", "title", "force_scale"]) if (final[key] !== undefined) D[key] = final[key];
      if (final.force_scale !== undefined && D.kind === "asperity") G.force_scale = final.force_scale;
      if (final.limits) for (const c of channels) if (final.limits[c.id]) c.limits = final.limits[c.id];
      if (D.recorded === undefined) D.recorded = N;
      finished = true;
      if (D.kind === "asperity" && S.slipping && final.slips) { // the flags streamed with a partial record's events: redone
        const flags = new Int8Array(N);
        for (const [a, b] of D.slips) for (let i = firstAfter(a); i < N && T[i] <= b; i++) if (T[i] > a) flags[i] = 1;
        S.slipping = flags;
      }
      for (const m of meters) { m.cache = null; m.autoLimits = null; }
      ui.title.textContent = D.title; buildEvents(); foot(); requestRender();
    }
    let destroyed = false;
    const ro = typeof ResizeObserver !== "undefined" ? new ResizeObserver(() => requestRender()) : null;
    if (ro) { ro.observe(ui.scene); ro.observe(ui.meters); }
    listen(window, "resize", requestRender);
    const io = typeof IntersectionObserver !== "undefined" ? new IntersectionObserver(() => requestRender()) : null;
    if (io) io.observe(root);
    const redrawAll = () => { for (const m of meters) m.cache = null; requestRender(); };
    created.add(redrawAll);
    function destroy() {
      destroyed = true; state.playing = false; created.delete(redrawAll);
      if (rafId !== null) cancelAnimationFrame(rafId);
      if (ro) ro.disconnect(); if (io) io.disconnect();
      for (const c of cleanups.splice(0)) c();
      cursorListeners.length = 0; viewListeners.length = 0;
      root.innerHTML = ""; root.classList.remove("ap");
    }

    // ---- start -------------------------------------------------------------------------------
    for (const id of D.meters || channels.slice(0, 4).map((c) => c.id)) makeMeter(id);
    buildEvents(); foot();
    render();

    const api = {
      kind: D.kind, get samples() { return N; }, get t0() { return tStart(); }, get t1() { return tEnd(); },
      state: () => ({ t: N ? T[state.index] : 0, index: state.index, playing: state.playing, speed: state.speed,
                      zoom: state.zoom, camera_mode: state.camera, exaggeration: state.exaggeration,
                      slow: slowAt(N ? T[state.index] : 0), ...sceneState, drawn: drawn, meter_cursor_px: cursors,
                      meter_plots: meters.map((m) => m.plot), view: timeView(), zoomed: state.view !== null,
                      measure: state.measure, finished: finished, samples: N }),
      seek: (t) => { pause(); userSeek(t); return T[state.index]; },
      play: play, pause: () => { pause(); render(); }, step: step,
      setSpeed: (v) => { state.speed = v; ui.speed.value = String(v); },
      si: si,
      channels: () => channels.map((c) => ({ id: c.id, title: c.title, unit: c.unit, group: c.group || "run" })),
      meters: () => meters.map((m) => ({ channel: m.spec.id, title: m.spec.title, unit: m.spec.unit, limits: m.limits,
                                         plot: m.plot, clipped: m.clipped, labels: m.spec.traces.map((tr) => tr.label),
                                         axis_unit: m.unitLabel, readouts: (m.traces || []).map((tr) => axisText(m, tr.values[state.index])) })),
      setChannel: (k, id) => { setChannel(meters[k], id); render(); return meters[k].spec.id; },
      zoomMeter: (k, ta, tb, lo, hi) => { zoomMeter(meters[k], ta, tb, lo, hi); render(); },
      resetZoom: (k) => { resetZoom(k === undefined ? null : meters[k]); render(); },
      exportMeter: (k, kind) => (kind === "svg" ? meterSvg(meters[k]) : kind === "csv-all" ? meterCsvAll(meters[k]) : meterCsv(meters[k])),
      overlays: () => overlays.map((ov) => ({ label: ov.label, colour: ov.colour, samples: ov.T.length })),
      difference: () => difference,
      selected: () => (state.selected ? { ...state.selected } : null),
      select: (sel) => { state.selected = sel; render(); },
      pick: (px, py) => pick(px, py),
      dragLower: (j, dxPx) => { // as a person drags lower asperity j by dxPx pixels (tests)
        const c = sceneState.camera; if (!c) return null;
        const dx = dxPx / (c.scale * c.zoom); emitEdit({ kind: "lower", index: j, dx: dx }); return dx; },
      dragSlider: (dxPx) => { // as a person drags the slider by dxPx pixels: its start moves (tests)
        const c = sceneState.camera; if (!c) return null;
        const dx = dxPx / (c.scale * c.zoom); emitEdit({ kind: "slider", index: null, dx: dx }); return dx; },
      exportFrame: () => frameSvg(),
      events: () => eventList().map((e) => ({ t: e.t, end: e.end, label: e.label, lands: eventTime(e) })),
      jumpToEvent: (k) => { const e = eventList()[k]; pause(); userSeek(eventTime(e)); return T[state.index]; },
      contactAt: (px, py) => contactAt(px, py),
      measure: (a, b) => { setMeasure(a, b); render(); return state.measure; },
    };
    return {
      api, append, finish, destroy,
      /* the kept runs: [{label, colour, T, S}] (a snapshot()'s arrays), drawn on every meter under this run */
      setOverlays(list) { overlays = (list || []).slice(); if (difference !== null && !overlays[difference]) difference = null; overlayVersion++; for (const m of meters) m.cache = null; requestRender(); },
      /* the meters show this run minus kept run k (interpolated at this run's samples); null: the runs themselves */
      setDifference(k) { difference = k === null || k === undefined || !overlays[k] ? null : k; overlayVersion++; for (const m of meters) { m.cache = null; m.zoomY = null; } requestRender(); },
      /* this run's arrays, and each channel's axis as its meter draws it (kept runs widen later runs' axes to theirs) */
      snapshot() {
        const limits = {};
        for (const c of channels) if (c.limits) limits[c.id] = c.limits.slice();
        return { T: T, S: S, samples: N, limits: limits };
      },
      onSelect(cb) { selectListeners.push(cb); },
      onEdit(cb) { editListeners.push(cb); },
      clearPreview() { state.preview = null; requestRender(); },
      onCursor(cb) { cursorListeners.push(cb); return () => { const k = cursorListeners.indexOf(cb); if (k >= 0) cursorListeners.splice(k, 1); }; },
      setCursor(t) { if (!destroyed && N) { state.playing = false; seek(t); } },
      onView(cb) { viewListeners.push(cb); return () => { const k = viewListeners.indexOf(cb); if (k >= 0) viewListeners.splice(k, 1); }; },
      setView(view) { if (destroyed) return; state.view = view && view[1] > view[0] ? [view[0], view[1]] : null; requestRender(); },
      get samples() { return N; },
    };
  }

  /* the units menu: setUnits({"m": -6, "N": -3, "s": -6, "m/s": 0}) fixes each unit's prefix (an
     exponent of 10); a unit left out or null is automatic. Every player of the page redraws. */
  const created = new Set();
  function setUnits(map) {
    for (const k of Object.keys(UNITS)) delete UNITS[k];
    for (const [k, v] of Object.entries(map || {})) if (v !== null && v !== undefined && PREFIX[String(v)] !== undefined) UNITS[k] = v;
    for (const redraw of created) redraw();
  }
  window.AsperityPlayer = { create: create, version: 3, setUnits: setUnits, units: () => ({ ...UNITS }), _created: created };
  // the offline page: boot from the embedded JSON
  const data = document.getElementById("asperity-data"), host = document.getElementById("asperity-player");
  if (data && host) {
    const player = create(host, JSON.parse(data.textContent), { keys: true });
    window.asperityPlayer = player.api;
    window.asperityPlayerInstance = player;
  }
})();
