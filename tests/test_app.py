"""The workbench's server, protocol and command line, without a browser.

The server runs in-process under Starlette's TestClient (token, Host and Origin checks, 403,
the WebSocket protocol, hostile values, cancellation, one run at a time, closing the tab) and
once as a real ``asperity2d explore`` process under uvicorn (loopback only, the URL on one line,
Ctrl-C). The run streamed in pieces is checked bit-identical to ``simulate``, and the scene
the app saves as TOML is checked to give, through ``asperity2d run``, the app's run to the bit.
Cost: ~25 s here (the real server process and its start-up dominate).
"""

from __future__ import annotations

import gc
import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("starlette", reason='needs the app extra: pip install -e ".[test]"')
pytest.importorskip("httpx", reason="Starlette's TestClient needs httpx")

from starlette.testclient import TestClient  # noqa: E402

import asperity2d as a  # noqa: E402
from asperity2d.app import controls  # noqa: E402
from asperity2d.app.server import bind, create_app  # noqa: E402
from asperity2d.app.session import Session  # noqa: E402
from asperity2d.cli import main  # noqa: E402
from asperity2d.run import Run, Simulation, simulate  # noqa: E402

TOKEN = "test-token-0123456789"
#: A scene whose run to the end of the surface takes ~0.3 s here (2 of 4 asperities, short).
SMALL = {"lower_count": "6", "upper_count": "2"}
ARRAYS = ("t", "x", "y", "v", "vy", "drive_x", "drive_force", "friction_force", "normal_force",
          "lower_dy", "lower_contact")


# -- the run in pieces ---------------------------------------------------------------------------
def test_simulation_in_pieces_is_simulate_to_the_bit():
    scene = a.make_scene(lower_count=6, upper_count=2, spacing="random", seed=4, track="free")
    whole = simulate(scene, 1e-7)
    sim = Simulation(scene, 1e-7, every=7)
    seen = [run.samples for run in sim]
    assert seen[0] == 0 and len(seen) > 10 and all(b - a >= 7 for a, b in zip(seen[1:], seen[2:]))
    for name in ARRAYS:
        assert np.array_equal(getattr(whole, name), getattr(sim.result, name)), name
    assert sim.result.meta["status"] == whole.meta["status"]


def test_simulation_stopped_early_keeps_what_it_recorded():
    scene = a.make_scene(lower_count=6, upper_count=2)
    sim = Simulation(scene, every=50)
    for run in sim:
        if run.samples >= 100:
            break
    sim.close()
    part = run.result()
    whole = simulate(scene)
    assert 100 <= len(part.t) < len(whole.t)
    assert np.array_equal(part.x, whole.x[:len(part.t)])  # the same run, cut short


# -- controls from the parameter records ------------------------------------------------------------
def test_controls_are_the_parameter_records_in_the_references_groups():
    from asperity2d.builders import KEYWORDS, PARAMETERS

    schema = controls.schema()
    titles = [g["title"] for g in schema["groups"]]
    assert titles == ["make_scene's named keywords", "Ooten's fixed track", "everything else"]
    shown = [(c["name"], c["unit"], c["meaning"]) for g in schema["groups"] for c in g["controls"]]
    assert shown == [(p.name, p.unit, p.meaning) for p in KEYWORDS + PARAMETERS]
    kinds = {c["name"]: c for g in schema["groups"] for c in g["controls"]}
    assert kinds["spacing"]["choices"] == ["regular", "random", "random-upper", "random-lower"]
    assert kinds["lower_count"]["kind"] == "integer" and kinds["mass"]["kind"] == "number"
    assert kinds["surface_detrend"]["kind"] == "flag" and kinds["height"]["derived"]


# -- the protocol, host-free ---------------------------------------------------------------------------
class Page:
    """A page's end of a Session: every message, and waiting for one."""

    def __init__(self, values=None, workers=None):
        self.messages, self.cond = [], threading.Condition()
        self.session = Session(self.receive, values=values, workers=workers)

    def receive(self, text):
        with self.cond:
            self.messages.append(json.loads(text))
            self.cond.notify_all()

    def wait(self, test, timeout=60.0):
        end = time.monotonic() + timeout
        with self.cond:
            while True:
                found = [m for m in self.messages if test(m)]
                if found:
                    return found[-1]
                left = end - time.monotonic()
                assert left > 0, f"no such message; got {[m['type'] for m in self.messages][-20:]}"
                self.cond.wait(left)

    def of(self, kind):
        with self.cond:
            return [m for m in self.messages if m["type"] == kind]


