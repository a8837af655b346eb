"""The HTML player in a real browser: headless Chromium driven by Selenium with Debian's chromedriver.

Opens the player from ``file://`` (no network), fails on any console error, scrubs to given
times and checks that the drawn bodies sit where the result's arrays put them -- through the
state the player exposes (``window.asperityPlayer.state()``) and by reading the canvas's
pixels -- and that playing advances the time. Skipped, saying what to install, on a machine
without the browser: ``apt-get install chromium chromium-driver`` (Debian) and
``pip install selenium`` (in the ``test`` extra).
"""

import contextlib
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
         "--disable-background-networking", "--disable-component-update", "--disable-sync")
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


@contextlib.contextmanager
def chromium(*, window: str, page_load_timeout: float = 30):
    """Headless Chromium through its driver, at ``window`` ("W,H" px), its console log kept, in a
    profile folder of its own (removed after): the one way every browser test opens it."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in (*FLAGS, f"--window-size={window}"):
        options.add_argument(flag)
    profile = tempfile.mkdtemp(prefix="asperity2d-chromium-")
    options.add_argument(f"--user-data-dir={profile}")
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(CHROMEDRIVER), options=options)
    driver.set_page_load_timeout(page_load_timeout)
    driver.set_script_timeout(30)
    try:
        yield driver
    finally:
        driver.quit()
        shutil.rmtree(profile, ignore_errors=True)


@pytest.fixture(scope="module")
def browser():
    with chromium(window="1100,1300") as driver:
        yield driver


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


# -- analysis in the player ------------------------------------------------------------------------
@pytest.fixture(scope="module")
def main_run():
    """The main job's run (scenes/quickstart.py): the default scene, 12,210 samples (decimated)."""
    return a.simulate(a.make_scene())


@pytest.fixture(scope="module")
def main_player(main_run, tmp_path_factory):
    return render(main_run, tmp_path_factory.mktemp("main") / "run.html")


def kept(run, browser) -> np.ndarray:
    """Indices into the result of the samples the open player holds (its times are the result's own)."""
    t = np.array(browser.execute_script(
        "const c = window.asperityPlayer.exportMeter(0, 'csv').trim().split('\\n').slice(1);"
        "return c.map((l) => parseFloat(l.split(',')[0]));"))
    k = np.searchsorted(run.t, t)
    np.testing.assert_array_equal(run.t[k], t)
    return k


def catch_downloads(browser):
    browser.execute_script(
        "window.__blobs = []; const make = URL.createObjectURL.bind(URL);"
        "URL.createObjectURL = (b) => { window.__blobs.push(b); return make(b); };"
        "window.__clicks = 0; window.__names = [];"
        "HTMLAnchorElement.prototype.click = function () { window.__names = window.__names.concat([this.download]); };")


def last_download(browser, as_text=True):
    """The download the last click started (waits for it: a PNG is encoded asynchronously)."""
    return browser.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const wait = () => { if ((window.__names || []).length < window.__clicks) return setTimeout(wait, 20);"
        "const b = window.__blobs[window.__blobs.length - 1];"
        "const name = window.__names[window.__names.length - 1];"
        + ("b.text().then((t) => done([b.type, name, t]));" if as_text else
           "b.arrayBuffer().then((buf) => done([b.type, name, Array.from(new Uint8Array(buf).slice(0, 8)), buf.byteLength]));")
        + "}; wait();")


def click(browser, element):
    """Click an export button, counting the downloads it should start."""
    browser.execute_script("window.__clicks = (window.__clicks || 0) + 1")
    element.click()


def meter_box(browser, k):
    canvas = browser.find_elements("css selector", ".ap-meters canvas")[k]
    box = browser.execute_script("const r = arguments[0].getBoundingClientRect(); return [r.left, r.top];", canvas)
    return canvas, box, browser.execute_script("return window.asperityPlayer.meters()[arguments[0]]", k)


def mouse(browser, element, kind, x, y):
    browser.execute_script("arguments[0].dispatchEvent(new MouseEvent(arguments[1], {clientX: arguments[2],"
                           " clientY: arguments[3], button: 0, bubbles: true, cancelable: true}))", element, kind, x, y)


