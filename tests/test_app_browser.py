"""The workbench in a real browser: ``asperity2d explore --no-browser`` as a subprocess, headless
Chromium driven by Selenium with Debian's chromedriver, as a person would use it.

Changes a parameter in its control and sees the new run stream in (samples and the drawn frame
advance while the run is still computing), types a refused value and reads its inline error,
asks for a critical force, runs a 4-seed comparison, puts two variants side by side with one
time cursor, exports a meter as CSV and checks its numbers against the result's arrays, and
fails on any console error. The notebook widget's module (the player and the workbench as one
ES module, exactly what ``asperity2d.explore()`` ships) is rendered too, with a stand-in for
anywidget's model. Screenshots go to ``$ASPERITY2D_SHOTS`` when set. Skipped, saying what to
install, without the browser (the player's browser test's rule). Cost: ~40 s here.
"""

from __future__ import annotations

import csv
import io
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from test_player_browser import INSTALL, _missing, chromium

pytestmark = pytest.mark.skipif(_missing() is not None, reason=f"{_missing()}: {INSTALL}")
pytest.importorskip("starlette", reason='needs the app extra: pip install -e ".[test]"')

import asperity2d as a  # noqa: E402

SHOTS = os.environ.get("ASPERITY2D_SHOTS")
#: The scene the test switches to: a run of ~2,000 samples, a critical force of ~2 s.
CHANGE = {"lower_count": "6", "upper_count": "2"}