def test_toml_saved_by_the_app_reproduces_its_run_to_the_bit(tmp_path, capsys):
    page = Page()
    values = {**SMALL, "spacing": "random", "seed": "5", "drive_velocity": "25.5", "mu_static": "0.35",
              "duration": "1.5e-7"}
    page.session.handle({"type": "set", "values": values})
    page.wait(lambda m: m["type"] == "run-end")
    page.session.handle({"type": "export", "what": "toml"})
    text = page.wait(lambda m: m["type"] == "export")["text"]
    path = tmp_path / "scene.toml"
    path.write_text(text)
    assert main(["run", str(path), "--save", str(tmp_path / "cli.npz")]) == 0
    assert f"wrote {tmp_path / 'cli.npz'}" in capsys.readouterr().out  # run says where it wrote
    cli = a.load(tmp_path / "cli.npz")
    app = page.session.result
    for name in ARRAYS:
        assert np.array_equal(getattr(cli, name), getattr(app, name)), name
    # the .npz the app exports is that run too
    page.session.handle({"type": "export", "what": "npz"})
    import base64

    npz = page.wait(lambda m: m["type"] == "export" and m["what"] == "npz")
    (tmp_path / "app.npz").write_bytes(base64.b64decode(npz["base64"]))
    assert np.array_equal(a.load(tmp_path / "app.npz").x, cli.x)
    # and "copy as Python" is the make_scene call of the same scene
    python = page.session.lanes and controls.to_python(page.session.params, page.session.run_settings)
    namespace = {}
    exec(python.replace("result = simulate", "_ = None and simulate"), namespace)
    assert namespace["scene"] == cli.scene
    page.session.close()


def test_streamed_samples_are_the_runs_samples():
    from asperity2d.renderers.player import chunk_payload

    page = Page(values=SMALL)
    page.session.handle({"type": "set", "values": SMALL})
    end = page.wait(lambda m: m["type"] == "run-end")
    chunks = [m["chunk"] for m in page.of("run-chunk") if m["job"] == end["job"]]
    assert len(chunks) >= 2
    starts = [c["start"] for c in chunks]
    result = page.session.result
    assert starts[0] == 0 and sum(c["t"]["shape"][0] for c in chunks) == len(result.t)
    import base64

    x = np.concatenate([np.frombuffer(base64.b64decode(c["series"]["x"]["data"]), "<f8") for c in chunks])
    assert np.array_equal(x, result.x)
    assert chunk_payload(result, starts[1])["start"] == starts[1]
    page.session.close()


#: Values no control should take: wrong signs, non-finite, overflow, wrong types, injections,
#: huge texts, device and system files (a surface profile control reads a path).
HOSTILE = ["-1", "nan", "-inf", "1e400", "abc", "'; DROP TABLE", "[[[[[[", "{a = 1}", "\u0000\u202e",
           "9" * 400, "x" * 5000, "/dev/zero", "/etc/passwd"]


def test_hostile_values_give_the_inline_error_and_run_nothing():
    page = Page()
    names = [c["name"] for g in controls.schema()["groups"] for c in g["controls"]] + ["duration", "no_such"]
    refused = 0
    for name in names:
        for text in HOSTILE:
            page.messages.clear()
            page.session.handle({"type": "set", "values": {**SMALL, name: text}})
            reply = page.wait(lambda m: m["type"] in ("invalid", "valid", "error"), timeout=10)
            if reply["type"] == "invalid":
                refused += 1
                (line,) = reply["errors"].values()
                assert "\n" not in line and "Traceback" not in line and len(line) < 600
                assert not line.startswith("unexpected"), (name, text, line)
            else:
                assert reply["type"] == "valid", (name, text, reply)
            page.session.lanes["run"].cancel()
    assert refused > 0.6 * len(names) * len(HOSTILE)
    # a refused value starts nothing
    page.messages.clear()
    page.session.handle({"type": "set", "values": {**SMALL, "mass": "-1"}})
    page.wait(lambda m: m["type"] == "invalid")
    time.sleep(0.3)
    assert not page.of("run-start") and not page.session.lanes["run"].busy
    # messages that are not the protocol are refused in one line too
    for raw in ["not json", "[]", "null", '{"type": 5}', '{"type": "__init__"}', '{"type": "../x"}',
                json.dumps({"type": "set", "values": [1, 2]}), json.dumps({"type": "measure", "name": "rm -rf"}),
                json.dumps({"type": "ensemble", "measure": "critical", "seeds": 10**9, "preset": "spacing"}),
                json.dumps({"type": "variants", "preset": "nope"}), "x" * 300_000]:
        page.messages.clear()
        page.session.handle(raw)
        reply = page.wait(lambda m: m["type"] in ("error", "invalid"), timeout=5)
        assert "Traceback" not in reply.get("message", "")
    page.session.close()