def settle(browser):
    browser.execute_script("return new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")


def test_box_zoom_sets_linked_time_axes_and_the_value_axis_and_double_click_resets(browser, main_run, main_player):
    open_player(browser, main_player)
    canvas, (left, top), meter = meter_box(browser, 3)  # slider velocity
    p, lim0 = meter["plot"], meter["limits"]
    view0 = browser.execute_script("return window.asperityPlayer.state().view")
    assert view0 == [main_run.t[0], main_run.t[-1]]
    fx = (0.30, 0.55)  # of the plot's width
    fy = (0.20, 0.70)  # of its height, from the top
    # whole client px (a mouse event's coordinates are), and where they fall on the plot
    X = [round(left + p["x0"] + f * (p["x1"] - p["x0"])) for f in fx]
    Y = [round(top + p["y0"] + f * (p["y1"] - p["y0"])) for f in fy]
    fx = [(x - left - p["x0"]) / (p["x1"] - p["x0"]) for x in X]
    fy = [(y - top - p["y0"]) / (p["y1"] - p["y0"]) for y in Y]
    mouse(browser, canvas, "mousedown", X[0], Y[0])
    mouse(browser, canvas, "mousemove", X[1], Y[1])
    mouse(browser, canvas, "mouseup", X[1], Y[1])
    settle(browser)
    state = browser.execute_script("return window.asperityPlayer.state()")
    span = view0[1] - view0[0]
    assert state["view"] == pytest.approx([view0[0] + fx[0] * span, view0[0] + fx[1] * span], rel=1e-12)
    meters = browser.execute_script("return window.asperityPlayer.meters()")
    height = lim0[1] - lim0[0]
    assert meters[3]["limits"] == pytest.approx([lim0[1] - fy[1] * height, lim0[1] - fy[0] * height], rel=1e-9)
    assert 0.2 * (lim0[1] - lim0[0]) < meters[3]["limits"][1] - meters[3]["limits"][0] < 0.8 * (lim0[1] - lim0[0])
    assert meters[0]["limits"] == browser.execute_script("return window.asperityPlayer.meters()[0].limits")
    # the other meters' time axes follow (linked): their cursor is placed on the zoomed axis
    browser.execute_script("window.asperityPlayer.seek(arguments[0])", 0.5 * sum(state["view"]))
    state = browser.execute_script("return window.asperityPlayer.state()")
    for plot, x in zip(state["meter_plots"], state["meter_cursor_px"]):
        assert x == round(plot["x0"] + (state["t"] - state["view"][0]) / (state["view"][1] - state["view"][0])
                          * (plot["x1"] - plot["x0"]))
    browser.execute_script("arguments[0].dispatchEvent(new MouseEvent('dblclick', {bubbles: true}))", canvas)
    settle(browser)
    assert browser.execute_script("return window.asperityPlayer.state().view") == view0
    assert browser.execute_script("return window.asperityPlayer.meters()[3].limits") == lim0
    assert console_errors(browser) == []


def test_values_off_the_axis_are_counted_and_marked(browser, main_run, main_player):
    from asperity2d.renderers.meters import asperity_meters

    open_player(browser, main_player)
    keep = kept(main_run, browser)
    lo, hi = asperity_meters(main_run)[3].limits
    v = main_run.v[keep]
    meter = browser.execute_script("return window.asperityPlayer.meters()[3]")
    assert meter["limits"] == [lo, hi] and meter["title"] == "slider velocity"
    assert meter["clipped"] == np.count_nonzero((v > hi) | (v < lo)) > 0
    # at the fastest sample the cursor's marker is an arrowhead just under the plot's top edge
    browser.execute_script("window.asperityPlayer.seek(arguments[0])", float(main_run.t[keep][np.argmax(v)]))
    state = browser.execute_script("return window.asperityPlayer.state()")
    x, plot = state["meter_cursor_px"][3], state["meter_plots"][3]
    canvas = ".ap-meter:nth-child(4) canvas"
    assert pixel(browser, canvas, x, plot["y0"] + 4) == hex_rgb("#%02x%02x%02x" % raster.COLOURS["c4"])
    assert console_errors(browser) == []


