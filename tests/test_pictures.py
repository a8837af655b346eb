"""What the animation frames show, checked on their pixels against the result's arrays.

Each check would fail if the picture were wrong: a body drawn at the wrong place (the pixel
where the arrays put it has another colour), a meter cursor off its time, a trace that does
not grow, a slip without frames, a missing STICK/SLIP badge or slow-motion mark. Positions
come from the result (and the scene's own geometry); only the camera (left edge, scale) is
the renderer's, and it is itself checked to keep the slider and the drive block in view.
"""

import math

import numpy as np
import pytest
from PIL import Image, ImageSequence

import asperity2d as a
from asperity2d._format import number, prefixed, si
from asperity2d.belt import simulate_chain
from asperity2d.belt.presets import preset
from asperity2d.renderers import raster, render
from asperity2d.renderers.animate import Movie
from asperity2d.renderers.notebook import rest_record
from asperity2d.renderers.stage import FOOTER, HEADER, Stage
from asperity2d.renderers.timeline import schedule, slip_intervals

I = raster.INDEX


@pytest.fixture(scope="module")
def run(stick_slip_run):
    return stick_slip_run


@pytest.fixture(scope="module")
def movie_frames(run):
    movie = Movie(run, frames=90)
    return movie, [np.asarray(f) for f in movie.frames()]


@pytest.fixture(scope="module")
def chain():
    return simulate_chain(**preset("table2-3dof"))


def slipping(run, t):
    """Independent of the renderer: inside an event's slip (t_slip, t_end]."""
    return any(e.t_slip < t <= e.t_end for e in a.stick_slip_events(run))


# -- frame times ----------------------------------------------------------------------------------
def test_every_slip_gets_frames_in_slow_motion_where_uniform_frames_give_few(run, movie_frames):
    movie, _ = movie_frames
    events = [e for e in a.stick_slip_events(run) if e.complete]
    assert len(events) >= 2  # the detector's count since issue 25 (slips that move 0.1 base)
    times, slow = movie.schedule.time, movie.schedule.slow
    uniform = schedule(run.t, slip_intervals(run), 90, timing="uniform").time
    ours = theirs = 0
    for e in events:
        inside = (times > e.t_slip) & (times < e.t_end)
        assert inside.sum() >= 3, f"slip at {e.t_slip:.3e} s has {inside.sum()} frames"
        assert np.all(slow[inside] > 1)  # each one marked "×N slow"
        ours += inside.sum()
        theirs += np.count_nonzero((uniform > e.t_slip) & (uniform < e.t_end))
    assert ours >= 3 * theirs  # evenly spaced frames give the slips two or none each
    assert np.all(slow[[0, -1]] >= 1) and np.all(np.diff(times) >= 0)
    # frames are the recorded samples' own times (picture and cursor agree)
    np.testing.assert_array_equal(times, run.t[movie.schedule.index])


def test_slow_factor_is_the_ratio_of_frame_steps(run):
    """A slowed frame step is the normal step divided by the factor shown (to a recorded sample)."""
    plan = schedule(run.t, slip_intervals(run), 400)
    assert plan.intervals
    for start, end, factor in plan.intervals:
        inside = np.flatnonzero((plan.time > start + 0.1 * (end - start)) & (plan.time < end - 0.1 * (end - start)))
        if len(inside) < 4:
            continue
        steps = np.diff(plan.time[inside])
        sample = float(np.median(np.diff(run.t)))
        # each frame time is rounded to the nearest sample: one sample of slack per step
        assert np.median(steps) == pytest.approx(plan.normal_step / factor, abs=sample)