def _runs_alive() -> int:
    gc.collect()
    return sum(1 for o in gc.get_objects() if isinstance(o, Run))


def test_fifty_changes_in_a_second_leave_one_run_and_flat_memory():
    page = Page()
    import tracemalloc

    tracemalloc.start()
    for k in range(50):
        page.session.handle({"type": "set", "values": {**SMALL, "drive_velocity": str(20.0 + k)}})
        time.sleep(0.01)
    # exactly one run computing: the lane's job is the last change's
    lane = page.session.lanes["run"]
    end = page.wait(lambda m: m["type"] == "run-end", timeout=60)
    starts = page.of("run-start")
    assert end["job"] == starts[-1]["job"] == 50
    ended = {m["job"] for m in page.of("run-end")}
    assert ended == {50}, ended  # every other run was cancelled before it finished
    assert page.session.result.scene.drive.velocity == 69.0
    t = time.monotonic()
    while lane.busy:  # the lane lets go of its job just after the job's last message
        time.sleep(0.02)
        assert time.monotonic() - t < 2
    assert _runs_alive() <= 1
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert peak < 200e6  # one run of this scene holds ~1 MB; 50 kept would still be small, so ...
    assert _runs_alive() <= 1  # ... the real check: no cancelled run is kept alive
    page.session.close()


def test_a_measure_streams_progress_and_cancels_at_once():
    page = Page(values=SMALL)
    page.session.handle({"type": "set", "values": SMALL})
    page.session.handle({"type": "measure", "name": "critical"})
    page.wait(lambda m: m["type"] == "measure-progress")
    t = time.monotonic()
    page.session.handle({"type": "cancel", "lane": "measure"})
    page.wait(lambda m: m["type"] == "cancelled")
    while page.session.lanes["measure"].busy:
        time.sleep(0.05)
        assert time.monotonic() - t < 5
    assert not page.of("measure-result")
    page.session.close()


def test_a_measure_gives_the_library_value_with_its_unit():
    from asperity2d.critical import critical_force

    page = Page(values=SMALL)
    page.session.handle({"type": "set", "values": SMALL})
    page.session.handle({"type": "measure", "name": "critical"})
    got = page.wait(lambda m: m["type"] in ("measure-result", "error"), timeout=120)
    assert got["type"] == "measure-result", got
    scene = a.make_scene(lower_count=6, upper_count=2, drive="force")
    assert got["value"] == critical_force(scene) and got["unit"] == "N"
    page.session.close()


# -- the web server ---------------------------------------------------------------------------
@pytest.fixture()
def client():
    sessions = []
    app = create_app(token=TOKEN, hosts={"testserver"}, values=SMALL, sessions=sessions)
    with TestClient(app) as c:
        c.sessions = sessions
        yield c
    for s in sessions:
        s.close()


def test_requests_without_the_token_or_from_elsewhere_are_refused(client):
    assert client.get(f"/?token={TOKEN}").status_code == 200
    assert client.get(f"/assets/app.js?token={TOKEN}").text.startswith("/* asperity2d workbench")
    for path, headers in [("/", {}), ("/?token=wrong", {}), (f"/?token={TOKEN}x", {}),
                          (f"/?token={TOKEN}", {"origin": "http://evil.example"}),
                          (f"/?token={TOKEN}", {"origin": "null"}),
                          (f"/?token={TOKEN}", {"host": "evil.example"}),
                          (f"/?token={TOKEN}", {"host": "127.0.0.1.evil.example"}),
                          ("/assets/app.js", {}), ("/assets/player.js?token=", {})]:
        client.cookies.clear()  # the page's cookie (set by the first request) carries the token
        r = client.get(path, headers=headers)
        assert r.status_code == 403, (path, headers)
        assert TOKEN not in r.text
    # the token as a cookie (what the page's own requests carry) is accepted, a wrong one not
    for cookie, status in ((TOKEN, 200), ("nope", 403)):
        client.cookies.clear()
        client.cookies.set("asperity2d_token", cookie)
        assert client.get("/assets/app.css").status_code == status
    from starlette.websockets import WebSocketDisconnect

    client.cookies.clear()
    for path, headers in [("/ws", {}), ("/ws?token=bad", {}), (f"/ws?token={TOKEN}", {"origin": "http://evil.example"})]:
        with pytest.raises(WebSocketDisconnect):
            with client.websocket_connect(path, headers=headers) as ws:
                ws.receive_text()


