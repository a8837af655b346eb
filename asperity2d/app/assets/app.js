/* asperity2d workbench: one front end for two hosts (an ES module, no library, no build step).

   The notebook widget (anywidget) calls the default export's render({model, el}); the web app's
   page calls it with socketModel(url), a WebSocket that behaves as an anywidget model for the
   two calls the workbench makes: model.send(object) and model.on("msg:custom", callback).
   The message protocol is asperity2d.app.session's. Runs are drawn by the player component
   (window.AsperityPlayer, asperity2d/renderers/assets/player.js), streamed in as they are
   computed. window.asperityWorkbench (the first workbench of a page) is the test interface. */

const PREFIX = { "-18": "a", "-15": "f", "-12": "p", "-9": "n", "-6": "\u00b5", "-3": "m", "0": "", "3": "k",
                 "6": "M", "9": "G", "12": "T" };
function si(value, unit, digits) {  // the rule of asperity2d._format.si
  digits = digits || 4;
  const sep = unit ? " " : "";
  if (value === null || value === undefined || !isFinite(value)) return "\u2013" + sep + unit;
  if (value === 0) return "0" + sep + unit;
  let base = unit, shift = 0;
  if (unit === "kg") { base = "g"; shift = 3; }
  const scaled = value * Math.pow(10, shift);
  let e = Math.max(-18, Math.min(12, 3 * Math.floor(Math.log10(Math.abs(scaled)) / 3)));
  if (unit === "1" || unit === "-" || unit === "") { base = ""; e = 0; }
  const m = scaled / Math.pow(10, e);
  const text = m.toPrecision(digits).replace(/(\.\d*?[1-9])0+$|\.0+$/, "$1");
  return text + sep + (PREFIX[e] || "") + base;
}

/* a TOML list of numbers, each written so it reads back as the same double (shortest round trip) */
function tomlList(values) { return "[" + values.map((v) => { const t = String(v); return /[.eEn]/.test(t) ? t : t + ".0"; }).join(", ") + "]"; }
// kept runs: colours none of the meters' own traces use (those are matplotlib's tab10 c0-c6)
const KEPT_COLOURS = ["#17becf", "#bcbd22", "#e377c2", "#7f7f7f", "#000000"];
/* the units menu: automatic SI prefixes, or one fixed prefix per quantity (an exponent of 10) */
const UNIT_CHOICES = { m: [["auto", null], ["nm", -9], ["\u00b5m", -6], ["mm", -3], ["m", 0]],
                       N: [["auto", null], ["\u00b5N", -6], ["mN", -3], ["N", 0]],
                       s: [["auto", null], ["ns", -9], ["\u00b5s", -6], ["ms", -3], ["s", 0]],
                       "m/s": [["auto", null], ["mm/s", -3], ["m/s", 0]] };
const UNITS_KEY = "asperity2d.workbench.units";

function fix(v) { return v === null || v === undefined || !isFinite(v) ? "\u2013" : v.toFixed(3); }

function h(tag, attrs, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (k === "class") el.className = v;
    else if (k.startsWith("on")) el.addEventListener(k.slice(2), v);
    else if (k === "text") el.textContent = v;
    else if (v !== null && v !== undefined && v !== false) el.setAttribute(k, v === true ? "" : v);
  }
  for (const c of children.flat()) if (c !== null && c !== undefined) el.append(c.nodeType ? c : document.createTextNode(String(c)));
  return el;
}

/* A WebSocket as an anywidget-like model: send(object), on("msg:custom", cb). */
export function socketModel(url) {
  const listeners = [], queue = [];
  let ws = null, open = false, closed = false;
  const status = { connected: false, closed: false };
  function connect() {
    ws = new WebSocket(url);
    ws.onopen = () => { open = true; status.connected = true; while (queue.length) ws.send(queue.shift()); };
    ws.onmessage = (m) => { for (const cb of listeners) cb(m.data); };
    ws.onclose = (ev) => { open = false; status.connected = false; status.closed = true;
                           for (const cb of listeners) cb(JSON.stringify({ type: "disconnected", code: ev.code, reason: ev.reason })); };
  }
  connect();
  return {
    send(obj) { const text = JSON.stringify(obj); if (open) ws.send(text); else if (!closed) queue.push(text); },
    on(event, cb) { if (event === "msg:custom") listeners.push(cb); },
    off() { listeners.length = 0; },
    close() { closed = true; if (ws) ws.close(); },
    status,
  };
}

function decodeMessage(msg) {
  if (typeof msg === "string") return JSON.parse(msg);
  if (msg && typeof msg.m === "string") return JSON.parse(msg.m);
  return msg;
}