def test_main_job_slips_move_the_slider_less_than_a_pitch_per_frame():
    """The main job's run (scenes/quickstart.py: the default scene, 120 frames): no frame inside a
    slip moves the slider a pitch or more past the previous one -- the tips are seen to climb the
    flanks. (Before, its largest slip had 4 frames, one a jump of 6.5 pitches.)"""
    run = a.simulate(a.make_scene())
    pitch = run.scene.lower.spacing.mean_pitch
    plan = Movie(run).schedule  # render(run, "run.gif")'s own frames
    assert len(plan) == 120 and plan.coarse_reason == ""
    jumps = np.abs(np.diff(run.x[plan.index])) / pitch  # independent of the schedule's own record
    np.testing.assert_allclose(jumps, plan.jumps[1:])
    events = a.stick_slip_events(run)
    largest = max(events, key=lambda e: e.slip_distance)
    assert largest.slip_distance > 5 * pitch  # a slip over several asperities
    for e in events:
        # frames from the last one before the slip to the first one after it
        inside = np.flatnonzero((plan.time > e.t_slip) & (plan.time <= e.t_end))
        span = np.arange(max(inside[0] - 1, 0), min(inside[-1] + 2, len(plan)))
        assert np.max(jumps[span[:-1]]) < 1.0, f"slip at {e.t_slip:.3e} s: a frame jumps {np.max(jumps[span[:-1]]):.2f} pitches"
        assert len(inside) >= e.slip_distance / pitch  # at least a frame per pitch travelled
        assert np.all(plan.slow[inside[:-1]] > 1)
    # the frames are still recorded samples, in order
    assert np.all(np.diff(plan.time) >= 0) and np.array_equal(plan.time, run.t[plan.index])


def test_too_few_frames_for_a_slip_say_so_in_the_frame(run):
    movie = Movie(run, frames=8)
    plan = movie.schedule
    assert plan.coarse_reason.startswith("8 frames are too few")
    j = int(np.argmax(plan.jumps))
    assert plan.jumps[j] > 1.0
    for k in range(j + 1):
        img = movie.frame(k)
    assert movie.drawn["note"].startswith(f"moved {plan.jumps[j]:.1f} pitches since the last frame")
    row = np.asarray(img)[HEADER:HEADER + 16, :300]
    red = raster.RAMPS["slider_slip", "white"] + raster.LEVELS - 1  # the text colour's own entry
    assert np.count_nonzero(row == red) > 20  # the note is written, in red


def test_meter_marks_a_value_off_its_axis():
    """The velocity meter's axis ends below the peak slip speed: the read-out says so and the
    cursor's marker is an arrowhead on the plot's top edge, in the trace's colour."""
    from asperity2d.renderers.meters import MeterPanel, asperity_meters

    run = a.simulate(a.make_scene(lower_count=8))
    meter = asperity_meters(run)[3]
    assert meter.title == "slider velocity"
    k = int(np.argmax(run.v))
    assert run.v[k] > meter.limits[1]  # the robust axis clips the peak
    panel = MeterPanel(meter, (0, 0, 359, 139), run.t)
    img = raster.new(360, 140, "panel")
    panel.draw_static(img)
    panel.advance(img, float(run.t[k]))
    panel.draw_now(img, k)
    px = np.asarray(img)
    cx, top = int(panel.x_of(run.t[k])), panel.plot[1]
    assert px[top + 4, cx] == I[meter.traces[0].colour]  # inside the arrowhead under the edge
    # the read-out ("▲ <value> off axis") is written in the trace's colour at the title row's right end
    right = px[2:18, 200:359]
    ink = raster.RAMPS[meter.traces[0].colour, "panel"] + raster.LEVELS - 1
    assert np.count_nonzero(right == ink) > 30
    assert panel.off_axis[0][panel.column(run.t[k])] == 1