def test_the_websocket_speaks_the_protocol_and_closing_stops_the_runs(client):
    with client.websocket_connect(f"/ws?token={TOKEN}", headers={"origin": "http://testserver"}) as ws:
        ws.send_text(json.dumps({"type": "hello"}))
        kinds = []
        while "run-chunk" not in kinds:
            kinds.append(json.loads(ws.receive_text())["type"])
        assert kinds[:5] == ["schema", "measures", "values", "valid", "run-start"]
        ws.send_text(json.dumps({"type": "set", "values": {"lower_count": "-3"}}))
        while (m := json.loads(ws.receive_text()))["type"] != "invalid":
            pass
        assert m["errors"] == {"lower_count": "`lower_count` must be >= 1, got -3"}
        ws.send_text(json.dumps({"type": "set", "values": {**SMALL, "duration": "2e-5"}}))  # a long run (~10 min)
        while (m := json.loads(ws.receive_text()))["type"] != "run-chunk":
            assert m["type"] != "invalid", m
        (session,) = client.sessions
        assert session.lanes["run"].busy
    t = time.monotonic()
    while session.lanes["run"].busy:  # the tab closed: its run stops at its next piece
        time.sleep(0.02)
        assert time.monotonic() - t < 5
    assert session.closed


def test_the_server_binds_loopback_only():
    sock = bind(0)
    try:
        assert sock.getsockname()[0] == "127.0.0.1"
    finally:
        sock.close()