function download(name, blob) {
  const a = h("a", { href: URL.createObjectURL(blob), download: name });
  document.body.append(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

function render({ model, el }) {
  const S = {  // everything the tests read
    schema: null, values: {}, errors: {}, valid: true, python: "",
    run: { job: null, running: false, chunks: 0, samples: 0, t: 0, started: 0, firstChunkMs: null, endMs: null,
           finished: false, summary: null, chunkLog: [] },
    measures: {}, measureList: [], presets: {},
    variants: { job: null, names: [], done: 0, players: {} },
    ensemble: { job: null, values: {}, stats: null, done: false, variants: [], seeds: [], unit: "N", label: "" },
    messages: [], lastError: null, exports: [], connected: true, changedAt: null,
    bodies: null, selected: null, kept: [], difference: null, units: {}, drawer: false,
  };
  let player = null, follow = true;
  const players = {};  // compare players by variant name

  // ---- layout ------------------------------------------------------------------------------
  el.classList.add("aw");
  const status = h("span", { class: "aw-status", text: "connecting\u2026" });
  const bar = h("div", { class: "aw-bar" }, h("div", { class: "aw-bar-fill" }));
  const cancelRun = h("button", { class: "aw-btn", "data-act": "stop", title: "stop the run being computed", onclick: () => model.send({ type: "cancel", lane: "run" }) }, "Stop");
  const runBtn = h("button", { class: "aw-btn", "data-act": "run", title: "run the scene again from its start (a change runs by itself)", onclick: () => rerun() }, "\u25B6 Run");
  const resetBtn = h("button", { class: "aw-btn", "data-act": "reset", title: "back to the model's start (the first sample)", onclick: () => { if (player) player.api.seek(player.api.t0); } }, "Reset");
  const stepBtn = h("button", { class: "aw-btn", "data-act": "step", title: "one sample forward", onclick: () => { if (player) player.api.step(1); } }, "Step \u25B8");
  const keepBtn = h("button", { class: "aw-btn", "data-act": "keep", title: "keep this run: the next runs are drawn over it, in another colour", onclick: () => keepRun() }, "Keep run");
  const drawerBtn = h("button", { class: "aw-btn aw-drawer-btn", "data-act": "drawer", title: "show or hide the controls", "aria-expanded": "false", onclick: () => toggleDrawer() }, "\u2630 Controls");
  const unitsBox = h("details", { class: "aw-units" }, h("summary", { class: "aw-btn", title: "units of the axes and read-outs" }, "Units"));
  const saveToml = h("button", { class: "aw-btn", "data-act": "save-toml", title: "the scene as a TOML file: `asperity2d run scene.toml` reproduces this run", onclick: () => model.send({ type: "export", what: "toml" }) }, "Save TOML");
  const copyPy = h("button", { class: "aw-btn", title: "copy the make_scene(...) call", onclick: () => copyPython() }, "Copy as Python");
  const saveNpz = h("button", { class: "aw-btn", "data-act": "save-npz", title: "the finished run as a .npz result (asperity2d.load)", onclick: () => model.send({ type: "export", what: "npz" }) }, "Save run .npz");
  const header = h("div", { class: "aw-header" }, drawerBtn, h("span", { class: "aw-brand" }, "asperity2d"),
                   runBtn, cancelRun, resetBtn, stepBtn, keepBtn, bar, status, unitsBox, saveToml, copyPy, saveNpz);
  const sidebar = h("div", { class: "aw-side" });
  const formError = h("div", { class: "aw-form-error", role: "alert" });
  const tabs = h("div", { class: "aw-tabs", role: "tablist" });
  const panes = {};
  const main = h("div", { class: "aw-main" }, tabs);
  const note = h("pre", { class: "aw-python", title: "make_scene call of the current scene" });
  for (const [id, label] of [["run", "Run"], ["measure", "Measure"], ["compare", "Compare"], ["ensemble", "Ensemble"]]) {
    const b = h("button", { class: "aw-tab", role: "tab", "data-tab": id, onclick: () => showTab(id) }, label);
    tabs.append(b);
    panes[id] = h("div", { class: "aw-pane", "data-pane": id });
    main.append(panes[id]);
  }
  const playerHost = h("div", { class: "aw-player" });
  const inspector = h("div", { class: "aw-inspector", "data-panel": "selection" },
                      h("span", { class: "aw-help" }, "Click a lower asperity or the slider to select it; drag a lower asperity along the surface to move it, the slider along its track to set its start."));
  const keptBox = h("div", { class: "aw-kept", hidden: true });
  panes.run.append(inspector, keptBox, playerHost, h("details", { class: "aw-py" }, h("summary", {}, "make_scene call"), note));
  const sideWrap = h("div", { class: "aw-side-wrap" }, formError, sidebar);
  el.append(header, h("div", { class: "aw-body" }, sideWrap, main));
  function toggleDrawer(open) {
    S.drawer = open === undefined ? !S.drawer : open;
    el.classList.toggle("aw-drawer-open", S.drawer); drawerBtn.setAttribute("aria-expanded", String(S.drawer));
  }
  function showTab(id) {
    for (const b of tabs.children) b.classList.toggle("aw-active", b.dataset.tab === id);
    for (const [k, p] of Object.entries(panes)) p.hidden = k !== id;
  }
  showTab("run");

  // ---- controls ----------------------------------------------------------------------------
  const inputs = {}, errorEls = {};
  function buildControls(schema) {
    sidebar.replaceChildren();
    const groups = [...schema.groups, { title: "run", controls: schema.run }];
    groups.forEach((g, gi) => {
      const box = h("details", { class: "aw-group", open: gi < 2 || g.title === "run" }, h("summary", {}, g.title));
      for (const c of g.controls) {
        let input;
        const current = S.values[c.name] || "";
        if (c.kind === "choice") {
          input = h("select", { name: c.name, "aria-label": c.name },
                    h("option", { value: "", text: c.default ? `${c.default} (default)` : "(derived)" }),
                    c.choices.filter((v) => v !== c.default).map((v) => h("option", { value: v, text: v })));
          input.value = current;
        } else if (c.kind === "flag") {
          input = h("select", { name: c.name, "aria-label": c.name }, h("option", { value: "", text: `${c.default} (default)` }),
                    h("option", { value: "true", text: "true" }), h("option", { value: "false", text: "false" }));
          input.value = current;
        } else {
          input = h("input", { name: c.name, "aria-label": c.name, type: "text", spellcheck: "false", autocomplete: "off",
                               placeholder: c.derived ? "derived" : c.default });
          input.value = current;
        }
        input.addEventListener("change", () => change(c.name, input.value));
        if (input.tagName === "INPUT") input.addEventListener("keydown", (e) => { if (e.key === "Enter") input.blur(); });
        const unit = c.unit === "-" || c.unit === "1" ? "" : c.unit;
        const err = h("div", { class: "aw-error", "data-error": c.name });
        inputs[c.name] = input; errorEls[c.name] = err;
        box.append(h("label", { class: "aw-control", title: c.meaning },
                     h("span", { class: "aw-name" }, c.name), input, h("span", { class: "aw-unit" }, unit)), err);
      }
      sidebar.append(box);
    });
  }
  function change(name, text) {
    if (text.trim()) S.values[name] = text; else delete S.values[name];
    S.changedAt = performance.now();
    model.send({ type: "set", values: S.values, changed: name });
  }
  function rerun() { S.changedAt = performance.now(); model.send({ type: "set", values: S.values }); }
  function setValues(values) {
    S.values = { ...values };
    for (const [name, input] of Object.entries(inputs)) input.value = S.values[name] || "";
  }
  function showErrors(errors) {
    S.errors = errors || {};
    for (const [name, e] of Object.entries(errorEls)) { e.textContent = S.errors[name] || ""; inputs[name].classList.toggle("aw-bad", !!S.errors[name]); }
    const other = Object.keys(S.errors).filter((k) => k && !errorEls[k]);  // a stage edit (lower_positions)
    formError.textContent = [S.errors[""] || ""].concat(other.map((k) => S.errors[k])).filter(Boolean).join("; ");
    for (const e of inspector.querySelectorAll("[data-edit-error]")) e.textContent = "";
    for (const [k, v] of Object.entries(S.errors)) {
      const e = inspector.querySelector(`[data-edit-error="${CSS.escape(k)}"]`);
      if (e) e.textContent = v;
      const f = inspector.querySelector(`[data-field="${CSS.escape(k)}"]`);
      if (f) f.classList.add("aw-bad");
    }
    if (S.errors.lower_positions || Object.keys(S.errors).length) { if (player && player.clearPreview) player.clearPreview(); }
    if (Object.keys(S.errors).some((k) => k && errorEls[k])) toggleDrawer(true);  // at 375 px the marked control must show
  }
  async function copyPython() {
    try { await navigator.clipboard.writeText(S.python); flash("make_scene call copied"); }
    catch (e) { note.closest("details").open = true; flash("select the make_scene call below to copy it"); }
  }
  let flashTimer = null;
  function flash(text) { status.dataset.flash = text; status.classList.add("aw-flash"); clearTimeout(flashTimer); flashTimer = setTimeout(() => status.classList.remove("aw-flash"), 2500); setStatus(); }

  // ---- the run -----------------------------------------------------------------------------
  function setStatus() {
    const r = S.run;
    let text;
    if (!S.connected) text = "disconnected";
    else if (!S.valid) text = "refused: see the control marked in red (the last valid run stays)";
    else if (r.running) text = `computing\u2026 t = ${si(r.t, "s", 3)}, ${r.samples} samples`;
    else if (r.finished && r.summary) text = `done: ${r.samples} samples, ${si(r.t, "s", 3)}` + (r.summary.status ? `, ${r.summary.status}` : "") + (r.endMs !== null ? ` (${(r.endMs / 1000).toFixed(1)} s)` : "");
    else if (r.job !== null) text = "stopped";
    else text = "ready";
    status.textContent = status.classList.contains("aw-flash") ? status.dataset.flash : text;
    status.title = status.textContent;  // the whole line where the header cuts it
    bar.classList.toggle("aw-busy", r.running);
    const duration = player && r.duration ? Math.min(1, r.t / r.duration) : (r.finished ? 1 : 0);
    bar.firstChild.style.width = `${Math.round(100 * (r.finished ? 1 : duration))}%`;
    cancelRun.disabled = !r.running;
    saveNpz.disabled = !r.finished;
    keepBtn.disabled = !r.finished;
    resetBtn.disabled = stepBtn.disabled = !player;
  }
  function newPlayer(host, payload, options) {
    return window.AsperityPlayer.create(host, payload, options);
  }
  function onRun(m) {
    if (m.type === "run-start") {
      if (player) player.destroy();
      playerHost.replaceChildren();
      const host = h("div", { class: "ap" });
      playerHost.append(host);
      player = newPlayer(host, m.player, { keys: true, duration: m.player.duration, edit: true, runLabel: "this run" });
      follow = true;
      player.onCursor(() => { follow = false; });
      player.setOverlays(S.kept);
      if (S.difference !== null) player.setDifference(S.difference);
      player.onSelect((sel) => select(sel));
      player.onEdit((edit) => (edit.kind === "slider" ? moveSlider(edit.dx) : moveLower(edit.index, edit.dx)));
      if (S.selected && player.api.select) player.api.select(S.selected);
      Object.assign(S.run, { job: m.job, running: true, chunks: 0, samples: 0, t: 0, started: performance.now(),
                              firstChunkMs: null, endMs: null, finished: false, summary: null, chunkLog: [],
                              duration: m.player.duration });
    } else if (m.job !== S.run.job || !player) {
      return;  // a cancelled run's late message
    } else if (m.type === "run-chunk") {
      player.append(m.chunk);
      const r = S.run;
      r.chunks += 1; r.samples = player.samples; r.t = m.t;
      if (r.firstChunkMs === null) r.firstChunkMs = performance.now() - (S.changedAt || r.started);
      if (follow) player.setCursor(m.t);  // the scene shows the newest computed state
      r.chunkLog.push({ at: performance.now(), samples: r.samples, index: player.api.state().index });
    } else if (m.type === "run-end") {
      player.finish(m.final);
      Object.assign(S.run, { running: false, finished: true, summary: m.summary, samples: player.samples,
                              endMs: performance.now() - (S.changedAt || S.run.started) });
      if (follow) player.setCursor(player.api.t0);
    }
    setStatus();
  }

  // ---- the selection: a body's own panel, its values written into the scene's fields ----------
  const LOWER_FIELDS = [["stiffness", "stiffness", "N/m"], ["damping", "damping", "N s/m"], ["mass", "mass", "kg"]];
  function perAsperity(field, j, text) {  // one asperity's value changed: the whole per-asperity list, as a parameter
    const list = S.bodies.lower[field].slice();
    const v = Number(text.trim());
    if (!text.trim() || !isFinite(v)) { showErrors({ [field]: `\`${field}\` of asperity ${j + 1} must be a finite number, got ${JSON.stringify(text.slice(0, 40))}` }); S.valid = false; setStatus(); return; }
    list[j] = v;
    if (field === "damping") delete S.values.damping_ratio;  // per-track dampers replace the ratio
    setControl(field, tomlList(list));
  }
  function setControl(name, text) { if (inputs[name]) inputs[name].value = text; change(name, text); }
  function moveLower(j, dx) {
    if (!S.bodies) return;
    const xs = S.bodies.lower.x.slice();
    xs[j] = xs[j] + dx;
    S.selected = { kind: "lower", index: j };
    setControl("lower_positions", tomlList(xs));
  }
  function sliderStart() {  // where the slider's rear tip starts: the scene's slider_start, else where this run began
    if (S.bodies && S.bodies.slider.start !== null && S.bodies.slider.start !== undefined) return S.bodies.slider.start;
    return player && player.samples ? player.snapshot().S.x[0] : null;
  }
  function moveSlider(dx) {
    const x0 = sliderStart();
    if (x0 === null || !isFinite(dx)) return;
    S.selected = { kind: "slider", index: null };
    setControl("slider_start", String(x0 + dx));
  }
  function select(sel) { S.selected = sel; showSelection(); }
  function showSelection() {
    const sel = S.selected, B = S.bodies;
    if (!sel || !B) return;
    const rows = [];
    const field = (name, value, unit, onset, readOnly) => {
      const input = h("input", { type: "text", "data-field": name, "aria-label": name, value: String(value), spellcheck: "false", readonly: !!readOnly });
      if (!readOnly) {
        input.addEventListener("change", () => onset(input.value));
        input.addEventListener("keydown", (e) => { if (e.key === "Enter") input.blur(); });
      }
      rows.push(h("label", { class: "aw-control" }, h("span", { class: "aw-name" }, name), input, h("span", { class: "aw-unit" }, unit)),
                h("div", { class: "aw-error", "data-edit-error": name }));
    };
    if (sel.kind === "lower") {
      const j = sel.index, L = B.lower;
      if (j >= L.x.length) return;
      field("position", L.x[j], "m", (t) => { const v = Number(t); if (isFinite(v) && t.trim()) moveLower(j, v - L.x[j]); else showErrors({ lower_positions: `the position of asperity ${j + 1} must be a finite number of m, got ${JSON.stringify(t.slice(0, 40))}` }); });
      field("height", si(L.height[j], "m", 4), "", null, true);
      for (const [name, key, unit] of LOWER_FIELDS) field(key, L[key][j], unit, (t) => perAsperity(key, j, t));
      inspector.replaceChildren(h("div", { class: "aw-inspector-title" }, `lower asperity ${j + 1} of ${L.x.length}`,
        h("button", { class: "aw-btn", "data-act": "unmove", title: "every lower asperity back on its spacing", onclick: () => setControl("lower_positions", "") }, "undo moves")), ...rows,
        h("div", { class: "aw-help" }, "Edits go into the scene's per-asperity fields (lists); the height follows the surface's shape."));
    } else {
      const x0 = sliderStart();
      field("start", x0 === null ? "" : x0, "m", (t) => setControl("slider_start", t.trim()));
      field("slider_mass", B.slider.mass, "kg", (t) => setControl("slider_mass", t));
      field("normal_load", B.slider.normal_load, "N", (t) => setControl("normal_load", t));
      field("track", B.slider.track, "", (t) => setControl("track", t));
      inspector.replaceChildren(h("div", { class: "aw-inspector-title" }, `slider (${B.slider.count} tips)`,
        h("button", { class: "aw-btn", "data-act": "unstart", title: "the set-up's start: left of the surface (fixed track), over the first valley (free)", onclick: () => setControl("slider_start", "") }, "set-up's start")), ...rows,
        h("div", { class: "aw-help" }, "Drag the slider along its track to set its start (slider_start: its rear tip's x, the first lower tip at 0); by default it starts left of the surface (fixed track) or over the first valley (free)."));
    }
    if (player && player.api.select) player.api.select(sel);
    showErrors(S.errors);
  }

  // ---- kept runs: drawn over the next ones, a difference channel, CSV of all ---------------------
  function describeChanges(from, to) {  // the parameters where two runs' texts differ
    const names = [...new Set([...Object.keys(from), ...Object.keys(to)])].sort();
    const shown = (v) => (v === undefined ? "default" : v.length > 24 ? "edited list" : v);
    const out = names.filter((k) => (from[k] || "") !== (to[k] || "")).map((k) => `${k} ${shown(from[k])} (now ${shown(to[k])})`);
    return out.length ? out.join(", ") : "same parameters";
  }
  function keepRun() {
    if (!player || !S.run.finished) return;
    const snap = player.snapshot(), k = S.kept.length;
    S.kept.push({ label: `kept ${k + 1}`, colour: KEPT_COLOURS[k % KEPT_COLOURS.length], T: snap.T, S: snap.S,
                  values: { ...S.values }, samples: snap.samples, limits: snap.limits });
    player.setOverlays(S.kept);
    showKept(); flash(`run kept as "kept ${k + 1}": the next runs are drawn over it`);
  }
  function showKept() {
    keptBox.hidden = !S.kept.length;
    const meterSel = h("select", { "aria-label": "meter to export", "data-act": "csv-meter" }, [0, 1, 2, 3].map((k) => h("option", { value: String(k), text: `meter ${k + 1}` })));
    keptBox.replaceChildren(h("div", { class: "aw-kept-head" }, h("b", {}, "kept runs"), " (drawn under this run, in their colours)",
      h("span", { class: "aw-sep" }),
      h("label", {}, h("input", { type: "radio", name: "aw-diff", checked: S.difference === null, onchange: () => setDifference(null) }), " runs"),
      meterSel,
      h("button", { class: "aw-btn", "data-act": "csv-all", title: "this meter's samples of this run and of every kept run, one CSV", onclick: () => {
        if (!player) return;
        const k = parseInt(meterSel.value, 10), text = player.api.exportMeter(k, "csv-all");
        S.exports.push({ what: "csv-all", filename: `meter-${k + 1}-runs.csv`, text, size: text.length });
        download(`meter-${k + 1}-runs.csv`, new Blob([text], { type: "text/csv" }));
      } }, "CSV of all runs"),
      h("button", { class: "aw-btn", "data-act": "forget", onclick: () => { S.kept = []; setDifference(null); if (player) player.setOverlays([]); showKept(); } }, "forget all")),
      ...S.kept.map((r, k) => h("div", { class: "aw-kept-row", "data-kept": String(k) },
        h("span", { class: "aw-swatch", style: `background:${r.colour}` }), h("b", {}, r.label), `: ${describeChanges(r.values, S.values)} \u2014 ${r.samples} samples `,
        h("label", { title: "the meters show this run minus the kept one" }, h("input", { type: "radio", name: "aw-diff", "data-diff": String(k), checked: S.difference === k, onchange: () => setDifference(k) }), " this \u2212 kept"))));
  }
  function setDifference(k) { S.difference = k; if (player) player.setDifference(k); }

  // ---- units menu ------------------------------------------------------------------------------
  function loadUnits() { try { return JSON.parse(localStorage.getItem(UNITS_KEY) || "{}") || {}; } catch (e) { return {}; } }
  function applyUnits(units) {
    S.units = units;
    try { localStorage.setItem(UNITS_KEY, JSON.stringify(units)); } catch (e) { /* no storage: this page only */ }
    if (window.AsperityPlayer && window.AsperityPlayer.setUnits) window.AsperityPlayer.setUnits(units);
  }
  {
    const saved = loadUnits();
    const box = h("div", { class: "aw-units-menu" });
    for (const [unit, choices] of Object.entries(UNIT_CHOICES)) {
      const sel = h("select", { "aria-label": `unit of ${unit}`, "data-unit": unit }, choices.map(([label, e]) => h("option", { value: e === null ? "" : String(e), text: label })));
      sel.value = saved[unit] === undefined || saved[unit] === null ? "" : String(saved[unit]);
      sel.addEventListener("change", () => { const u = { ...S.units }; if (sel.value === "") delete u[unit]; else u[unit] = parseInt(sel.value, 10); applyUnits(u); });
      box.append(h("label", {}, h("span", {}, { m: "length", N: "force", s: "time", "m/s": "speed" }[unit]), sel));
    }
    unitsBox.append(box);
    applyUnits(saved);
  }

  // ---- measures ----------------------------------------------------------------------------
  const measureRows = {}, measuredWith = {};
  function sortedValues() { return Object.keys(S.values).sort().map((k) => [k, S.values[k]]); }
  function markStale() {  // a measured value belongs to the scene it was measured on
    const now = JSON.stringify(sortedValues());
    for (const [name, M] of Object.entries(S.measures)) {
      if (M.running || M.value === null || M.value === undefined) continue;
      M.stale = measuredWith[name] !== now;
      const row = measureRows[name];
      row.value.classList.toggle("aw-stale", M.stale);
      row.value.textContent = si(M.value, M.unit, 4) + (M.stale ? " (an earlier scene: measure again)" : "");
      row.value.title = M.stale ? "measured on the scene before the last change" : "";
    }
  }
  function buildMeasures(list) {
    S.measureList = list;
    panes.measure.replaceChildren(h("p", { class: "aw-help" }, "Each measure runs on the scene as the controls set it, under the drive it needs, in its own process; Cancel stops it at once."));
    const table = h("table", { class: "aw-table aw-measures" }, h("tr", {}, h("th", {}, "measure"), h("th", {}, "drive"), h("th", {}, "value"), h("th", {}, "")));
    for (const m of list) {
      const value = h("span", { class: "aw-value", "data-measure": m.name, text: "\u2013" });
      const go = h("button", { class: "aw-btn", "data-measure": m.name, onclick: () => { measuredWith[m.name] = JSON.stringify(sortedValues()); model.send({ type: "measure", name: m.name }); } }, "Measure");
      const stop = h("button", { class: "aw-btn", hidden: true, onclick: () => model.send({ type: "cancel", lane: "measure" }) }, "Cancel");
      const prog = h("div", { class: "aw-bar aw-small", hidden: true }, h("div", { class: "aw-bar-fill" }));
      measureRows[m.name] = { value, go, stop, prog };
      table.append(h("tr", {}, h("td", { title: `${m.kind}; ${m.name}` }, m.label), h("td", {}, m.drive === "force" ? "constant force" : "spring"),
                     h("td", { class: "aw-value-cell" }, value, prog), h("td", {}, go, stop)));
    }
    panes.measure.append(table);
  }
  function onMeasure(m) {
    const row = measureRows[m.name];
    if (m.type === "measure-start") {
      for (const r of Object.values(measureRows)) { r.stop.hidden = true; r.prog.hidden = true; }
      S.measures[m.name] = { running: true, value: null, elapsed: 0 };
      row.stop.hidden = false; row.prog.hidden = false; row.prog.classList.add("aw-busy");
      row.value.textContent = "measuring\u2026";
    } else if (m.type === "measure-progress") {
      if (S.measures[m.name]) S.measures[m.name].elapsed = m.elapsed;
      row.value.textContent = `measuring\u2026 ${m.elapsed.toFixed(1)} s`;
    } else if (m.type === "measure-result") {
      S.measures[m.name] = { running: false, value: m.value, unit: m.unit, label: m.label, stale: false };
      row.value.textContent = si(m.value, m.unit, 4);
      markStale();
      row.stop.hidden = true; row.prog.hidden = true;
    }
  }

  // ---- compare: variants side by side, one time cursor ---------------------------------------
  const variantGrid = h("div", { class: "aw-grid" });
  function buildCompare(presets) {
    S.presets = presets;
    const buttons = Object.entries(presets).map(([id, names]) => h("button", { class: "aw-btn", "data-preset": id,
      onclick: () => model.send({ type: "variants", preset: id }) }, names.join(" vs ")));
    panes.compare.replaceChildren(h("p", { class: "aw-help" }, "Two variants of the current scene, run one after the other and streamed side by side; moving one time cursor moves the other."),
      h("div", { class: "aw-row" }, buttons, h("button", { class: "aw-btn", onclick: () => model.send({ type: "cancel", lane: "variants" }) }, "Cancel")), variantGrid);
  }
  function onVariants(m) {
    const V = S.variants;
    if (m.type === "variants-start") {
      for (const p of Object.values(players)) p.destroy();
      for (const k of Object.keys(players)) delete players[k];
      variantGrid.replaceChildren();
      Object.assign(V, { job: m.job, names: m.names, done: 0, players: {} });
      for (const name of m.names) {
        variantGrid.append(h("div", { class: "aw-variant", "data-variant": name }, h("div", { class: "aw-variant-title" }, name), h("div", { class: "ap" })));
      }
      return;
    }
    if (m.job !== V.job) return;
    const box = variantGrid.querySelector(`[data-variant="${CSS.escape(m.variant)}"]`);
    if (!box) return;
    if (m.type === "variant-start") {
      const p = newPlayer(box.lastChild, m.player, { keys: false, duration: m.player.duration, linkName: m.variant });
      players[m.variant] = p;
      p.onCursor((t) => { for (const [n, q] of Object.entries(players)) if (n !== m.variant) q.setCursor(t); });
      if (p.onView) p.onView((view) => { for (const [n, q] of Object.entries(players)) if (n !== m.variant) q.setView(view); });
      V.players[m.variant] = { samples: 0, finished: false };
    } else if (m.type === "variant-chunk" && players[m.variant]) {
      players[m.variant].append(m.chunk); V.players[m.variant].samples = players[m.variant].samples;
    } else if (m.type === "variant-end" && players[m.variant]) {
      players[m.variant].finish(m.final); V.players[m.variant].finished = true; V.done += 1;
    }
  }

  // ---- ensemble over seeds -----------------------------------------------------------------
  const ens = { table: h("table", { class: "aw-table" }), stats: h("div", { class: "aw-stats" }), progress: h("div", { class: "aw-bar" }, h("div", { class: "aw-bar-fill" })) };
  function buildEnsemble(list, presets) {
    const measure = h("select", { name: "ensemble-measure", "aria-label": "measure" }, list.map((m) => h("option", { value: m.name, text: m.label })));
    const seeds = h("input", { name: "ensemble-seeds", type: "number", min: "2", max: "200", value: "4", "aria-label": "seeds" });
    const maxSeeds = h("input", { name: "ensemble-max-seeds", type: "number", min: "2", max: "200", value: "40", "aria-label": "at most this many seeds" });
    const fixedBox = h("label", {}, "seeds ", seeds), autoBox = h("label", { hidden: true, title: "seeds are added in stages of 10 until every verdict is decided, as compare(seeds=\"auto\")" }, "at most ", maxSeeds, " seeds");
    const mode = h("select", { name: "ensemble-mode", "aria-label": "how many seeds" }, h("option", { value: "fixed", text: "a fixed number of seeds" }),
                   h("option", { value: "auto", text: "seeds until decided (auto)" }));
    mode.addEventListener("change", () => { fixedBox.hidden = mode.value === "auto"; autoBox.hidden = mode.value !== "auto"; });
    const preset = h("select", { name: "ensemble-preset", "aria-label": "variants" }, Object.entries(presets).map(([id, n]) => h("option", { value: id, text: n.join(" vs ") })));
    const start = h("button", { class: "aw-btn", "data-act": "ensemble-start", onclick: () => model.send(mode.value === "auto"
      ? { type: "ensemble", measure: measure.value, seeds: "auto", max_seeds: parseInt(maxSeeds.value, 10), preset: preset.value }
      : { type: "ensemble", measure: measure.value, seeds: parseInt(seeds.value, 10), preset: preset.value }) }, "Compare over seeds");
    const stop = h("button", { class: "aw-btn", onclick: () => model.send({ type: "cancel", lane: "ensemble" }) }, "Cancel");
    panes.ensemble.replaceChildren(h("p", { class: "aw-help" }, "A measure of each variant over N seeds, on every core (the ensemble engine); the table fills in per seed as results arrive, with the running ratio, its 95 % interval, the Wilcoxon p and the verdict. \"Until decided\" adds seeds in stages of 10 and stops at the first stage where every verdict is decided (holds, no effect, or the other way), as asperity2d.compare(seeds=\"auto\") does."),
      h("div", { class: "aw-row" }, measure, preset, mode, fixedBox, autoBox, start, stop), ens.progress, ens.stats, ens.table);
  }
  function seedRows(seeds) {
    const E = S.ensemble;
    for (const s of seeds) ens.table.append(h("tr", {}, h("td", {}, String(s)), E.variants.map((v) => h("td", { "data-cell": `${v}/${s}`, text: "\u2026" }))));
  }
  function undecidedText(c, E) {  // an undecided row: about how many more seeds would decide it
    if (c.verdict !== "undecided") return null;
    if (c.more === null || c.more === undefined) return "undecided: no number of seeds would decide it at this spread (the effect sits at the margin)";
    const left = E.design ? E.design.stages[E.design.stages.length - 1] - (E.stats ? E.stats.seeds_done : 0) : null;
    return `undecided: about ${c.more} more seed${c.more === 1 ? "" : "s"}` + (left !== null && c.more > left ? ` (more than the ${left} left of the budget)` : "");
  }
  function onEnsemble(m) {
    const E = S.ensemble;
    if (m.type === "ensemble-start") {
      Object.assign(E, { job: m.job, values: {}, stats: null, done: false, variants: m.variants, seeds: [], unit: m.unit, label: m.label,
                         design: m.design || null, stage: null, end: null });
      ens.table.replaceChildren(h("tr", {}, h("th", {}, "seed"), m.variants.map((v) => h("th", {}, v))));
      seedRows(m.seeds); E.seeds = m.seeds.slice();
      ens.stats.textContent = `${m.label}: running on ${m.workers} worker${m.workers > 1 ? "s" : ""}` + (m.design ? `, seeds in ${m.design.text}\u2026` : "\u2026");
      ens.progress.classList.add("aw-busy"); ens.progress.firstChild.style.width = "0%";
      return;
    }
    if (m.job !== E.job) return;
    if (m.type === "ensemble-stage") {
      E.stage = m; seedRows(m.seeds); E.seeds = E.seeds.concat(m.seeds);
    } else if (m.type === "ensemble-value") {
      (E.values[m.variant] = E.values[m.variant] || {})[m.seed] = m.value;
      const cell = ens.table.querySelector(`[data-cell="${CSS.escape(m.variant + "/" + m.seed)}"]`);
      if (cell) { cell.textContent = m.error ? "failed" : si(m.value, E.unit, 4); if (m.error) cell.title = m.error; }
      const n = Object.values(E.values).reduce((a, o) => a + Object.keys(o).length, 0);
      const total = E.design ? E.design.stages[E.design.stages.length - 1] : E.seeds.length;
      ens.progress.firstChild.style.width = `${Math.round(100 * n / (E.variants.length * total))}%`;
    } else if (m.type === "ensemble-stats") {
      E.stats = m;
      const L = m.look;
      const head = !E.design ? `${E.label} \u2014 ${m.seeds_done} of ${E.seeds.length} seeds done`
        : L.interim ? `${E.label} \u2014 ${m.seeds_done} seeds; interim: stage ${L.stage} of ${L.of} is judged after seed ${L.next}`
        : `${E.label} \u2014 ${m.seeds_done} seeds; the look after stage ${L.stage} of ${L.of} (level ${L.nominal_alpha.toPrecision(2)})`;
      ens.stats.replaceChildren(h("div", {}, head),
        ...Object.entries(m.summary).map(([v, s]) => h("div", {}, `${v}: mean ${si(s.mean, E.unit, 4)}, 95 % CI [${si(s.ci_low, E.unit, 3)}, ${si(s.ci_high, E.unit, 3)}]`)),
        ...m.versus.map((c) => { const more = undecidedText(c, E); return h("div", { class: "aw-verdict", "data-verdict": c.verdict, "data-more": more === null || c.more == null ? null : String(c.more) },
          `${c.variant} / ${c.reference}: ratio \u00d7${fix(c.ratio)}, 95 % interval ${c.ratio_ci[0] === null ? "not yet (too few seeds)" : `[${fix(c.ratio_ci[0])}, ${fix(c.ratio_ci[1])}]`}, Wilcoxon p = ${c.p_text}, ${c.n} seeds`,
          h("br"), c.line, more ? h("div", { class: "aw-more" }, more) : null); }));
    } else if (m.type === "ensemble-end") {
      E.done = true; E.end = m; ens.progress.classList.remove("aw-busy"); ens.progress.firstChild.style.width = "100%";
      if (!E.stats) ens.stats.textContent = `${E.label}: done (a ratio needs two variants and two seeds)`;
      else if (E.design) ens.stats.append(h("div", { class: "aw-ensemble-end" }, m.decided
        ? `decided after ${m.seeds_done} seeds in ${m.looks} stage${m.looks > 1 ? "s" : ""} (of up to ${m.max_seeds})`
        : `the budget of ${m.max_seeds} seeds is spent before every verdict was decided`));
    }
  }

  // ---- messages ------------------------------------------------------------------------------
  function onMessage(raw) {
    let m;
    try { m = decodeMessage(raw); } catch (e) { return; }
    S.messages.push(m.type);
    if (S.messages.length > 200) S.messages.splice(0, 100);
    switch (m.type) {
      case "schema": S.schema = m; buildControls(m); break;
      case "measures": buildMeasures(m.measures); buildCompare(m.presets); buildEnsemble(m.measures, m.presets); break;
      case "values": setValues(m.values); break;
      case "invalid": S.valid = false; showErrors(m.errors); break;
      case "valid":
        S.valid = true; S.python = m.python; note.textContent = m.python;
        if (m.values) {  // the scene now running (a change from elsewhere shows in the controls too)
          S.values = { ...m.values };
          for (const [name, input] of Object.entries(inputs)) if (input !== document.activeElement) input.value = S.values[name] || "";
        }
        if (m.bodies) S.bodies = m.bodies;
        for (const f of inspector.querySelectorAll(".aw-bad")) f.classList.remove("aw-bad");
        showErrors({}); showSelection(); markStale(); if (S.kept.length) showKept();
        break;
      case "export": {
        S.exports.push({ what: m.what, filename: m.filename, text: m.text, size: m.text ? m.text.length : m.base64.length });
        const blob = m.text !== undefined ? new Blob([m.text], { type: m.mime })
          : new Blob([Uint8Array.from(atob(m.base64), (c) => c.charCodeAt(0))], { type: m.mime });
        download(m.filename, blob);
        flash(`saved ${m.filename}`);
        break;
      }
      case "error":
        S.lastError = m;
        if (m.lane === "measure") { for (const r of Object.values(measureRows)) { if (!r.stop.hidden) r.value.textContent = m.message; r.stop.hidden = true; r.prog.hidden = true; } }
        else if (m.lane === "ensemble") { ens.stats.textContent = m.message; ens.progress.classList.remove("aw-busy"); }
        else if (m.lane === "run") { S.run.running = false; formError.textContent = m.message; }
        else formError.textContent = m.message;
        break;
      case "cancelled":
        if (m.lane === "run") S.run.running = false;
        if (m.lane === "measure") for (const [name, r] of Object.entries(measureRows)) { if (!r.stop.hidden) r.value.textContent = "cancelled"; r.stop.hidden = true; r.prog.hidden = true; if (S.measures[name]) S.measures[name].running = false; }
        if (m.lane === "ensemble") { ens.stats.textContent = "cancelled"; ens.progress.classList.remove("aw-busy"); }
        break;
      case "disconnected": S.connected = false; S.closedWith = [m.code, m.reason]; break;
      default:
        if (m.type.startsWith("run-")) onRun(m);
        else if (m.type.startsWith("measure-")) onMeasure(m);
        else if (m.type.startsWith("variant")) onVariants(m);
        else if (m.type.startsWith("ensemble-")) onEnsemble(m);
    }
    setStatus();
  }
  model.on("msg:custom", onMessage);
  model.send({ type: "hello" });

  const handle = {
    state: () => S,
    player: () => player,
    players: () => players,
    set: (name, text) => { if (inputs[name]) inputs[name].value = text; change(name, text); },
    send: (obj) => model.send(obj),
  };
  el.asperityWorkbench = handle;
  if (!window.asperityWorkbench) window.asperityWorkbench = handle;
  return () => {  // anywidget's clean-up: the view is gone
    if (player) player.destroy();
    for (const p of Object.values(players)) p.destroy();
    if (window.asperityWorkbench === handle) window.asperityWorkbench = null;
  };
}

export default { render };
