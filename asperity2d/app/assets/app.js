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
    ws.onclose = () => { open = false; status.connected = false; status.closed = true;
                         for (const cb of listeners) cb(JSON.stringify({ type: "disconnected" })); };
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
  };
  let player = null, follow = true;
  const players = {};  // compare players by variant name

  // ---- layout ------------------------------------------------------------------------------
  el.classList.add("aw");
  const status = h("span", { class: "aw-status", text: "connecting\u2026" });
  const bar = h("div", { class: "aw-bar" }, h("div", { class: "aw-bar-fill" }));
  const cancelRun = h("button", { class: "aw-btn", title: "stop the run being computed", onclick: () => model.send({ type: "cancel", lane: "run" }) }, "Stop");
  const saveToml = h("button", { class: "aw-btn", title: "the scene as a TOML file: `asperity2d run scene.toml` reproduces this run", onclick: () => model.send({ type: "export", what: "toml" }) }, "Save TOML");
  const copyPy = h("button", { class: "aw-btn", title: "copy the make_scene(...) call", onclick: () => copyPython() }, "Copy as Python");
  const saveNpz = h("button", { class: "aw-btn", title: "the finished run as a .npz result (asperity2d.load)", onclick: () => model.send({ type: "export", what: "npz" }) }, "Save run .npz");
  const header = h("div", { class: "aw-header" }, h("span", { class: "aw-brand" }, "asperity2d workbench"),
                   status, bar, cancelRun, h("span", { class: "aw-sep" }), saveToml, copyPy, saveNpz);
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
  panes.run.append(playerHost, h("details", { class: "aw-py" }, h("summary", {}, "make_scene call"), note));
  el.append(header, h("div", { class: "aw-body" }, h("div", { class: "aw-side-wrap" }, formError, sidebar), main));
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
    model.send({ type: "set", values: S.values });
  }
  function setValues(values) {
    S.values = { ...values };
    for (const [name, input] of Object.entries(inputs)) input.value = S.values[name] || "";
  }
  function showErrors(errors) {
    S.errors = errors || {};
    for (const [name, e] of Object.entries(errorEls)) { e.textContent = S.errors[name] || ""; inputs[name].classList.toggle("aw-bad", !!S.errors[name]); }
    formError.textContent = S.errors[""] || "";
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
    bar.classList.toggle("aw-busy", r.running);
    const duration = player && r.duration ? Math.min(1, r.t / r.duration) : (r.finished ? 1 : 0);
    bar.firstChild.style.width = `${Math.round(100 * (r.finished ? 1 : duration))}%`;
    cancelRun.disabled = !r.running;
    saveNpz.disabled = !r.finished;
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
      player = newPlayer(host, m.player, { keys: true, duration: m.player.duration });
      follow = true;
      player.onCursor(() => { follow = false; });
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
      r.chunkLog.push({ at: performance.now(), samples: r.samples, index: player.api.state().index });
      if (follow) player.setCursor(m.t);  // the scene shows the newest computed state
    } else if (m.type === "run-end") {
      player.finish(m.final);
      Object.assign(S.run, { running: false, finished: true, summary: m.summary, samples: player.samples,
                              endMs: performance.now() - (S.changedAt || S.run.started) });
      if (follow) player.setCursor(player.api.t0);
    }
    setStatus();
  }

  // ---- measures ----------------------------------------------------------------------------
  const measureRows = {};
  function buildMeasures(list) {
    S.measureList = list;
    panes.measure.replaceChildren(h("p", { class: "aw-help" }, "Each measure runs on the scene as the controls set it, under the drive it needs, in its own process; Cancel stops it at once."));
    const table = h("table", { class: "aw-table aw-measures" }, h("tr", {}, h("th", {}, "measure"), h("th", {}, "drive"), h("th", {}, "value"), h("th", {}, "")));
    for (const m of list) {
      const value = h("td", { class: "aw-value", "data-measure": m.name, text: "\u2013" });
      const go = h("button", { class: "aw-btn", "data-measure": m.name, onclick: () => model.send({ type: "measure", name: m.name }) }, "Measure");
      const stop = h("button", { class: "aw-btn", hidden: true, onclick: () => model.send({ type: "cancel", lane: "measure" }) }, "Cancel");
      const prog = h("div", { class: "aw-bar aw-small", hidden: true }, h("div", { class: "aw-bar-fill" }));
      measureRows[m.name] = { value, go, stop, prog };
      table.append(h("tr", {}, h("td", { title: `${m.kind}; ${m.name}` }, m.label), h("td", {}, m.drive === "force" ? "constant force" : "spring"),
                     h("td", {}, value, prog), h("td", {}, go, stop)));
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
      S.measures[m.name] = { running: false, value: m.value, unit: m.unit, label: m.label };
      row.value.textContent = si(m.value, m.unit, 4);
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
    const preset = h("select", { name: "ensemble-preset", "aria-label": "variants" }, Object.entries(presets).map(([id, n]) => h("option", { value: id, text: n.join(" vs ") })));
    const start = h("button", { class: "aw-btn", "data-act": "ensemble-start", onclick: () => model.send({ type: "ensemble", measure: measure.value, seeds: parseInt(seeds.value, 10), preset: preset.value }) }, "Compare over seeds");
    const stop = h("button", { class: "aw-btn", onclick: () => model.send({ type: "cancel", lane: "ensemble" }) }, "Cancel");
    panes.ensemble.replaceChildren(h("p", { class: "aw-help" }, "A measure of each variant over N seeds, on every core (the ensemble engine); the table fills in per seed as results arrive, with the running ratio, its 95 % interval, the Wilcoxon p and the verdict."),
      h("div", { class: "aw-row" }, measure, preset, h("label", {}, "seeds ", seeds), start, stop), ens.progress, ens.stats, ens.table);
  }
  function onEnsemble(m) {
    const E = S.ensemble;
    if (m.type === "ensemble-start") {
      Object.assign(E, { job: m.job, values: {}, stats: null, done: false, variants: m.variants, seeds: m.seeds, unit: m.unit, label: m.label });
      ens.table.replaceChildren(h("tr", {}, h("th", {}, "seed"), m.variants.map((v) => h("th", {}, v))));
      for (const s of m.seeds) ens.table.append(h("tr", {}, h("td", {}, String(s)), m.variants.map((v) => h("td", { "data-cell": `${v}/${s}`, text: "\u2026" }))));
      ens.stats.textContent = `${m.label}: running on ${m.workers} worker${m.workers > 1 ? "s" : ""}\u2026`;
      ens.progress.classList.add("aw-busy"); ens.progress.firstChild.style.width = "0%";
      return;
    }
    if (m.job !== E.job) return;
    if (m.type === "ensemble-value") {
      (E.values[m.variant] = E.values[m.variant] || {})[m.seed] = m.value;
      const cell = ens.table.querySelector(`[data-cell="${CSS.escape(m.variant + "/" + m.seed)}"]`);
      if (cell) { cell.textContent = m.error ? "failed" : si(m.value, E.unit, 4); if (m.error) cell.title = m.error; }
      const n = Object.values(E.values).reduce((a, o) => a + Object.keys(o).length, 0);
      ens.progress.firstChild.style.width = `${Math.round(100 * n / (E.variants.length * E.seeds.length))}%`;
    } else if (m.type === "ensemble-stats") {
      E.stats = m;
      ens.stats.replaceChildren(h("div", {}, `${E.label} \u2014 ${m.seeds_done} of ${E.seeds.length} seeds done`),
        ...Object.entries(m.summary).map(([v, s]) => h("div", {}, `${v}: mean ${si(s.mean, E.unit, 4)}, 95 % CI [${si(s.ci_low, E.unit, 3)}, ${si(s.ci_high, E.unit, 3)}]`)),
        ...m.versus.map((c) => h("div", { class: "aw-verdict", "data-verdict": c.verdict },
          `${c.variant} / ${c.reference}: ratio \u00d7${fix(c.ratio)}, 95 % interval ${c.ratio_ci[0] === null ? "not yet (too few seeds)" : `[${fix(c.ratio_ci[0])}, ${fix(c.ratio_ci[1])}]`}, Wilcoxon p = ${c.p_wilcoxon === null ? "\u2013" : c.p_wilcoxon.toPrecision(2)}, ${c.n} seeds`,
          h("br"), c.line)));
    } else if (m.type === "ensemble-end") {
      E.done = true; ens.progress.classList.remove("aw-busy"); ens.progress.firstChild.style.width = "100%";
      if (!E.stats) ens.stats.textContent = `${E.label}: done (a ratio needs two variants and two seeds)`;
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
      case "valid": S.valid = true; S.python = m.python; note.textContent = m.python; showErrors({}); break;
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
      case "disconnected": S.connected = false; break;
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