def _listening(port: int) -> set[str]:
    """Local addresses listening on ``port`` (Linux /proc/net/tcp{,6})."""
    out = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        if not os.path.exists(table):
            continue
        for line in Path(table).read_text().splitlines()[1:]:
            local, state = line.split()[1], line.split()[3]
            address, hexport = local.rsplit(":", 1)
            if int(hexport, 16) == port and state == "0A":
                out.add(address)
    return out


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/net/tcp")
def test_explore_serves_on_loopback_prints_one_url_and_stops_on_ctrl_c():
    proc = subprocess.Popen([sys.executable, "-m", "asperity2d", "explore", "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        url = proc.stdout.readline().strip()
        match = re.fullmatch(r"http://127\.0\.0\.1:(\d+)/\?token=([A-Za-z0-9_-]{20,})", url)
        assert match, url
        port = int(match.group(1))
        assert _listening(port) == {"0100007F"}  # 127.0.0.1, nothing else (no 0.0.0.0, no IPv6)
        import httpx

        assert httpx.get(url, timeout=10).status_code == 200
        assert httpx.get(f"http://127.0.0.1:{port}/", timeout=10).status_code == 403
        assert httpx.get(url, headers={"origin": "http://evil.example"}, timeout=10).status_code == 403
        websocket = pytest.importorskip("websocket", reason="websocket-client (selenium's) checks the WebSocket")
        token = match.group(2)
        for ws_url, origin in [(f"ws://127.0.0.1:{port}/ws?token={token}", "http://evil.example"),
                               (f"ws://127.0.0.1:{port}/ws?token=wrong", f"http://127.0.0.1:{port}")]:
            with pytest.raises(websocket.WebSocketBadStatusException) as refused:
                websocket.create_connection(ws_url, origin=origin, timeout=10)
            assert refused.value.status_code == 403
        ok = websocket.create_connection(f"ws://127.0.0.1:{port}/ws?token={token}", origin=f"http://127.0.0.1:{port}",
                                         timeout=10)
        ok.close()
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=20)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "Traceback" not in err and "Error" not in err, err
    assert err.strip().endswith("asperity2d: stopped")


def test_explore_refuses_bad_input_in_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("mass = -1\n")
    assert main(["explore", str(bad), "--no-browser"]) == 2
    assert main(["explore", "--port", "70000", "--no-browser"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[0] == "asperity2d: error: `mass` must be > 0, got -1" and len(err) == 2


# -- the command line around it -----------------------------------------------------------------
def test_run_takes_set_and_says_where_it_wrote(tmp_path, capsys):
    scene = tmp_path / "s.toml"
    scene.write_text('lower_count = 4\nupper_count = 2\n[run]\nduration = 5e-8\n')
    out = tmp_path / "r.npz"
    assert main(["run", str(scene), "--set", "mu_static=0.45", "--set", 'spacing="random"', "--save", str(out)]) == 0
    assert capsys.readouterr().out.strip().endswith(f"wrote {out}")
    r = a.load(out)
    assert r.scene == a.make_scene(lower_count=4, upper_count=2, mu_static=0.45, spacing="random")
    assert main(["run", str(scene), "--set", "mu_static=-1"]) == 2
    assert capsys.readouterr().err.strip() == "asperity2d: error: `mu_static` must be >= 0, got -1"


def test_belt_output_takes_every_extension_render_takes(tmp_path, capsys):
    from asperity2d.cli.belt import outputs
    from asperity2d.renderers import suffixes

    assert set(suffixes("belt")) <= set(outputs())
    chain = tmp_path / "chain.toml"
    chain.write_text('masses = [1.0]\nsprings = [10.0, 0.0]\ndampers = [0.0, 0.0]\nmu_s = 0.3\nv_belt = 0.1\n'
                     'x0 = [0.0]\nv0 = [0.0]\nt_end = 2.0\n')
    for ext, magic in ((".html", b"<!DOCTYPE html>"), (".wav", b"RIFF")):
        path = tmp_path / f"chain{ext}"
        assert main(["belt", str(chain), "-o", str(path)]) == 0, capsys.readouterr().err
        assert path.read_bytes().startswith(magic)
        assert f"wrote {path}" in capsys.readouterr().out


def test_explore_is_a_lazy_public_name_and_import_stays_light():
    code = ("import sys, asperity2d; assert callable(asperity2d.explore); "
            "print(sorted(m for m in ('numpy', 'starlette', 'uvicorn', 'anywidget') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


# -- refusals before any run, on the control typed in ------------------------------------------------
def test_over_budget_values_are_refused_before_any_run_on_the_control_typed_in():
    page = Page()
    for name, text in [("duration", "1e308"), ("upper_count", "100000"), ("mass", "1e308"),
                       ("lower_surface", "/etc/passwd"), ("stop_pitches", "-2"), ("stop_force", "nan")]:
        page.messages.clear()
        page.session.handle({"type": "set", "values": {**SMALL, name: text}, "changed": name})
        reply = page.wait(lambda m: m["type"] in ("invalid", "valid"), timeout=10)
        assert reply["type"] == "invalid" and list(reply["errors"]) == [name], (name, reply)
        time.sleep(0.2)
        assert not page.of("run-start") and not page.session.lanes["run"].busy, name
    # "nan" and "NaN" are one reading, one message
    lines = []
    for text in ("nan", "NaN", "-NaN"):
        page.session.handle({"type": "set", "values": {**SMALL, "mass": text}, "changed": "mass"})
        lines.append(page.wait(lambda m: m["type"] == "invalid")["errors"]["mass"])
        page.messages.clear()
    assert lines[0] == lines[1] == lines[2] == "`mass` must be a finite number, got nan"
    page.session.close()


# -- stop conditions: the API, the [run] table, the workbench -------------------------------------------
def test_stop_conditions_in_the_api_stop_where_they_say():
    from asperity2d.run import FirstSlip, ForceCrossed, stops_from_settings

    scene = a.make_scene(lower_count=4, upper_count=2)
    crossed = simulate(scene, stop=ForceCrossed(5e-3))
    # the first sample at or above 5 mN ends the run; every one before it is below
    assert crossed.status == "force crossed" and crossed.drive_force[-1] >= 5e-3 > crossed.drive_force[:-1].max()
    slipped = simulate(scene, stop=FirstSlip.for_scene(scene))
    (first, *_) = a.stick_slip_events(simulate(scene))
    # the stop lands at the first sample faster than 3 V: inside the event finder's first slip
    assert slipped.status == "first slip" and first.t_slip <= slipped.t[-1] <= first.t_end
    assert slipped.v[-1] > 3 * scene.drive.velocity
    moved = simulate(scene, stop=stops_from_settings(scene, {"stop_pitches": 2}))
    assert moved.status == "travelled" and moved.x[-1] - moved.x[0] >= 2 * 1.25e-6
    for bad in ({"stop_pitches": -1}, {"stop_force": float("nan")}, {"stop_first_slip": "yes"}):
        with pytest.raises(a.SceneError, match="stop_"):
            stops_from_settings(scene, bad)


def test_an_edited_scene_with_a_stop_saves_as_toml_that_run_reproduces_to_the_bit(tmp_path, capsys):
    """Per-asperity stiffness, a moved asperity (ExplicitSpacing) and "stop at the first slip":
    the TOML the workbench saves, and its "Copy as Python", give its run to the bit."""
    page = Page()
    values = {**SMALL, "stiffness": "[50000.0, 37200.0, 37200.0, 37200.0, 37200.0, 37200.0]",
              "lower_positions": "[-6.25e-7, 1.25e-6, 2.5e-6, 3.75e-6, 5e-6, 6.25e-6]", "drive_velocity": "10",
              "stop_first_slip": "true"}
    page.session.handle({"type": "set", "values": values, "changed": "stop_first_slip"})
    end = page.wait(lambda m: m["type"] == "run-end", timeout=120)
    assert end["summary"]["status"] == "first slip"
    page.session.handle({"type": "export", "what": "toml"})
    path = tmp_path / "edited.toml"
    path.write_text(page.wait(lambda m: m["type"] == "export")["text"])
    assert main(["run", str(path), "--save", str(tmp_path / "cli.npz")]) == 0
    cli, app = a.load(tmp_path / "cli.npz"), page.session.result
    assert cli.status == "first slip" and cli.scene.lower.spacing.positions[0] == -6.25e-7
    for name in ARRAYS:
        assert np.array_equal(getattr(cli, name), getattr(app, name)), name
    namespace = {}
    exec(controls.to_python(page.session.params, page.session.run_settings), namespace)
    assert np.array_equal(namespace["result"].x, app.x) and namespace["scene"] == app.scene
    # an asperity moved onto its neighbour: refused on the edit, nothing runs
    page.messages.clear()
    page.session.handle({"type": "set", "values": {**values, "lower_positions": "[0, 5e-7, 2.5e-6, 3.75e-6, 5e-6, 6.25e-6]"},
                         "changed": "lower_positions"})
    reply = page.wait(lambda m: m["type"] in ("invalid", "valid"))
    assert list(reply["errors"]) == ["lower_positions"] and "overlap" in reply["errors"]["lower_positions"]
    page.session.close()


# -- the ensemble: interleaved per seed, one p text, workers gone with the tab ------------------------
def test_the_ensemble_interleaves_variants_per_seed_and_formats_p_once():
    from asperity2d.app.jobs import verdict  # noqa: F401 -- the row the page shows

    page = Page(workers=1)
    page.session.handle({"type": "set", "values": SMALL})
    page.wait(lambda m: m["type"] == "run-end", timeout=60)
    page.session.handle({"type": "ensemble", "measure": "first-breakaway", "seeds": 3, "preset": "spacing"})
    page.wait(lambda m: m["type"] == "ensemble-end", timeout=300)
    values = [(m["variant"], m["seed"]) for m in page.of("ensemble-value")]
    assert values == [("regular", 0), ("random", 0), ("regular", 1), ("random", 1), ("regular", 2), ("random", 2)]
    kinds = [m["type"] for m in page.messages if m["type"].startswith("ensemble-")]
    assert kinds.index("ensemble-stats") == kinds.index("ensemble-value") + 4  # from the second seed on
    for stats in page.of("ensemble-stats"):
        (row,) = stats["versus"]
        assert row["p_text"] == f"{row['p_wilcoxon']:.2g}" and f"p = {row['p_text']}" in row["line"]
    page.session.close()


def test_closing_the_tab_stops_the_ensembles_worker_processes():
    from asperity2d.sweep.executors import _pools, warm_pools

    page = Page(workers=2)
    page.session.handle({"type": "set", "values": SMALL})
    page.session.handle({"type": "ensemble", "measure": "first-breakaway", "seeds": 2, "preset": "spacing"})
    page.wait(lambda m: m["type"] == "ensemble-end", timeout=300)
    assert 2 in warm_pools()
    workers = list(_pools[2]._processes.values())
    assert workers and all(p.is_alive() for p in workers)
    page.session.close()
    end = time.monotonic() + 30
    while (2 in warm_pools() or any(p.is_alive() for p in workers)) and time.monotonic() < end:
        time.sleep(0.1)
    assert 2 not in warm_pools() and not any(p.is_alive() for p in workers)


# -- the ensemble with seeds="auto": stages until decided, as compare(seeds="auto") ---------------------
def smallest_gap(scene):
    """A measure that needs no run (the closest two lower tips): random spacing lowers it on every
    seed, so the first look decides."""
    return float(np.min(np.diff(scene.lower.tips())))


def first_gap(scene):
    """The first two tips' gap: random spacing moves it either way, too little to decide in 30 seeds."""
    tips = scene.lower.tips()
    return float(tips[1] - tips[0])


@pytest.mark.parametrize("fn, max_seeds", [pytest.param(smallest_gap, 30, marks=pytest.mark.slow), (first_gap, 30)])
def test_the_ensemble_with_auto_seeds_decides_as_compare_does(monkeypatch, fn, max_seeds):
    """The page's ``seeds: "auto"`` takes the stages, the looks and the verdicts of
    ``asperity2d.compare(seeds="auto", max_seeds=...)``, streams an interim line from the second
    seed, and says how many more seeds an undecided verdict wants. Measures that need no run keep
    it to ~3 s on a loaded machine (most of it the design's boundaries): what is tested is the
    staging, not a measure. The case decided at the first look is marked slow."""
    from asperity2d.app import session as session_module
    from asperity2d.experiments.measures import Measure, register_measure, unregister_measure

    register_measure(Measure(fn.__name__, fn, fn.__name__.replace("_", " "), unit="m"), replace=True)
    monkeypatch.setattr(session_module, "OFFERED", (*session_module.OFFERED, fn.__name__))
    try:
        base = {"lower_count": 6, "upper_count": 2}
        api = a.compare(fn.__name__, {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}}, "auto",
                        max_seeds=max_seeds, base=base, progress=False, workers=1)
        page = Page(workers=1)
        page.session.handle({"type": "set", "values": {k: str(v) for k, v in base.items()}})
        page.session.handle({"type": "cancel", "lane": "run"})  # the scene's run is not what is tested
        page.session.handle({"type": "ensemble", "measure": fn.__name__, "seeds": "auto", "max_seeds": max_seeds,
                             "preset": "spacing"})
        end = page.wait(lambda m: m["type"] == "ensemble-end", timeout=120)
        page.session.close()
    finally:
        unregister_measure(fn.__name__)
    start = page.of("ensemble-start")[-1]
    assert start["design"]["stages"] == api.design["stages"] and start["reference"] == "regular"
    stages = page.of("ensemble-stage")
    assert [s["seeds"] for s in stages] == [look["seeds"] for look in api.design["looks"]]
    assert end["seeds_done"] == len(api.seeds) and end["looks"] == len(api.design["looks"])
    values = {v: [m["value"] for m in page.of("ensemble-value") if m["variant"] == v] for v in api.values}
    assert values == {v: list(x) for v, x in api.values.items()}  # the same numbers, seed by seed
    stats = page.of("ensemble-stats")
    assert stats[0]["seeds_done"] == 2 and stats[0]["look"]["interim"]  # the line fills in from the second seed
    looks = [m for m in stats if not m["look"].get("interim")]
    assert [m["versus"][0]["verdict"] for m in looks] == [look["verdicts"]["random"] for look in api.design["looks"]]
    final = looks[-1]["versus"][0]
    record = api.verdict("random", "regular")
    assert final["line"] == verdict_line_of(record) and end["decided"] == (record["verdict"] != "undecided")
    if record["verdict"] == "undecided":  # spent the budget: about how many more seeds would decide it
        assert final["more"] == record["numbers"]["seeds_needed"] - len(api.seeds) > 0
    else:
        assert len(api.seeds) < max_seeds  # decided before the budget was spent: it stopped there


def verdict_line_of(record):
    from asperity2d.experiments.verdicts import verdict_line

    return verdict_line(record)


def test_the_ensemble_refuses_a_bad_seed_budget_in_one_line():
    page = Page(workers=1)
    for message, text in [({"seeds": "auto", "max_seeds": 1}, "`max_seeds` must be a whole number from 2 to 200"),
                          ({"seeds": "many"}, "`seeds` must be a whole number from 2 to 200 or 'auto'"),
                          ({"seeds": "auto", "max_seeds": 20, "stage_seeds": 30}, "`stage_seeds` must be a whole number from 2 to 20")]:
        page.session.handle({"type": "ensemble", "measure": "first-breakaway", "preset": "spacing", **message})
        error = page.wait(lambda m: m["type"] == "error")
        assert error["message"].startswith(text), error
        page.messages.clear()
    page.session.close()


# -- the slider's start: a scene field, set on the stage ---------------------------------------------
def test_slider_start_moves_the_first_contact_by_its_distance_over_the_drive_speed(tmp_path):
    """``slider_start`` is where the slider's rear tip is at t = 0; starting d farther left on the
    fixed track, the spring-driven slider meets the surface d / v later. The drive spring from
    rest leaves the slider oscillating about the drive end's steady lag with amplitude v / omega
    (omega = sqrt(k / M), undamped): each run's contact time is off its steady one by at most
    1 / omega, so the two differ from d / v by at most 2 / omega (1.8 ns here), plus a sample."""
    import dataclasses
    import math

    def first_contact(result):
        return result.t[np.argmax(np.abs(result.normal_force) > 0)]

    scene = a.make_scene(lower_count=6, upper_count=2)
    here = a.simulate(scene, 3e-7)
    start = -4e-6
    moved = scene.replace(slider=dataclasses.replace(scene.slider, start=start))
    there = a.simulate(moved, 3e-7)
    assert a.Scene.from_toml(moved.to_toml(tmp_path / "moved.toml")) == moved  # the whole-scene file keeps it
    assert there.x[0] == start and here.x[0] < 0  # the rear tip there at t = 0 (the set-up's start otherwise)
    d, v = float(here.x[0]) - start, scene.drive.velocity
    omega = math.sqrt(scene.drive.stiffness / scene.slider.mass)
    assert abs((first_contact(there) - first_contact(here)) - d / v) <= 2 / omega + (here.t[1] - here.t[0])
    assert a.make_scene(lower_count=6, upper_count=2, slider_start=start).slider.start == start
    for bad, says in [(1e-6, "`slider_start` (1e-06 m) puts the fixed-track slider's front tip over the lower surface"),
                      (math.nan, "`slider_start` must be a finite number")]:
        with pytest.raises(a.SceneError, match=re.escape(says)):
            a.make_scene(lower_count=6, upper_count=2, slider_start=bad)
    with pytest.raises(a.SceneError, match="past the last lower tip"):
        a.make_scene(lower_count=6, upper_count=2, track="free", slider_start=7e-6)


def test_a_slider_start_set_on_the_page_saves_as_toml_and_python_that_reproduce_the_run(tmp_path, capsys):
    page = Page()
    page.session.handle({"type": "set", "values": {**SMALL, "slider_start": "-3.1e-06", "duration": "1.5e-7"}})
    valid = page.wait(lambda m: m["type"] == "valid")
    assert valid["bodies"]["slider"]["start"] == -3.1e-06  # the stage's panel shows it
    page.wait(lambda m: m["type"] == "run-end")
    app = page.session.result
    assert app.x[0] == -3.1e-06
    page.session.handle({"type": "export", "what": "toml"})
    (tmp_path / "scene.toml").write_text(page.wait(lambda m: m["type"] == "export")["text"])
    assert main(["run", str(tmp_path / "scene.toml"), "--save", str(tmp_path / "cli.npz")]) == 0
    cli = a.load(tmp_path / "cli.npz")
    for name in ARRAYS:
        assert np.array_equal(getattr(cli, name), getattr(app, name)), name
    namespace = {}
    exec(controls.to_python(page.session.params, page.session.run_settings).replace("result = simulate", "_ = None and simulate"),
         namespace)
    assert namespace["scene"] == cli.scene and cli.scene.slider.start == -3.1e-06
    assert controls.params_of(cli.scene)["slider_start"] == -3.1e-06  # explore(scene) starts from it too
    # a start over the surface on the fixed track: one line on that control, nothing runs
    page.messages.clear()
    page.session.handle({"type": "set", "values": {**SMALL, "slider_start": "1e-6"}, "changed": "slider_start"})
    invalid = page.wait(lambda m: m["type"] == "invalid")
    assert list(invalid["errors"]) == ["slider_start"] and not page.of("run-start")
    page.session.close()