def test_csv_export_gives_the_results_numbers(browser, main_run, main_player):
    open_player(browser, main_player)
    catch_downloads(browser)
    keep = kept(main_run, browser)
    assert len(keep) < len(main_run.t)  # decimated: the CSV holds the kept samples
    checks = [(0, "drive", "drive force", [main_run.drive_force]),
              (1, "contact", "contact force on the slider", [main_run.friction_force, main_run.tangential_force]),
              (0, "normal", "normal force on the slider", [main_run.normal_force]),
              (0, "y", "slider height y", [main_run.y]),
              (0, "lower_dy_3", "lower asperity 4 deflection", [main_run.lower_dy[3]])]
    for k, channel, title, arrays in checks:
        if browser.execute_script("return window.asperityPlayer.meters()[arguments[0]].channel", k) != channel:
            select = browser.find_elements("css selector", ".ap-meter select")[k]
            browser.execute_script("arguments[0].value = arguments[1];"
                                   "arguments[0].dispatchEvent(new Event('change'))", select, channel)
        button = browser.find_elements("css selector", ".ap-meter")[k].find_element("css selector", '[data-act="csv"]')
        click(browser, button)
        kind, name, text = last_download(browser)
        assert kind == "text/csv" and name.endswith(".csv")
        lines = text.strip().split("\n")
        head = lines[0].split('","')
        assert lines[0].startswith('t (s),"') and all(h.rstrip('"').endswith(")") for h in head)
        unit = {"drive": "N", "contact": "N", "normal": "N", "y": "m", "lower_dy_3": "m"}[channel]
        assert lines[0].count(f"({unit})") == len(arrays) and title in lines[0]
        table = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
        np.testing.assert_array_equal(table[:, 0], main_run.t[keep])  # float64, 17 digits: exact
        for j, array in enumerate(arrays):
            np.testing.assert_array_equal(table[:, j + 1], np.asarray(array)[keep])
    assert console_errors(browser) == []


def test_meter_and_frame_export_as_png_and_svg(browser, main_player):
    import xml.etree.ElementTree as ET

    open_player(browser, main_player)
    catch_downloads(browser)
    meter = browser.find_elements("css selector", ".ap-meter")[0]
    click(browser, meter.find_element("css selector", '[data-act="svg"]'))
    kind, name, text = last_download(browser)
    assert kind == "image/svg+xml" and name == "drive-force.svg"
    svg = ET.fromstring(text)
    texts = " ".join(t.text or "" for t in svg.iter("{http://www.w3.org/2000/svg}text"))
    assert "drive force (mN)" in texts and len(list(svg.iter("{http://www.w3.org/2000/svg}path"))) > 5
    for selector in ('.ap-meter [data-act="png"]', '.ap-bar [data-act="png"]'):
        click(browser, browser.find_element("css selector", selector))
        kind, name, head, size = last_download(browser, as_text=False)
        assert kind == "image/png" and head == [137, 80, 78, 71, 13, 10, 26, 10] and size > 2000
    click(browser, browser.find_element("css selector", '.ap-bar [data-act="svg"]'))
    kind, name, text = last_download(browser)
    frame = ET.fromstring(text)
    assert name == "frame.svg" and len(list(frame.iter("{http://www.w3.org/2000/svg}path"))) > 16
    assert console_errors(browser) == []


def test_jump_to_event_lands_inside_the_slip(browser, main_run, main_player):
    open_player(browser, main_player)
    keep = kept(main_run, browser)
    events = a.stick_slip_events(main_run)
    buttons = browser.find_elements("css selector", ".ap-events button")
    assert len(buttons) == len(events)
    for e, button in zip(events, buttons):
        button.click()
        state = browser.execute_script("return window.asperityPlayer.state()")
        assert e.t_slip < state["t"] <= e.t_end and state["slipping"]
        assert state["t"] == main_run.t[keep][np.searchsorted(main_run.t[keep], e.t_slip, side="right")]
        badge = browser.find_element("css selector", ".ap-state").text
        assert badge == "SLIP"
    assert console_errors(browser) == []