@pytest.fixture(scope="module")
def server():
    proc = subprocess.Popen([sys.executable, "-m", "asperity2d", "explore", "--no-browser", "--workers", "2"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    url = proc.stdout.readline().strip()
    assert re.fullmatch(r"http://127\.0\.0\.1:\d+/\?token=\S+", url), url
    yield url
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=20)
    assert "Traceback" not in err, err  # nothing the test did left a traceback in the server's log


@pytest.fixture(scope="module")
def browser():
    with chromium(window="1280,800") as driver:
        yield driver


def console_errors(browser) -> list:
    return [e for e in browser.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]


def state(browser, expr="s"):
    return browser.execute_script(f"const s = window.asperityWorkbench.state(); return {expr};")


def wait_for(browser, expr, timeout=180.0, every=0.05):
    # the workbench may not exist yet (a module still importing): not yet, rather than an error
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        value = browser.execute_script(
            f"const w = window.asperityWorkbench; if (!w) return null; const s = w.state(); return {expr};")
        if value:
            return value
        time.sleep(every)
    raise AssertionError(f"timed out waiting for {expr}; messages {state(browser, 's.messages.slice(-12)')}")


def shot(browser, name):
    if SHOTS:
        Path(SHOTS).mkdir(parents=True, exist_ok=True)
        browser.save_screenshot(str(Path(SHOTS) / name))


def type_into(browser, name, text):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    box = browser.find_element(By.CSS_SELECTOR, f'.aw-side [name="{name}"]')
    box.clear()
    box.send_keys(text + Keys.ENTER)


def click(browser, selector):
    from selenium.webdriver.common.by import By

    browser.find_element(By.CSS_SELECTOR, selector).click()


def test_the_workbench_as_a_person_uses_it(server, browser):
    from selenium.webdriver.common.by import By

    browser.get(server)
    wait_for(browser, "s.schema && s.run.job !== null")
    # every make_scene parameter has its control, with its unit
    names = state(browser, "s.schema.groups.flatMap(g => g.controls.map(c => c.name))")
    from asperity2d.builders import KEYWORDS, PARAMETERS

    assert names == [p.name for p in KEYWORDS + PARAMETERS]
    assert browser.execute_script('return document.querySelector(\'[name="mass"]\').closest("label")'
                                  '.querySelector(".aw-unit").textContent') == "kg"

    # change a parameter: the new run streams in while it is computed
    type_into(browser, "lower_count", CHANGE["lower_count"])
    type_into(browser, "upper_count", CHANGE["upper_count"])
    job = wait_for(browser, "s.run.finished && s.values.lower_count === '6' && s.values.upper_count === '2' && s.run.job")
    # the page's own log of the run's chunks as they came in, before its end (polling from here
    # could miss a run that streams faster than a round trip to the browser)
    log = state(browser, "s.run.chunkLog")
    assert len({c["samples"] for c in log}) >= 2, log  # more samples arrived while it still ran ...
    assert len({c["index"] for c in log}) >= 2, log  # ... and the drawn frame followed them
    first_ms = state(browser, "s.run.firstChunkMs")
    assert first_ms is not None and first_ms < 5000  # the target (1 s) is measured in benchmarks/
    wait_for(browser, "s.run.finished")
    shot(browser, "app_run.png")
    samples = state(browser, "s.run.samples")

    # the meter's CSV gives the result's numbers (the same run, simulated here)
    result = a.simulate(a.make_scene(lower_count=6, upper_count=2))
    assert samples == len(result.t)
    text = browser.execute_script("return window.asperityWorkbench.player().api.exportMeter(0, 'csv')")
    rows = list(csv.reader(io.StringIO(text)))
    header, body = rows[0], [r for r in rows[1:] if r]
    assert "s" in header[0] and "drive" in header[1].lower()
    table = np.array([[float(v) for v in r[:2]] for r in body])
    assert np.array_equal(table[:, 0], result.t) and np.array_equal(table[:, 1], result.drive_force)

    # a refused value: its one line beside the control, nothing runs, the run on screen stays
    type_into(browser, "mass", "-1")
    wait_for(browser, "!s.valid")
    error = browser.execute_script('return document.querySelector(\'[data-error="mass"]\').textContent')
    assert error == "`mass` must be > 0, got -1"
    assert state(browser, "s.run.samples") == samples and not state(browser, "s.run.running")
    shot(browser, "app_refused.png")
    type_into(browser, "mass", "")
    wait_for(browser, "s.valid && s.run.finished && s.run.job > %d" % job)

    # a critical force on a click, with its unit
    click(browser, '[data-tab="measure"]')
    click(browser, 'button[data-measure="critical"]')
    value = wait_for(browser, "s.measures.critical && s.measures.critical.value", timeout=240)
    from asperity2d.critical import critical_force

    assert value == critical_force(a.make_scene(lower_count=6, upper_count=2, drive="force"))
    shown = browser.execute_script('return document.querySelector(\'.aw-value[data-measure="critical"]\').textContent')
    assert shown.endswith(" mN"), shown
    shot(browser, "app_measure.png")

    # a comparison over seeds "until decided", at most 4: filled in per seed, with the ratio, its
    # interval, p and the verdict from the second seed, and what the budget came to
    click(browser, '[data-tab="ensemble"]')
    browser.execute_script("""
        document.querySelector('[name="ensemble-measure"]').value = 'first-breakaway';
        const mode = document.querySelector('[name="ensemble-mode"]'); mode.value = 'auto'; mode.dispatchEvent(new Event('change'));
        document.querySelector('[name="ensemble-max-seeds"]').value = '4';
        document.querySelector('[name="ensemble-preset"]').value = 'spacing';""")
    assert browser.find_element(By.CSS_SELECTOR, '[name="ensemble-max-seeds"]').is_displayed()
    assert not browser.find_element(By.CSS_SELECTOR, '[name="ensemble-seeds"]').is_displayed()
    click(browser, '[data-act="ensemble-start"]')
    wait_for(browser, "s.ensemble.done", timeout=240)
    ens = state(browser, "s.ensemble")
    assert sorted(ens["values"]) == ["random", "regular"] and all(len(v) == 4 for v in ens["values"].values())
    assert ens["design"]["stages"] == [4] and ens["end"]["seeds_done"] == 4
    (versus,) = ens["stats"]["versus"]
    assert ens["stats"]["seeds_done"] == 4 and versus["verdict"] and versus["line"].startswith("random lowers")
    page = browser.execute_script("return document.querySelector('.aw-stats').textContent")
    assert "Wilcoxon p" in page and "ratio" in page and versus["verdict"] in page
    assert ("decided after 4 seeds" if ens["end"]["decided"] else "the budget of 4 seeds is spent") in page
    shot(browser, "app_ensemble.png")

    # two variants side by side, one time cursor
    click(browser, '[data-tab="compare"]')
    click(browser, 'button[data-preset="profile"]')
    wait_for(browser, "s.variants.done === 2", timeout=240)
    t_full = browser.execute_script("""
        const ps = window.asperityWorkbench.players();
        const t = ps.full.api.seek(ps.full.api.t1 * 0.5); return [t, ps.half.api.state().t];""")
    assert t_full[1] == pytest.approx(t_full[0], rel=0.02)
    # and one time window: a box zoom on one variant's meter zooms the other's
    view = browser.execute_script("""
        const ps = window.asperityWorkbench.players();
        ps.full.api.zoomMeter(0, ps.full.api.t1 * 0.2, ps.full.api.t1 * 0.4, null, null);
        return [ps.full.api.state().view, ps.half.api.state().view];""")
    assert view[1] == pytest.approx(view[0])
    shot(browser, "app_compare.png")

    assert console_errors(browser) == []


def test_the_widget_module_renders_in_chromium(server, browser, tmp_path):
    """The notebook widget's own ES module and CSS (``explore()._esm``), given a stand-in for
    anywidget's model that carries the protocol over the app's WebSocket."""
    widget = a.explore(**{k: int(v) for k, v in CHANGE.items()})
    port_token = re.search(r"127\.0\.0\.1:(\d+)/\?token=(\S+)", server)
    browser.get(server)  # the page's origin: the stand-in's WebSocket is same-origin
    wait_for(browser, "s.schema")
    browser.execute_script("""
        document.body.innerHTML = '<style>' + arguments[1] + '</style><div id="w" style="width:1000px"></div>';
        window.asperityWorkbench = null;
        const url = URL.createObjectURL(new Blob([arguments[0]], {type: 'text/javascript'}));
        import(url).then((mod) => {
          const ws = new WebSocket(arguments[2]); const cbs = []; const q = [];
          ws.onopen = () => { while (q.length) ws.send(q.shift()); };
          ws.onmessage = (m) => cbs.forEach((cb) => cb({m: m.data}));
          const model = { send: (o) => (ws.readyState === 1 ? ws.send(JSON.stringify(o)) : q.push(JSON.stringify(o))),
                          on: (ev, cb) => { if (ev === 'msg:custom') cbs.push(cb); }, get: () => null };
          window.widgetCleanup = mod.default.render({ model, el: document.getElementById('w') });
        });""", widget._esm, widget._css, f"ws://127.0.0.1:{port_token.group(1)}/ws?token={port_token.group(2)}")
    wait_for(browser, "s.schema && s.run.job !== null")
    browser.execute_script("window.asperityWorkbench.send({type: 'set', values: arguments[0]})", CHANGE)
    wait_for(browser, "s.run.finished && s.run.samples > 1000", timeout=180)
    assert browser.execute_script("return typeof window.widgetCleanup") == "function"
    from asperity2d.builders import KEYWORDS, PARAMETERS

    controls = browser.execute_script("return document.querySelectorAll('#w .aw-control').length")
    from asperity2d.app.controls import RUN_CONTROLS

    assert controls == len(KEYWORDS + PARAMETERS) + len(RUN_CONTROLS)  # every parameter, and the run's settings
    shot(browser, "widget.png")
    assert console_errors(browser) == []
    widget.close()


# -- the stage as Working Model's users touched it -------------------------------------------------
def wait_run_after(browser, job, timeout=240):
    """The number of the first finished run after ``job``."""
    return wait_for(browser, f"s.run.job > {job} && s.run.finished && s.valid && s.run.job", timeout=timeout)


def stage_point(browser, j):
    """``(canvas, dx, dy, px_per_m)``: lower asperity ``j``'s body on the stage, as offsets from the
    canvas's centre (where Selenium's pointer offsets start), and the stage's scale."""
    from selenium.webdriver.common.by import By

    boxes, scale, zoom = browser.execute_script(
        "const p = window.asperityWorkbench.player().api.state(); return [p.drawn.lower_box, p.camera.scale, p.camera.zoom]")
    canvas = browser.find_element(By.CSS_SELECTOR, ".aw-player .ap-scene")
    w, h = browser.execute_script("const r = arguments[0].getBoundingClientRect(); return [r.width, r.height]", canvas)
    box = boxes[j]
    x, y = 0.5 * (box[0] + box[2]), 0.3 * box[1] + 0.7 * box[3]  # inside the triangle, below its apex
    return canvas, int(round(x - w / 2)), int(round(y - h / 2)), scale * zoom


def kept_pixels(browser, meter=0, colour=(0x17, 0xBE, 0xCF)):
    """How many pixels of the run pane's meter ``meter`` are drawn in the first kept run's colour."""
    return browser.execute_script("""
        const c = document.querySelectorAll('.aw-player .ap-meters canvas')[arguments[0]];
        const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data, [r, g, b] = arguments[1];
        let n = 0; for (let i = 0; i < d.length; i += 4) if (Math.abs(d[i] - r) < 20 && Math.abs(d[i + 1] - g) < 20 && Math.abs(d[i + 2] - b) < 20) n++;
        return n;""", meter, list(colour))


def test_click_edit_drag_keep_compare_stop_and_save_reproduces(server, browser, tmp_path):
    """The issue's "done when", as a person does it: click a lower asperity, change its stiffness,
    drag it half a pitch, keep the run, change the drive, see both runs on one meter, stop at the
    first slip, save a TOML that ``asperity2d run`` reproduces to the bit."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys
    from selenium.webdriver.support.ui import Select

    browser.get(server)
    wait_for(browser, "s.schema && s.run.job !== null")
    type_into(browser, "lower_count", "6")
    type_into(browser, "upper_count", "2")
    job = wait_run_after(browser, 2)

    # click the first lower asperity: it is selected and its own panel shows its values
    canvas, dx, dy, _ = stage_point(browser, 0)
    ActionChains(browser).move_to_element_with_offset(canvas, dx, dy).click().perform()
    wait_for(browser, "s.selected && s.selected.kind === 'lower' && s.selected.index === 0")
    panel = browser.find_element(By.CSS_SELECTOR, ".aw-inspector")
    for field in ("position", "height", "stiffness", "damping", "mass"):
        assert panel.find_element(By.CSS_SELECTOR, f'[data-field="{field}"]')
    stiffness = panel.find_element(By.CSS_SELECTOR, '[data-field="stiffness"]')
    assert float(stiffness.get_attribute("value")) == 37200.0

    # change its stiffness there: the scene's per-asperity list, and a new run
    stiffness.clear()
    stiffness.send_keys("50000" + Keys.ENTER)
    job = wait_run_after(browser, job)
    assert state(browser, "s.bodies.lower.stiffness") == [50000, 37200, 37200, 37200, 37200, 37200]
    assert state(browser, "s.values.stiffness") == "[50000.0, 37200.0, 37200.0, 37200.0, 37200.0, 37200.0]"

    # drag it half a pitch (leftwards: a neighbour half a pitch away would overlap its base)
    canvas, dx, dy, px_per_m = stage_point(browser, 0)
    pitch = 1.25e-6
    shift = int(round(0.5 * pitch * px_per_m))
    ActionChains(browser).move_to_element_with_offset(canvas, dx, dy).click_and_hold() \
        .move_by_offset(-shift // 2, 0).move_by_offset(-(shift - shift // 2), 0).release().perform()
    job = wait_run_after(browser, job)
    x = state(browser, "s.bodies.lower.x")
    assert x[1:] == pytest.approx([1.25e-6, 2.5e-6, 3.75e-6, 5e-6, 6.25e-6], abs=1e-18)
    assert x[0] == pytest.approx(-0.5 * pitch, abs=1.0 / px_per_m)  # half a pitch, to a pixel
    assert "lower_positions" in state(browser, "s.values")
    shot(browser, "app_edited.png")

    # keep the run, change the drive: both runs on one meter, in two colours
    samples_kept = state(browser, "s.run.samples")
    click(browser, '[data-act="keep"]')
    type_into(browser, "drive_velocity", "10")
    job = wait_run_after(browser, job)
    overlays = browser.execute_script("return window.asperityWorkbench.player().api.overlays()")
    assert overlays == [{"label": "kept 1", "colour": "#17becf", "samples": samples_kept}]
    browser.execute_script("const p = window.asperityWorkbench.player(); p.api.seek(p.api.t1)")  # nothing faded
    time.sleep(0.3)  # a frame
    with_kept = kept_pixels(browser)
    browser.execute_script("window.asperityWorkbench.player().setOverlays([])")
    time.sleep(0.3)
    without = kept_pixels(browser)
    browser.execute_script("window.asperityWorkbench.player().setOverlays(window.asperityWorkbench.state().kept)")
    assert with_kept - without > 50, (with_kept, without)  # the kept run's trace, drawn on the drive-force meter
    # every meter's axis holds the kept run's axis as its own meter had it, and this run's own
    axes = browser.execute_script("""
        const w = window.asperityWorkbench, p = w.player(), kept = w.state().kept[0].limits, own = p.snapshot().limits;
        return p.api.meters().map((m) => [m.channel, m.limits, kept[m.channel], own[m.channel]]);""")
    for channel, lim, kept_axis, own_axis in axes:
        for axis in (kept_axis, own_axis):
            assert lim[0] <= axis[0] and lim[1] >= axis[1], (channel, lim, kept_axis, own_axis)
    legend = browser.find_element(By.CSS_SELECTOR, ".aw-kept").text
    assert "kept 1" in legend and "drive_velocity default (now 10)" in legend
    rows = list(csv.reader(io.StringIO(browser.execute_script(
        "return window.asperityWorkbench.player().api.exportMeter(0, 'csv-all')"))))
    runs = [r[0] for r in rows[1:] if r]
    assert runs.count("kept 1") == samples_kept and runs.count("this run") == state(browser, "s.run.samples")
    browser.execute_script("document.querySelector('.aw-player .ap-meters').scrollIntoView()")
    shot(browser, "app_kept.png")
    # the difference channel: this run minus the kept one
    browser.find_element(By.CSS_SELECTOR, '.aw-kept [data-diff="0"]').click()
    meters = browser.execute_script("return window.asperityWorkbench.player().api.meters()")
    assert "\u2212 kept 1" in meters[0]["labels"][0] or browser.execute_script(
        "return window.asperityWorkbench.player().api.difference()") == 0
    shot(browser, "app_difference.png")
    browser.find_element(By.CSS_SELECTOR, '.aw-kept input[name="aw-diff"]').click()  # back to the runs

    # stop at the first slip
    Select(browser.find_element(By.CSS_SELECTOR, '.aw-side [name="stop_first_slip"]')).select_by_value("true")
    job = wait_run_after(browser, job)
    assert state(browser, "s.run.summary.status") == "first slip"
    samples = state(browser, "s.run.samples")

    # save the TOML: `asperity2d run` reproduces this run to the bit
    click(browser, '[data-act="save-toml"]')
    text = wait_for(browser, "s.exports.length && s.exports[s.exports.length - 1].text")
    path = tmp_path / "edited.toml"
    path.write_text(text)
    out = tmp_path / "cli.npz"
    done = subprocess.run([sys.executable, "-m", "asperity2d", "run", str(path), "--save", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    cli = a.load(out)
    assert cli.status == "first slip" and len(cli.t) == samples
    assert cli.scene.lower.stiffness[0] == 50000.0 and cli.scene.drive.velocity == 10.0
    page = list(csv.reader(io.StringIO(browser.execute_script(
        "return window.asperityWorkbench.player().api.exportMeter(0, 'csv')"))))
    table = np.array([[float(v) for v in r[:2]] for r in page[1:] if r])
    assert np.array_equal(table[:, 0], cli.t) and np.array_equal(table[:, 1], cli.drive_force)
    assert console_errors(browser) == []


def retype(browser, name, text):
    """Select the control's text and type over it, as a person does (Selenium's clear() would send
    a change of its own: an empty value, a run of the default)."""
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    box = browser.find_element(By.CSS_SELECTOR, f'.aw-side [name="{name}"]')
    box.send_keys(Keys.CONTROL, "a")
    box.send_keys((text or Keys.BACKSPACE) + Keys.ENTER)


def test_refusals_mark_the_control_typed_in_and_keep_the_last_run(server, browser):
    """Each bad value: one line on the control typed in, nothing started, the last run's arrays
    still drawn, Stop disabled and Save .npz enabled."""
    browser.get(server)
    wait_for(browser, "s.schema && s.run.job !== null")
    type_into(browser, "lower_count", "6")
    type_into(browser, "upper_count", "2")
    job = wait_run_after(browser, 2)
    samples = state(browser, "s.run.samples")
    messages = {}
    for name, text in [("duration", "1e308"), ("upper_count", "100000"), ("mass", "1e308"),
                       ("lower_surface", "/etc/passwd"), ("mass", "nan"), ("mass", "NaN"), ("stop_force", "inf")]:
        browser.execute_script("window.asperityWorkbench.state().messages.length = 0")
        if name == "lower_surface":
            browser.execute_script("document.querySelector('.aw-side details:not([open])') && "
                                   "document.querySelectorAll('.aw-side details').forEach(d => d.open = true)")
        retype(browser, name, text)
        wait_for(browser, "!s.valid")
        marked = browser.execute_script("return [...document.querySelectorAll('.aw-side .aw-bad')].map(e => e.name)")
        assert marked == [name], (name, text, marked, state(browser, "s.errors"))
        messages[(name, text)] = state(browser, "s.errors")[name]
        time.sleep(0.3)  # a run that wrongly started would have sent run-start by now
        assert "run-start" not in state(browser, "s.messages"), (name, text)
        assert state(browser, "s.run.job") == job and state(browser, "s.run.samples") == samples
        assert browser.execute_script("return window.asperityWorkbench.player().samples") == samples
        assert browser.execute_script("return document.querySelector('[data-act=\"stop\"]').disabled")
        assert not browser.execute_script("return document.querySelector('[data-act=\"save-npz\"]').disabled")
        retype(browser, name, "")
        job = wait_run_after(browser, job)
        samples = state(browser, "s.run.samples")
    assert messages[("mass", "nan")] == messages[("mass", "NaN")]  # one reading, one message
    assert "`duration`" in messages[("duration", "1e308")]


def test_a_measured_force_is_marked_stale_when_the_scene_changes(server, browser):
    browser.get(server)
    wait_for(browser, "s.schema && s.run.job !== null")
    type_into(browser, "lower_count", "6")
    type_into(browser, "upper_count", "2")
    job = wait_run_after(browser, 2)
    click(browser, '[data-tab="measure"]')
    click(browser, 'button[data-measure="critical"]')
    wait_for(browser, "s.measures.critical && s.measures.critical.value", timeout=240)
    cell = 'return document.querySelector(\'.aw-value[data-measure="critical"]\')'
    assert "earlier scene" not in browser.execute_script(cell + ".textContent")
    shot(browser, "app_measure.png")
    browser.execute_script("window.asperityWorkbench.set('mu_static', '0.4')")
    wait_for(browser, "s.measures.critical.stale")
    assert "earlier scene" in browser.execute_script(cell + ".textContent")
    browser.execute_script("window.asperityWorkbench.set('mu_static', '')")  # the scene it was measured on
    wait_for(browser, "!s.measures.critical.stale")
    assert "earlier scene" not in browser.execute_script(cell + ".textContent")


@pytest.mark.parametrize("width", [375, 1000, 1280])
def test_the_page_at_a_phone_a_small_laptop_and_a_desktop_width(server, browser, width):
    """375 px: the controls are a drawer and the run has the width; 1000 px: the header is one
    row and Compare's two players are stacked, both on screen; 1280 px: the sidebar beside the run.
    At every width a meter's read-out is in its axis' unit."""
    browser.set_window_size(width, 900)
    try:
        browser.get(server)
        wait_for(browser, "s.schema && s.run.job !== null")
        browser.execute_script("window.asperityWorkbench.send({type: 'set', values: {lower_count: '6', upper_count: '2'}})")
        wait_for(browser, "s.run.finished && s.bodies && s.bodies.lower.x.length === 6", timeout=240)
        inner = browser.execute_script("return window.innerWidth")
        rect = lambda sel: browser.execute_script(  # noqa: E731
            f"const r = document.querySelector('{sel}').getBoundingClientRect(); return [r.left, r.top, r.width, r.height]")
        side_shown = browser.execute_script("return getComputedStyle(document.querySelector('.aw-side-wrap')).display") != "none"
        header = rect(".aw-header")
        player = rect(".aw-player")
        if width == 375:
            assert not side_shown and player[2] >= 0.9 * inner  # the run has the page's width
            click(browser, '[data-act="drawer"]')
            assert browser.execute_script("return getComputedStyle(document.querySelector('.aw-side-wrap')).display") != "none"
            assert rect(".aw-side-wrap")[2] <= inner
            shot(browser, f"app_{width}_drawer.png")
            click(browser, '[data-act="drawer"]')
        else:
            assert side_shown and player[2] >= 0.6 * inner
            assert header[3] < 40, header  # one row
        # a meter's read-out is in its axis' unit
        for m in browser.execute_script("return window.asperityWorkbench.player().api.meters()"):
            for text in m["readouts"]:
                assert text.endswith(" " + m["axis_unit"]) or text.startswith("\u2013"), (m["title"], text, m["axis_unit"])
        shot(browser, f"app_{width}.png")
        if width == 1000:
            click(browser, '[data-tab="compare"]')
            click(browser, 'button[data-preset="profile"]')
            wait_for(browser, "s.variants.done === 2", timeout=240)
            boxes = browser.execute_script(
                "return [...document.querySelectorAll('.aw-variant')].map(e => { const r = e.getBoundingClientRect(); "
                "return [r.left, r.top, r.right, r.bottom]; })")
            assert len(boxes) == 2 and boxes[1][1] >= boxes[0][3] - 1  # stacked
            assert all(b[2] <= inner + 1 for b in boxes)  # both within the page's width
            shot(browser, "app_1000_compare.png")
    finally:
        browser.set_window_size(1280, 800)


@pytest.mark.slow
def test_dragging_the_slider_sets_its_start(server, browser):
    """Drag the slider a micrometre to the left: ``slider_start`` is where its rear tip now starts,
    the new run begins there, and the slider's panel shows it."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.by import By

    browser.get(server)
    wait_for(browser, "s.schema && s.run.job !== null")
    type_into(browser, "lower_count", "6")
    type_into(browser, "upper_count", "2")
    job = wait_run_after(browser, 2)
    x0 = browser.execute_script("return window.asperityWorkbench.player().snapshot().S.x[0]")
    canvas = browser.find_element(By.CSS_SELECTOR, ".aw-player .ap-scene")
    read = """const p = window.asperityWorkbench.player().api.state(), r = arguments[0].getBoundingClientRect();
              return [p.drawn.slider_box, p.camera.scale, p.camera.zoom, r.width, r.height];"""
    seen = [None, browser.execute_script(read, canvas)]
    while seen[-1] != seen[-2]:  # the page's layout settled (a scrollbar that comes narrows the stage and its scale)
        time.sleep(0.3)
        seen.append(browser.execute_script(read, canvas))
    box, scale, zoom, w, h = seen[-1]
    dx, dy = int(round(0.5 * (box[0] + box[2]) - w / 2)), int(round(0.5 * (box[1] + box[3]) - h / 2))
    shift = int(round(1e-6 * scale * zoom))
    ActionChains(browser).move_to_element_with_offset(canvas, dx, dy).click_and_hold() \
        .move_by_offset(-shift // 2, 0).move_by_offset(-(shift - shift // 2), 0).release().perform()
    wait_run_after(browser, job)
    start = float(state(browser, "s.values.slider_start"))
    # a micrometre, to two pixels: the shift asked for is whole pixels (0.5 px) and Selenium places
    # the pointer at whole pixels from the element's fractional centre (up to 1 px more, seen: 72 for 71)
    assert start == pytest.approx(x0 - 1e-6, abs=2.0 / (scale * zoom))
    assert state(browser, "s.bodies.slider.start") == start
    assert browser.execute_script("return window.asperityWorkbench.player().snapshot().S.x[0]") == start
    assert state(browser, "s.selected.kind") == "slider"
    shown = browser.find_element(By.CSS_SELECTOR, '.aw-inspector [data-field="start"]').get_attribute("value")
    assert float(shown) == start
    assert console_errors(browser) == []
