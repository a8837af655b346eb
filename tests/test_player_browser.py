"""The HTML player in a real browser: headless Chromium driven by Selenium with Debian's chromedriver.

Opens the player from ``file://`` (no network), fails on any console error, scrubs to given
times and checks that the drawn bodies sit where the result's arrays put them -- through the
state the player exposes (``window.asperityPlayer.state()``) and by reading the canvas's
pixels -- and that playing advances the time. Skipped, saying what to install, on a machine
without the browser: ``apt-get install chromium chromium-driver`` (Debian) and
``pip install selenium`` (in the ``test`` extra).
"""

import os
import shutil
import tempfile

import numpy as np
import pytest

import asperity2d as a
from asperity2d.belt import simulate_chain
from asperity2d.belt.presets import preset
from asperity2d.renderers import raster, render

CHROMIUM = os.environ.get("ASPERITY2D_CHROMIUM", "/usr/bin/chromium")
CHROMEDRIVER = os.environ.get("ASPERITY2D_CHROMEDRIVER", "/usr/bin/chromedriver")
FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--window-size=1100,1300")
INSTALL = ("needs headless Chromium and its driver: apt-get install chromium chromium-driver "
           "(Debian; or set ASPERITY2D_CHROMIUM / ASPERITY2D_CHROMEDRIVER) and pip install selenium")


def _missing() -> str | None:
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed"
    for path in (CHROMIUM, CHROMEDRIVER):
        if not (os.path.exists(path) or shutil.which(path)):
            return f"{path} not found"
    return None


pytestmark = pytest.mark.skipif(_missing() is not None, reason=f"{_missing()}: {INSTALL}")


@pytest.fixture(scope="module")
def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in FLAGS:
        options.add_argument(flag)
    profile = tempfile.mkdtemp(prefix="asperity2d-chromium-")
    options.add_argument(f"--user-data-dir={profile}")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(30)
    driver.set_script_timeout(30)
    try:
        yield driver
    finally:
        driver.quit()
        shutil.rmtree(profile, ignore_errors=True)


def open_player(browser, path):
    browser.get(path.resolve().as_uri())
    browser.execute_script("return document.readyState")
    assert browser.execute_script("return typeof window.asperityPlayer") == "object"


def console_errors(browser) -> list:
    return [e for e in browser.get_log("browser") if e["level"] in ("SEVERE", "ERROR")]


def pixel(browser, selector, x, y):
    """RGB of the canvas pixel at CSS px (x, y) of the element matching ``selector``."""
    return browser.execute_script(
        "const c = document.querySelector(arguments[0]); const r = window.devicePixelRatio || 1;"
        "return Array.from(c.getContext('2d').getImageData(Math.round(arguments[1] * r),"
        " Math.round(arguments[2] * r), 1, 1).data).slice(0, 3);", selector, x, y)


@pytest.fixture(scope="module")
def run(stick_slip_run):
    return stick_slip_run


@pytest.fixture(scope="module")
def player(run, tmp_path_factory):
    return render(run, tmp_path_factory.mktemp("player") / "run.html")


def hex_rgb(colour: str):
    return [int(colour[i:i + 2], 16) for i in (1, 3, 5)]


def test_scrubbing_puts_the_bodies_where_the_arrays_do(browser, run, player):
    open_player(browser, player)
    events = a.stick_slip_events(run)
    times = [0.0, events[0].t_stick + 0.5 * events[0].stick_duration,
             0.5 * (events[2].t_slip + events[2].t_end), run.t[-1]]
    slip_seen = False
    for wanted in times:
        t = browser.execute_script("return window.asperityPlayer.seek(arguments[0])", wanted)
        state = browser.execute_script("return window.asperityPlayer.state()")
        assert state["t"] == t
        k = int(np.flatnonzero(run.t == t)[0])  # the player shows a recorded sample
        assert abs(t - wanted) <= 2 * float(np.max(np.diff(run.t)))
        assert state["slider"]["x"] == run.x[k] and state["slider"]["y"] == run.y[k]
        assert state["drive_end"] == run.drive_x[k]
        lower = state["lower"]
        np.testing.assert_allclose([l["dy"] for l in lower], run.lower_dy[:, k], rtol=1e-6, atol=1e-15)
        assert [l["contact"] for l in lower] == run.lower_contact[:, k].tolist()
        slipping = any(e.t_slip < t <= e.t_end for e in events)
        assert state["slipping"] == slipping
        slip_seen |= slipping
        # the pixel at the centre of the slider's bar, from the record's x and the player's camera
        cam = state["camera"]
        scene = run.scene
        rear = scene.slider.tips()[0] - float(np.ravel(scene.slider.runs()[0])[0])
        front = scene.slider.tips()[-1] + float(np.ravel(scene.slider.runs()[1])[-1])
        bx = ((run.x[k] + 0.5 * (rear + front) - cam["left"]) * cam["scale"] - cam["W"] / 2) * cam["zoom"] \
            + cam["W"] / 2 + cam["panX"]
        by = (cam["topPx"] - (run.y[k] - cam["yRef"]) * cam["vscale"] - cam["H"] / 2) * cam["zoom"] \
            + cam["H"] / 2 + cam["panY"]
        bar = state["drawn"]["slider_bar"]
        by -= 0.5 * (bar[3] - bar[1])
        expected = raster.COLOURS["slider_slip" if slipping else "slider_stick"]
        assert pixel(browser, ".ap-scene", bx, by) == list(expected)
        assert pixel(browser, ".ap-scene", bx, by - (bar[3] - bar[1])) != list(expected)  # above the bar
        # meter cursors at the time
        for plot, x in zip(state["meter_plots"], state["meter_cursor_px"]):
            assert x == round(plot["x0"] + (t - run.t[0]) / (run.t[-1] - run.t[0]) * (plot["x1"] - plot["x0"]))
    assert slip_seen
    assert console_errors(browser) == []