def test_title_and_event_list_beside_the_scene_at_1280x800(browser, main_player):
    browser.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                            {"width": 1280, "height": 800, "deviceScaleFactor": 1, "mobile": False})
    try:
        open_player(browser, main_player)
        title = browser.find_element("css selector", ".ap-title").text
        assert title == "Ooten's fixed track \u2014 16 regular lower asperities, 4-tip slider, spring drive 20 m/s"
        scene = browser.execute_script("return document.querySelector('.ap-scene').getBoundingClientRect().toJSON()")
        for button in browser.find_elements("css selector", ".ap-events button"):
            r = browser.execute_script("return arguments[0].getBoundingClientRect().toJSON()", button)
            assert r["left"] >= scene["right"] and r["right"] <= 1280 and 0 <= r["top"] and r["bottom"] <= 800
        assert browser.execute_script("return window.innerWidth") == 1280
    finally:
        browser.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})
    assert console_errors(browser) == []


def test_hover_on_a_contact_gives_its_force_and_the_ruler_measures(browser, run, player):
    from asperity2d.renderers.stage import force_shares

    open_player(browser, player)
    k = int(np.flatnonzero(run.lower_contact.any(axis=0))[len(run.t) // 10])
    browser.execute_script("window.asperityPlayer.seek(arguments[0])", float(run.t[k]))
    state = browser.execute_script("return window.asperityPlayer.state()")
    assert state["t"] == run.t[k]
    j = int(np.flatnonzero(run.lower_contact[:, k])[0])
    px, py = state["drawn"]["lower_px"][j]
    scene = browser.find_element("css selector", ".ap-scene")
    left, top = browser.execute_script("const r = arguments[0].getBoundingClientRect(); return [r.left, r.top]", scene)
    browser.execute_script("arguments[0].dispatchEvent(new PointerEvent('pointermove', {clientX: arguments[1],"
                           " clientY: arguments[2], bubbles: true}))", scene, left + px + 2, top + py + 1)
    tip = browser.execute_script("return document.querySelector('.ap-tip').textContent")
    share = force_shares(run, k)[j]
    force = share * np.hypot(run.friction_force[k], run.normal_force[k])
    contact = browser.execute_script("return window.asperityPlayer.contactAt(arguments[0], arguments[1])", px, py)
    assert contact["tip"] == j and contact["force"] == pytest.approx(force, rel=1e-12)
    assert f"lower tip {j + 1} touching" in tip and "contact force " + browser.execute_script(
        "return window.asperityPlayer.si(arguments[0], 'N', 4)", force) in tip
    # the ruler: from one lower tip to the next, in world metres
    browser.find_element("css selector", '[data-act="ruler"]').click()
    (ax, ay), (bx, by) = state["drawn"]["lower_px"][j], state["drawn"]["lower_px"][j + 1]
    for kind, x, y in (("pointerdown", ax, ay), ("pointermove", bx, by), ("pointerup", bx, by)):
        browser.execute_script("arguments[0].dispatchEvent(new PointerEvent(arguments[1], {clientX: arguments[2],"
                               " clientY: arguments[3], bubbles: true}))", scene, kind, left + x, top + y)
    settle(browser)
    measure = browser.execute_script("return window.asperityPlayer.state().measure")
    lower = state["lower"]
    # the pointer's CSS px are rounded by the browser: a pixel of slack, in metres
    slack = 1.0 / state["camera"]["scale"] / state["camera"]["zoom"]
    assert measure["dx"] == pytest.approx(lower[j + 1]["x"] - lower[j]["x"], abs=slack)
    assert measure["dy"] == pytest.approx(lower[j + 1]["y"] - lower[j]["y"], abs=slack / state["exaggeration"])
    browser.find_element("css selector", '[data-act="ruler"]').click()
    assert console_errors(browser) == []


def test_streamed_run_linked_cursors_and_destroy(browser, run, tmp_path):
    """The component as the app uses it: a scene's static payload, chunks appended, finish, two
    players with linked cursors, destroy."""
    import json

    from asperity2d.renderers.player import _clean, asset, chunk_payload, final_payload, scene_payload

    page = tmp_path / "stream.html"
    page.write_text("<!DOCTYPE html><html><head><meta charset='utf-8'><style>" + asset("player.css") +
                    "</style></head><body><div id='one'></div><div id='two'></div><script>" + asset("player.js") +
                    "</script></body></html>", encoding="utf-8")
    browser.get(page.as_uri())
    static = json.dumps(_clean(scene_payload(run.scene, duration=float(run.t[-1]))))
    browser.execute_script("window.players = [AsperityPlayer.create(document.getElementById('one'),"
                           " JSON.parse(arguments[0]), {keys: false}), AsperityPlayer.create("
                           "document.getElementById('two'), JSON.parse(arguments[0]), {keys: false})];"
                           "window.players[0].onCursor((t) => window.players[1].setCursor(t));", static)
    assert browser.execute_script("return window.players[0].samples") == 0
    bounds = np.linspace(0, len(run.t), 5).astype(int)
    for a_, b_ in zip(bounds[:-1], bounds[1:]):
        chunk = json.dumps(_clean(chunk_payload(run, int(a_), int(b_))))
        browser.execute_script("for (const p of window.players) p.append(JSON.parse(arguments[0]))", chunk)
        state = browser.execute_script("return window.players[0].api.state()")
        assert state["samples"] == b_ and not state["finished"]
        assert browser.execute_script("return document.querySelector('#one .ap-live').textContent").startswith("computing")
    with pytest.raises(Exception, match="chunk starts at sample 0"):
        browser.execute_script("window.players[0].append(JSON.parse(arguments[0]))",
                               json.dumps(_clean(chunk_payload(run, 0, 3))))
    final = json.dumps(_clean(final_payload(run)))
    browser.execute_script("for (const p of window.players) p.finish(JSON.parse(arguments[0]))", final)
    t = browser.execute_script("return window.players[0].api.seek(arguments[0])", float(run.t[len(run.t) // 2]))
    assert t == run.t[len(run.t) // 2]
    two = browser.execute_script("return window.players[1].api.state()")
    assert two["t"] == t and two["finished"]
    assert two["slider"]["x"] == run.x[len(run.t) // 2]
    e = a.stick_slip_events(run)[1]
    landed = browser.execute_script("return window.players[0].api.jumpToEvent(1)")
    assert e.t_slip < landed <= e.t_end
    # once finished, the slip flags are the whole run's (a partial record's last slip may end later)
    from asperity2d.renderers.stage import slip_mask

    mask = slip_mask(run)
    for k in np.linspace(0, len(run.t) - 1, 60).astype(int).tolist() + [int(np.searchsorted(run.t, e.t_slip))]:
        state = browser.execute_script("window.players[0].api.seek(arguments[0]);"
                                       "return window.players[0].api.state()", float(run.t[k]))
        assert state["slipping"] == bool(mask[k])
    # linked time windows: a box zoom on one player's meters zooms the other's
    browser.execute_script("window.players[0].onView((v) => window.players[1].setView(v));"
                           "window.players[0].api.zoomMeter(0, arguments[0], arguments[1], null, null)",
                           float(run.t[10]), float(run.t[200]))
    assert browser.execute_script("return window.players[1].api.state().view") == [run.t[10], run.t[200]]
    browser.execute_script("window.players[0].api.resetZoom()")
    assert browser.execute_script("return window.players[1].api.state().view") == [run.t[0], run.t[-1]]
    browser.execute_script("window.players[1].destroy()")
    assert browser.execute_script("return document.getElementById('two').children.length") == 0
    browser.execute_script("window.players[0].api.seek(0)")  # its listener to the destroyed one is harmless
    assert console_errors(browser) == []


def test_belt_player_in_a_hidden_notebook_cell_draws_when_shown_with_a_legend(browser, tmp_path):
    from asperity2d.renderers.notebook import result_html

    chain = simulate_chain(**preset("table2-3dof"))
    page = tmp_path / "cell.html"
    page.write_text("<!DOCTYPE html><html><body><div id='cell' style='display:none'>" + result_html(chain) +
                    "</div></body></html>", encoding="utf-8")
    browser.get(page.as_uri())
    browser.execute_script("return new Promise(r => setTimeout(r, 300))")
    browser.execute_script("document.getElementById('cell').style.display = 'block'")
    browser.execute_script("return new Promise(r => setTimeout(r, 500))")
    browser.switch_to.frame(browser.find_element("css selector", "iframe"))
    try:
        width, height = browser.execute_script("const c = document.querySelector('.ap-scene'); return [c.width, c.height]")
        assert width > 300 and height > 100  # not the 1x1 px of a canvas sized while hidden
        state = browser.execute_script("return window.asperityPlayer.state()")
        colours = {0: "mass_stick", 1: "mass_fast", -1: "mass_slow"}
        for (px, py), m in zip(state["drawn"]["masses_px"], state["masses"]):
            assert pixel(browser, ".ap-scene", px, py + 12) == list(raster.COLOURS[colours[m["state"]]])
        legend = browser.find_element("css selector", ".ap-legend").text
        assert "stuck to the belt" in legend and "slipping, faster than the belt" in legend
        assert console_errors(browser) == []
    finally:
        browser.switch_to.default_content()


def test_stepping_through_the_largest_slip_moves_less_than_a_pitch_a_frame(browser, main_run, main_player):
    """The player's frame step in a slip follows the GIF's slow motion (slower where the slider is
    fast): stepping frame by frame shows the tips climb the flanks."""
    open_player(browser, main_player)
    events = a.stick_slip_events(main_run)
    k = max(range(len(events)), key=lambda i: events[i].slip_distance)
    e, pitch = events[k], main_run.scene.lower.spacing.mean_pitch
    browser.execute_script("window.asperityPlayer.seek(arguments[0])", e.t_slip)
    xs, steps = [browser.execute_script("return window.asperityPlayer.state().slider.x")], 0
    while True:
        state = browser.execute_script("window.asperityPlayer.step(1); return window.asperityPlayer.state()")
        xs.append(state["slider"]["x"])
        steps += 1
        if state["t"] > e.t_end or steps > 2000:
            break
    jumps = np.abs(np.diff(xs)) / pitch
    assert steps >= e.slip_distance / pitch and jumps.max() < 1.0, (steps, jumps.max())
    assert console_errors(browser) == []


def test_energy_book_and_per_tip_force_channels(browser, main_run, main_player):
    """The derived channels, exported: the energy book's terms from the kept samples (drive work by
    the trapezoid rule, 0.5 m v^2, 0.5 k s^2, 0.5 sum k_i dy_i^2, the rest) and each tip's share of
    the contact force, as numpy computes them from the result (1e-12: float64 summation order)."""
    from asperity2d.renderers.stage import force_shares

    open_player(browser, main_player)
    keep = kept(main_run, browser)
    r, scene = main_run, main_run.scene
    browser.execute_script("window.asperityPlayer.setChannel(1, 'energy'); window.asperityPlayer.setChannel(2, 'tip_force_5')")
    table = lambda k: np.array([[float(v) for v in line.split(",")] for line in browser.execute_script(
        "return window.asperityPlayer.exportMeter(arguments[0], 'csv')", k).strip().split("\n")[1:]])
    energy = table(1)
    v, vy, x, dx = r.v[keep], r.vy[keep], r.x[keep], r.drive_x[keep]
    kin = 0.5 * scene.slider.mass * (v ** 2 + vy ** 2)
    spring = 0.5 * scene.drive.stiffness * (dx - x) ** 2
    track = 0.5 * (np.asarray(scene.lower.stiffness)[:, None] * r.lower_dy[:, keep] ** 2).sum(axis=0)
    f = r.drive_force[keep]
    work = np.r_[0.0, np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(dx))]
    rest = work - (kin + spring + track - kin[0] - spring[0] - track[0])
    scale = np.max(np.abs(work))
    for j, expected in enumerate((work, kin, spring, track, rest)):
        np.testing.assert_allclose(energy[:, j + 1], expected, rtol=0, atol=1e-12 * scale)
    assert rest[-1] > 0.5 * work[-1]  # most of the drive's work is dissipated by the end of the run
    tip = table(2)
    expected = [force_shares(r, k)[5] * np.hypot(r.friction_force[k], r.normal_force[k]) for k in keep]
    np.testing.assert_allclose(tip[:, 1], expected, rtol=1e-12, atol=1e-18)
    assert np.count_nonzero(tip[:, 1]) > 10
    assert console_errors(browser) == []