# -- bodies where the arrays put them -------------------------------------------------------------
@pytest.mark.parametrize("which", ["first", "slip", "stick", "last"])
def test_slider_and_lower_asperities_drawn_at_their_recorded_positions(run, movie_frames, which):
    movie, frames = movie_frames
    plan, stage = movie.schedule, movie.stage
    j = {"first": 0, "last": len(plan) - 1,
         "slip": int(np.flatnonzero(plan.slow > 1)[len(np.flatnonzero(plan.slow > 1)) // 2]),
         "stick": int(np.flatnonzero(plan.slow == 1)[len(np.flatnonzero(plan.slow == 1)) // 2])}[which]
    k = int(plan.index[j])
    img = frames[j]
    scene = run.scene
    left, right = (float(np.ravel(r)[i]) for r, i in zip(scene.slider.runs(), (0, -1)))
    rear = scene.slider.tips()[0] - left
    front = scene.slider.tips()[-1] + right
    # the slider's bar: the pixel at its centre, from x and y of the record
    cx, cy = stage.to_px(run.x[k] + 0.5 * (rear + front), run.y[k], k)
    py = int(cy - stage.bar_px / 2)
    colour = "slider_slip" if slipping(run, run.t[k]) else "slider_stick"
    assert img[py, int(cx)] == I[colour], f"frame {j}: slider bar not at x = {run.x[k]:.4g} m"
    # a base to the left of its rear end there is no bar (a misplaced slider would show)
    bx = int(stage.to_px(run.x[k] + rear - scene.base, 0.0, k)[0])
    if bx >= 0:
        assert img[py, bx] not in (I["slider_slip"], I["slider_stick"])
    # the camera keeps the slider and the drive block in view
    assert 0 <= stage.to_px(run.x[k] + rear, 0.0, k)[0] and stage.to_px(run.drive_x[k], 0.0, k)[0] < movie.width
    # every lower asperity in view: the pixel a third of the way up from its base centre
    checked = 0
    for i, tip in enumerate(scene.lower.tips()):
        h = scene.lower.profile.height
        px, py = stage.to_px(tip + run.lower_dx[i, k], run.lower_dy[i, k] + h / 3, k)
        if not (5 < px < movie.width - 5):
            continue
        expected = "touching" if run.lower_contact[i, k] else "lower"
        # the upper tips may cover a touching asperity's apex, never the lower third
        assert img[int(py), int(px)] == I[expected], f"frame {j}: lower asperity {i}"
        checked += 1
    assert checked >= 2


def test_camera_keeps_the_drive_block_in_view_and_moves_only_when_it_must(run, movie_frames):
    movie, _ = movie_frames
    stage, idx = movie.stage, movie.schedule.index
    lefts = stage.lefts[idx]
    ends = stage.drive_end[idx]
    assert np.all((ends - lefts) * stage.scale < movie.width)
    moves = np.abs(np.diff(lefts)) > 0
    assert 0 < moves.sum() < len(idx) - 1  # it moves, but not every frame (a lazy camera)


def test_contact_forces_are_arrows_on_the_touching_tips_summing_to_the_record(run, movie_frames):
    movie, frames = movie_frames
    stage = movie.stage
    hits = 0
    for j, k in enumerate(movie.schedule.index):
        shapes = stage.shapes(int(k))
        if not shapes["arrows"]:
            assert not run.lower_contact[:, k].any() or run.friction_force[k] == run.normal_force[k] == 0
            continue
        fx = sum(x1 - x0 for x0, _, x1, _ in shapes["arrows"]) / stage.newton_px
        fy = sum(y0 - y1 for _, y0, _, y1 in shapes["arrows"]) / stage.newton_px
        assert fx == pytest.approx(-run.friction_force[k], rel=1e-9, abs=1e-15)
        assert fy == pytest.approx(run.normal_force[k], rel=1e-9, abs=1e-15)
        tips = [shapes["tips"][i] for i in np.flatnonzero(run.lower_contact[:, k])]
        assert {(x0, y0) for x0, y0, _, _ in shapes["arrows"]} <= set(tips)
        long = [ar for ar in shapes["arrows"] if math.hypot(ar[2] - ar[0], ar[3] - ar[1]) > 6]
        for x0, y0, x1, y1 in long:  # the arrow's colour half way along it (a 2-px line: 3 x 3 px)
            mx, my = int(round((x0 + x1) / 2)), int(round((y0 + y1) / 2))
            assert np.any(frames[j][my - 1:my + 2, mx - 1:mx + 2] == I["arrow"])
            hits += 1
    assert hits > 0


# -- meters ---------------------------------------------------------------------------------------
def test_meter_cursor_sits_at_the_frame_time_and_traces_grow(run, movie_frames):
    movie, frames = movie_frames
    for j in (3, len(frames) // 2, len(frames) - 1):
        k = int(movie.schedule.index[j])
        img = frames[j]
        for panel in movie.meters:
            px0, py0, px1, py1 = panel.plot
            expected = px0 + round((run.t[k] - run.t[0]) / (run.t[-1] - run.t[0]) * (px1 - px0))
            # the cursor: the one column dark over (nearly) the whole plot height
            dark = np.count_nonzero(img[py0:py1 + 1, px0:px1 + 1] == I["cursor"], axis=0)
            cursor = np.flatnonzero(dark > 0.8 * (py1 - py0)) + px0
            assert list(cursor) == [expected]
            colours = [I[tr.colour] for tr in panel.meter.traces]
            ahead = img[py0:py1 + 1, expected + 5:px1 + 1]
            assert not np.isin(ahead, colours).any(), "a trace is drawn ahead of the cursor"
            if expected - px0 > 20:
                behind = img[py0:py1 + 1, px0 + 1:expected - 4]
                assert np.isin(behind, colours).any(), "no trace behind the cursor"


def test_meter_axes_are_in_engineering_units(run, movie_frames):
    movie, _ = movie_frames
    units = {panel.meter.title: panel.unit_label for panel in movie.meters}
    assert units["drive force"] == "mN" and units["position"] == "µm"
    assert units["slider velocity"] in ("m/s", "km/s") and movie.meters[0].tunit == "ns"


def test_header_shows_slip_and_slow_motion_and_time(run, movie_frames):
    movie, frames = movie_frames
    plan = movie.schedule
    for j in range(len(frames)):
        header = frames[j][:HEADER]
        t = run.t[plan.index[j]]
        assert np.any(header == I["slip_bg"]) == slipping(run, t)
        assert np.any(header == I["stick_bg"]) == (not slipping(run, t))
        slow_text = np.any(header[:, 230:600] == raster.RAMPS["spring", "white"] + raster.LEVELS - 1)
        assert slow_text == (plan.slow[j] > 1)
        assert movie.stage.shapes(int(plan.index[j]))["time"] == f"t = {si(t, 's', 4)}"


def test_scale_bar_has_its_labelled_length(run, movie_frames):
    movie, frames = movie_frames
    stage = movie.stage
    row = frames[0][int(stage.height - FOOTER / 2)]
    black = np.flatnonzero(row[:400] == I["black"])
    length = raster.nice_length(80.0 / stage.scale)
    assert black[0] == 10 and abs((black[-1] - black[0]) - length * stage.scale) <= 1.5
    assert si(length, "m", 1) in ("1 µm", "2 µm", "500 nm")


def test_shallow_surface_is_exaggerated_and_labelled():
    """Summits much lower than their base: heights drawn N times taller, labelled 'vertical ×N'."""
    scene = a.make_scene(lower_count=6, upper_count=2, height=0.05e-6)  # 1 µm bases, 50 nm high
    stage = Stage(rest_record(scene), width=720, height=240, camera="whole")
    assert stage.exaggeration >= 2
    img = raster.new(720, stage.height)
    stage.paint_static(img)
    stage.paint(img, stage.shapes(0))
    pixels = np.asarray(img)
    tip = scene.lower.tips()[2]
    column = pixels[:, int(stage.to_px(tip, 0.0, 0)[0])]
    drawn = np.count_nonzero(column == I["lower"])
    assert drawn == pytest.approx(0.05e-6 * stage.scale * stage.exaggeration, abs=2)
    assert 0.05e-6 * stage.scale < 6  # without exaggeration a sliver of a few px
    plain = Stage(rest_record(scene), width=720, height=240, camera="whole", exaggeration=1)
    assert plain.exaggeration == 1
    default = Stage(rest_record(a.make_scene(lower_count=6, upper_count=2)), width=720, height=240, camera="whole")
    assert default.exaggeration == 1  # 45° flanks are drawn true


def test_text_is_antialiased_truetype():
    assert raster.font(12).getname()[0].startswith("DejaVu")
    img = raster.new(120, 30)
    raster.draw_text(img, (4, 4), "t = 12.3 ns", size=13)
    used = set(np.unique(np.asarray(img)))
    ramp = set(range(raster.RAMPS["black", "white"], raster.RAMPS["black", "white"] + raster.LEVELS))
    assert len(used & ramp) >= 3  # intermediate grey levels, not 1-bit glyphs


def test_gif_size_budget_and_showcase_scale(run, tmp_path):
    path = render(run, tmp_path / "run.gif")
    assert path.stat().st_size < 2e6
    with Image.open(path) as im:
        assert im.n_frames == 120


# -- belt chains ----------------------------------------------------------------------------------
def test_chain_masses_drawn_where_x_says_in_their_state_colour(chain, tmp_path):
    path = render(chain, tmp_path / "chain.gif", frames=30)
    movie = Movie(chain, frames=30)
    stage = movie.stage
    colours = {0: "mass_stick", 1: "mass_fast", -1: "mass_slow"}
    decoded = [np.asarray(f.convert("RGB")) for f in ImageSequence.Iterator(Image.open(path))]
    assert len(decoded) == 30
    for j in (0, 10, 29):
        k = int(movie.schedule.index[j])
        for i in range(chain.n):
            px = stage.rest[i] + chain.x[i, k] * stage.scale  # the record's x, the stage's scale
            py = stage.box_top + 0.85 * stage.box_h  # below the mass's label
            colour = colours[int(chain.state[i, k])]
            assert tuple(decoded[j][int(py), int(round(px))]) == raster.COLOURS[colour]
            off = int(round(px + 0.5 * stage.box_w + 4))  # just right of the block: not the block
            assert tuple(decoded[j][int(py), off]) != raster.COLOURS[colour]


def test_chain_belt_moves_between_frames(chain):
    movie = Movie(chain, frames=20)
    marks = [movie.stage.shapes(int(k))["marks"][1] for k in movie.schedule.index[:5]]
    V = chain.chain.v_belt
    dt = np.diff(chain.t[movie.schedule.index[:5]])
    expected = (np.array(marks[:1]) + np.cumsum(V * dt * movie.stage.scale)) % 24.0
    np.testing.assert_allclose(np.array(marks[1:]) % 24.0, expected % 24.0, atol=1e-6)


@pytest.mark.parametrize("suffix", [".html", ".png", ".wav", ".mp4"])
def test_chain_renders_through_render(chain, tmp_path, suffix):
    if suffix == ".mp4":
        pytest.importorskip("imageio_ffmpeg")
    path = render(chain, tmp_path / f"chain{suffix}", **({"frames": 8} if suffix == ".mp4" else {}))
    assert path.stat().st_size > 1000


# -- the formatter ----------------------------------------------------------------------------------
@pytest.mark.parametrize("value, unit, text", [
    (0.03452, "N", "34.5 mN"), (1.25e-6, "m", "1.25 µm"), (999.96e-6, "N", "1.00 mN"), (0, "s", "0 s"),
    (2e4, "m/s", "20.0 km/s"), (-1.5e-9, "s", "-1.50 ns"), (2.88e-16, "kg", "288 fg"),
    (3720.0, "N/m", "3.72 kN/m"), (5e-3, "m/s", "5.00 mm/s"), (float("nan"), "N", "nan N"), (12.0, "", "12.0")])
def test_si(value, unit, text):
    assert si(value, unit) == text


def test_si_trim_digits_and_prefixed():
    assert si(1e-6, "m", trim=True) == "1 µm" and si(0.0346, "N", 2) == "35 mN"
    assert prefixed(0.0345, "N") == (1e-3, "mN") and prefixed(3e-6, "m") == (1e-6, "µm")
    assert prefixed(2e-16, "kg") == pytest.approx((1e-18, "fg"))
    assert number(0.000123) == "0.000123"
    with pytest.raises(ValueError, match="`digits`"):
        si(1.0, "m", 0)