def test_zoom_pan_keep_the_bodies_under_the_camera(browser, run, player):
    open_player(browser, player)
    browser.execute_script("window.asperityPlayer.seek(arguments[0])", float(run.t[len(run.t) // 3]))
    canvas = browser.find_element("css selector", ".ap-scene")
    browser.execute_script(
        "arguments[0].dispatchEvent(new WheelEvent('wheel', {deltaY: -400, clientX: arguments[1],"
        " clientY: arguments[2], bubbles: true, cancelable: true}))", canvas, 300, 120)
    browser.execute_script("return new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    state = browser.execute_script("return window.asperityPlayer.state()")
    assert state["zoom"] > 1.5
    cam, bar = state["camera"], state["drawn"]["slider_bar"]
    k = int(np.flatnonzero(run.t == state["t"])[0])
    rear = run.scene.slider.tips()[0] - float(np.ravel(run.scene.slider.runs()[0])[0])
    x0 = ((run.x[k] + rear - cam["left"]) * cam["scale"] - cam["W"] / 2) * cam["zoom"] + cam["W"] / 2 + cam["panX"]
    assert x0 == pytest.approx(bar[0], abs=1e-6)
    if 0 < bar[0] + 3 < cam["W"]:
        assert pixel(browser, ".ap-scene", bar[0] + 3, 0.5 * (bar[1] + bar[3])) in (
            list(raster.COLOURS["slider_stick"]), list(raster.COLOURS["slider_slip"]))
    assert console_errors(browser) == []


def test_hover_reads_out_with_units_and_the_timeline_jumps_to_events(browser, run, player):
    open_player(browser, player)
    meter = browser.find_elements("css selector", ".ap-meters canvas")[0]  # the drive force
    box = browser.execute_script("const r = arguments[0].getBoundingClientRect(); return [r.left, r.top, r.width, r.height]",
                                 meter)
    plot = browser.execute_script("return window.asperityPlayer.state().meter_plots[0]")
    x = box[0] + plot["x0"] + 0.5 * (plot["x1"] - plot["x0"])
    browser.execute_script("arguments[0].dispatchEvent(new MouseEvent('mousemove', {clientX: arguments[1],"
                           " clientY: arguments[2], bubbles: true}))", meter, x, box[1] + 60)
    tip = browser.execute_script("const t = document.querySelector('.ap-tip'); return [t.hidden, t.textContent]")
    assert not tip[0]
    assert "t = " in tip[1] and ("ns" in tip[1] or "µs" in tip[1])
    assert any(unit in tip[1] for unit in (" mN", " µN", " N")) and "drive:" in tip[1]
    # a click on the timeline next to an event's marker jumps to that slip
    event = a.stick_slip_events(run)[2]
    track = browser.find_element("css selector", ".ap-track")
    tb = browser.execute_script("const r = arguments[0].getBoundingClientRect(); return [r.left, r.top, r.width, r.height]",
                                track)
    mx = tb[0] + 6 + (event.t_slip - run.t[0]) / (run.t[-1] - run.t[0]) * (tb[2] - 12) + 3
    browser.execute_script("arguments[0].dispatchEvent(new MouseEvent('click', {clientX: arguments[1],"
                           " clientY: arguments[2], bubbles: true}))", track, mx, tb[1] + 10)
    t = browser.execute_script("return window.asperityPlayer.state().t")
    assert abs(t - event.t_slip) <= float(np.max(np.diff(run.t)))
    assert console_errors(browser) == []


def test_play_advances_time_and_pause_stops_it(browser, player):
    open_player(browser, player)
    browser.execute_script("window.asperityPlayer.seek(0); window.asperityPlayer.setSpeed(10);"
                           "window.asperityPlayer.play()")
    browser.execute_script("return new Promise(r => setTimeout(r, 600))")
    first = browser.execute_script("return window.asperityPlayer.state()")
    browser.execute_script("return new Promise(r => setTimeout(r, 400))")
    second = browser.execute_script("window.asperityPlayer.pause(); return window.asperityPlayer.state()")
    assert first["playing"] and 0 < first["t"] < second["t"]
    browser.execute_script("return new Promise(r => setTimeout(r, 300))")
    assert browser.execute_script("return window.asperityPlayer.state().t") == second["t"]
    browser.execute_script("window.asperityPlayer.step(1)")
    assert browser.execute_script("return window.asperityPlayer.state().t") > second["t"]
    assert console_errors(browser) == []


def test_belt_chain_player(browser, tmp_path):
    chain = simulate_chain(**preset("table2-3dof"))
    path = render(chain, tmp_path / "chain.html")
    open_player(browser, path)
    for wanted in (0.0, 3.3, 7.7):
        t = browser.execute_script("return window.asperityPlayer.seek(arguments[0])", wanted)
        state = browser.execute_script("return window.asperityPlayer.state()")
        k = int(np.flatnonzero(chain.t == t)[0])
        assert [m["x"] for m in state["masses"]] == chain.x[:, k].tolist()
        assert [m["state"] for m in state["masses"]] == chain.state[:, k].tolist()
        colours = {0: "mass_stick", 1: "mass_fast", -1: "mass_slow"}
        for (px, py), s in zip(state["drawn"]["masses_px"], chain.state[:, k]):
            assert pixel(browser, ".ap-scene", px, py + 12) == list(raster.COLOURS[colours[int(s)]])
    assert console_errors(browser) == []
