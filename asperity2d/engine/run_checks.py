"""Physical validity of an asperity run: what a result must never show (part of the adapter).

The divergence guard (:mod:`.recorder`: kinetic energy against what the scene held and was
given, overlap) catches runs that blow up. A run can stay finite and within its energy books
and still be impossible: a slider driven so hard that it moves farther in one step than the
asperities it should collide with passes them untouched (the drive really did the work, so the
energy guard is content), and a free slider pressed harder than its lower springs can carry
falls through the surface and the guard floor below it, for ever. This module holds the checks
that make such runs raise instead of returning a normal result, in two kinds:

Prevention (before anything is built, :func:`check_scene`): :class:`~asperity2d.errors.SceneError`
naming the parameter, for a scene whose step cannot resolve the motion its drive or load
imposes (the speed gained over one pitch, or one asperity height of fall, or released by the
drive's preload, times ``dt``, against the feature it must not skip), and for a free slider
whose load (``normal_load`` plus its weight) exceeds what the lower springs under it can carry
within their travel (:func:`load_capacity`).

Detection (at every sample, :class:`Validity`, called by the recorder beside the divergence
guard): :class:`~asperity2d.errors.SimulationError` naming what happened and what to change, when

* **step resolution** -- the slider, or a lower asperity, moves farther in one step than
  :data:`STEP_FRACTION` of the smallest feature it could collide with, while the slider is
  over the surface (its speed at the sample, and its mean displacement per step since the
  last sample, which no spike between samples can hide);
* **floor** -- a free slider's tips are below the guard floor (the bottom of the lower
  tracks) by more than :data:`FLOOR_TOLERANCE` bases: it has fallen through the surface;
* **contacts** -- on a fixed track, an upper tip passed over a lower asperity that stood at
  rest across its path (its tip above the upper tip's path) and left it exactly at rest: it
  went through without touching it (a touch always moves a sloped asperity).

Each check keeps its worst value; :meth:`Validity.report` is what ``result.meta["checks"]``
holds (``summary()`` shows it). Measured cost: see ``benchmarks/bench_core.py`` (a few
microseconds per sample, against tens per step).
"""

from __future__ import annotations

import math
from bisect import bisect_right

import numpy as np

from ..errors import SceneError, SimulationError

#: Largest displacement in one step, as a fraction of the smallest feature a body could
#: collide with (on a fixed track: the width of the window in which an upper tip overlaps a
#: lower one, a quarter of the base for Ooten's 45° triangles at a quarter height's
#: interference). A step of a whole window can skip a contact entirely. Measured over the
#: whole default test suite (every scene script, study and fuzzed scene): at most 0.55 of it
#: (a constant force of 2.5x the default on 4 asperities, whose pass time still agrees with
#: dt/8 to 0.1 %); the reproducers of issue 27 moved 1e4 - 1e9 windows a step. At 0.8 a pass
#: was already 10 % off its converged time, so the limit leaves little to spare on purpose.
STEP_FRACTION = 1.0
#: Past this fraction a result is returned, but marked degraded (``success`` False, a warning in
#: its message): the contacts are resolved by too few steps to trust the forces to 10 %.
STEP_WARNING = 0.75
#: Up-front refusal: the estimated displacement per step may reach this many features (the
#: estimate is a plausible speed, not a bound: only scenes that surely skip are refused).
PREVENT_FRACTION = 1.0
#: How far (asperity bases) a free slider's tips may sink below the guard floor: the floor
#: carries a resting slider with 1-2 % overlap; half a base is the divergence guard's limit.
FLOOR_TOLERANCE = 0.5
#: A lower tip must stand this far (bases) above an upper tip's path for a crossing to be a
#: certain touch (well above the collision slop of 1e-3 bases).
CROSS_MARGIN = 1e-2
#: The tunnelling check's filter (:meth:`Validity._clear_around`): at most this many (lower apex,
#: upper tip) pairs are listed (a Python list of floats, ~32 B each: 3.2 MB at most, built once and
#: shared by forks; a larger scene runs the exact check at every sample, as without the filter);
#: an interval must clear each by this fraction of the positions' magnitude (float64 sums are
#: within ~1e-16 of it) to skip the exact check.
EVENTS = 100_000
EVENT_MARGIN = 1e-9


# -- the end of the surface ------------------------------------------------------------------------
def surface_end(engine) -> tuple[float, int, float]:
    """Where the slider leaves the far end of the lower surface (internal units).

    Returns ``(slider_x, lower, edge)``: the slider position past which the rear end of its
    contact face (a flat block's face, a triangle's tip) is beyond ``edge``, the far end of the
    face of lower asperity ``lower`` (the one that reaches farthest in +x): from there on no face
    is under it, and a free slider tips off the edge and falls to the guard floor (a flat block at
    mu 0.5 / 0.35 under 9 mN: a normal-force spike of 58 x its load). Never before the ``Passed``
    stop's position (rear tip half a base past the last apex), so a run that stops on passing
    ends as before.
    """
    from ..geometry import outline

    scene, layout, u = engine.scene, engine.layout, engine.units

    def face(surface, upper):  # each asperity's face extent (m) about its tip: the vertices at the tip
        shapes, kind = surface.shape_set(), surface.profile.kind
        out = []
        for poly in shapes.vertices(kind, upper=upper):
            tip = min(y for _, y in poly) if upper else max(y for _, y in poly)
            xs = [x for x, y in poly if y == tip]
            out.append((min(xs), max(xs)))
        return np.array(out) / u.length

    lower, upper = face(scene.lower, False), face(scene.slider, True)
    ends = np.asarray(layout.lower_apex_x, dtype=float) + lower[:, 1]
    i = int(np.argmax(ends))
    rear = float(np.min(np.asarray(layout.upper_apex, dtype=float) + upper[:, 0]))
    passed = float(layout.lower_apex_x[-1]) + 0.5 * scene.base / u.length - float(layout.upper_apex[0])
    return max(float(ends[i]) - rear, passed), i, float(ends[i])


def off_surface_message(engine, slider_x: float, time: float) -> str:
    """The message of a run whose slider left the far end of the lower surface at ``time`` (s),
    at ``slider_x`` (internal units)."""
    _, i, edge = surface_end(engine)
    L = engine.units.length
    where = (f"the slider ran off the far end of the lower surface at t = {time:.6g} s: at x = {slider_x * L:.6g} m "
             f"the rear of its face passed the far end of lower asperity {i}'s face (x = {edge * L:.6g} m)")
    if engine.scene.slider.track == "free":
        return (f"{where}; a free slider tips off there and falls to the guard floor, so the run ends there "
                "(a longer surface, `lower_count`, or a shorter `duration` keeps it on)")
    return (f"{where}; on its track it touched nothing after that (a longer surface, `lower_count`, or a "
            "shorter `duration` keeps it on)")


# -- features and speeds (internal units: length = the lower profile's base) ---------------------
def _features(scene, units) -> tuple[float, float]:
    """(horizontal, vertical) smallest feature (internal lengths) a slider's step must resolve.

    Fixed track: the horizontal window in which an upper tip overlaps a lower one, at the
    track's ``interference`` (the two triangles' half-widths at that depth, summed); no
    vertical motion. Free slider: half the narrower base (a tip half-way down a flank), and
    the lower of the two asperity heights (a tip falling through a lower asperity, or through
    the guard floor, which has no thickness of its own)."""
    L = units.length
    lo, up = scene.lower.profile, scene.slider.profile
    if scene.slider.track == "fixed":
        i = scene.slider.interference

        def width(p):  # width of a profile at depth i below its tip
            return p.base if p.kind == "flat" else p.base * min(1.0, i / p.height)

        return 0.5 * (width(lo) + width(up)) / L, math.inf
    return 0.5 * min(lo.base, up.base) / L, min(lo.height, up.height) / L


def load_capacity(scene) -> tuple[float, int]:
    """(N, count): the most vertical force the lower springs under a free slider can carry
    within their travel, and how many asperities that counts.

    The slider presses at most the lower asperities whose tips lie within its footprint (its
    tips' span plus a base on each side); each carries at most ``stiffness × travel_down``
    (less its own weight under gravity) before it reaches the bottom of its track. The
    largest sum over every position of the footprint is returned."""
    lower, slider = scene.lower, scene.slider
    tips = lower.tips()
    k, m = np.asarray(lower.stiffness, dtype=float), np.asarray(lower.mass, dtype=float)
    each = np.maximum(k * lower.travel_down - m * scene.gravity, 0.0)
    span = float(slider.tips()[-1]) + 2.0 * float(max(np.max(lower.shape_set().bases),
                                                      np.max(slider.shape_set().bases)))
    cum = np.concatenate([[0.0], np.cumsum(each)])
    end = np.searchsorted(tips, tips + span, side="right")  # window starting at each tip
    sums = cum[end] - cum[np.arange(len(tips))]
    j = int(np.argmax(sums))
    return float(sums[j]), int(end[j] - j)


def check_scene(scene, dt: float, units) -> None:
    """Refuse (SceneError naming the parameter) a scene the step ``dt`` (s) cannot resolve, or a
    free slider its lower springs cannot carry. Called before anything is built."""
    slider, drive = scene.slider, scene.drive
    if slider.track == "free" and not scene.lower.substrate:
        load = slider.normal_load + slider.mass * scene.gravity
        capacity, count = load_capacity(scene)
        if load > capacity:
            what = "`normal_load`" + (" plus the slider's weight" if scene.gravity > 0 else "")
            raise SceneError(
                f"{what} ({load:.3g} N) is more than the lower springs can carry within their travel: "
                f"the {count} asperities under the slider hold at most {capacity:.3g} N (`stiffness` x "
                f"`travel_down`) before they reach the bottom of their tracks, and the slider would fall "
                f"through the surface; use a `normal_load` under {capacity:.3g} N, or a larger "
                f"`stiffness`, `travel_down` or `upper_count`")
    fx, fy = _features(scene, units)
    M = slider.mass
    pitch = min(scene.lower.spacing.mean_pitch, scene.lower.profile.base)
    across = "the width of an asperity where the slider's tips meet it"
    speeds = []  # (m/s, feature, parameter, how, what the feature is)
    if hasattr(drive, "preload"):
        release = abs(drive.preload) / math.sqrt(drive.stiffness * M)
        speeds.append((drive.velocity + release, fx, "`drive_preload`" if drive.preload else "`drive_velocity`",
                       "the drive's speed plus the speed its preload releases", across))
    elif drive.force:
        speeds.append((math.sqrt(2.0 * abs(drive.force) / M * pitch), fx, "`drive_force`",
                       "the speed the drive force gives the slider over one pitch", across))
    if slider.track == "free":
        weight = slider.normal_load + M * scene.gravity
        height = min(scene.lower.profile.height, slider.profile.height)
        speeds.append((math.sqrt(2.0 * weight / M * height), fy, "`normal_load`",
                       "the speed the load gives the slider falling one asperity height", "an asperity's height"))
    for speed, feature, name, how, what in speeds:
        step = speed * dt / units.length
        if step > PREVENT_FRACTION * feature:
            raise SceneError(
                f"{name} makes the slider too fast for the step: {how} is {speed:.3g} m/s, "
                f"{step * units.length:.3g} m per step of {dt:.3g} s, more than the "
                f"{feature * units.length:.3g} m it must not skip ({what}): it would pass through "
                f"asperities without touching them; lower {name}, raise `slider_mass`, or use a "
                f"smaller `dt`")


class Validity:
    """The per-sample checks of one run of ``engine`` (see the module doc); internal units.

    :meth:`check` is called with the bodies' rows at every sample; :meth:`report` gives
    each check's outcome and worst value for ``result.meta["checks"]``.
    """

    def __init__(self, engine):
        self.engine = e = engine
        scene, layout, u = e.scene, e.layout, e.units
        self.fx, self.fy = _features(scene, u)
        self.dt = e.dt_internal
        self.limit_x, self.limit_y = STEP_FRACTION * self.fx, STEP_FRACTION * self.fy
        self.free = scene.slider.track == "free"
        self.floor = scene.lower.floor / u.length
        self.depth = np.asarray(scene.slider.summits(), dtype=float) / u.length  # each tip below the datum
        self.deepest = float(np.max(self.depth))
        apex = layout.lower_apex_x
        reach = 2.0 * float(max(np.max(scene.lower.shape_set().bases), np.max(scene.slider.shape_set().bases)))
        reach /= u.length
        self.over = (float(apex[0]) - reach - float(layout.upper_apex[-1]), float(apex[-1]) + reach)
        # crossings are certain touches only on a fixed track over sloped, tracked, untouched asperities
        self.crossing = (layout.fixed_slider and layout.tracked and scene.lower.profile.kind != "flat"
                         and scene.gravity == 0 and len(apex) > 0 and bool(np.all(np.diff(apex) > 0)))
        self.lower_top = np.asarray(scene.lower.summits(), dtype=float) / u.length
        # half the summed run / height of each asperity's two flanks: the overlap window of a
        # lower and an upper tip at depth d is d x (lower_slope + upper_slope)
        for name, surface in (("lower_slope", scene.lower), ("upper_slope", scene.slider)):
            shapes = surface.shape_set()
            setattr(self, name, 0.5 * shapes.bases / np.asarray(shapes.heights))
        self.limit_l = min(self.limit_x, self.limit_y)
        # plain-Python copies for the per-sample checks (a few asperities: cheaper than NumPy's
        # per-call overhead; the same IEEE operations, so the same outcomes and worst values)
        self._apex = apex.tolist()
        self._offsets = list(enumerate(layout.upper_apex.tolist()))
        # The slider positions at which some upper tip is over some lower apex, sorted (up to
        # EVENTS of them): between two of them no tip passes an apex, so a sample whose interval
        # of positions lies there skips the tunnelling check's bisections (most samples: a
        # sample moves the slider a small part of a pitch). Tip j passes apex i when lo +
        # offset_j < apex_i <= hi + offset_j: apex_i - offset_j in (lo, hi] up to the roundings
        # of those sums, a few ulps of the positions, far inside EVENT_MARGIN of them.
        self._events = None
        if self.crossing and len(apex) * len(layout.upper_apex) <= EVENTS:
            self._events = np.sort(np.subtract.outer(apex, layout.upper_apex), axis=None).tolist()
        scale = float(np.max(np.abs(apex))) + float(np.max(np.abs(layout.upper_apex))) if len(apex) else 0.0
        self._margin = EVENT_MARGIN * (1.0 + scale + abs(self.over[0]) + abs(self.over[1]))
        # the lower asperities' span in the flat row list, when they are contiguous rows
        rows = layout.lower_rows
        self._lanes = (4 * rows.start, 4 * rows.stop) if isinstance(rows, slice) else None
        self._reset()

    def _reset(self) -> None:
        self.worst_step = 0.0  # largest step / limit seen
        self.lowest = math.inf  # lowest tip's height above the floor seen (bases)
        self.crossings = 0  # lower asperities passed over by an upper tip (fixed track)
        self._last = None  # (step, x, y, vx) at the previous sample
        self._clear = (math.inf, -math.inf)  # slider positions where no tip is near an apex (none yet)

    def fresh(self, engine) -> "Validity":
        """New checks for ``engine``, a copy of this one's engine (:meth:`.core.Engine.copy`:
        the same scene, units and geometry), sharing the limits computed from them (0.4 ms at
        16/4, paid once rather than by every fork), its worst values reset."""
        if engine.scene is not self.engine.scene or engine.units is not self.engine.units:
            return Validity(engine)
        out = object.__new__(Validity)
        out.__dict__.update(self.__dict__)
        out.engine, out.dt = engine, engine.dt_internal
        out._reset()
        return out

    def check(self, rows: np.ndarray, flat: list | None = None) -> None:
        """Raise SimulationError if the state ``rows`` (all bodies, internal units) shows an
        impossible run (see the module doc); else update the worst values. ``flat``: ``rows``
        as a flat list (``rows.ravel().tolist()``), when the caller has read it."""
        e, layout = self.engine, self.engine.layout
        r = layout.slider_row
        if flat is not None:
            sx, sy, svx, svy = flat[4 * r: 4 * r + 4]
        else:
            sx, sy, svx, svy = rows.item(r, 0), rows.item(r, 1), rows.item(r, 2), rows.item(r, 3)
        step_now = e.step_count
        last = self._last
        if self.free:
            clearance = sy - self.deepest - self.floor
            if clearance < self.lowest:
                self.lowest = clearance
                if clearance < -FLOOR_TOLERANCE:
                    self._fell(clearance)
        if not self.over[0] <= sx <= self.over[1]:
            self._last = (step_now, sx, sy, svx)
            return  # nothing to collide with: the slider is off the surface
        dt = self.dt
        steps = step_now - last[0] if last is not None else 0
        dx = max(abs(svx) * dt, abs(sx - last[1]) / steps if steps > 0 else 0.0)
        dy = max(abs(svy) * dt, abs(sy - last[2]) / steps if steps > 0 else 0.0) if self.free else 0.0
        # vx: the lattice's peaks. max |v| in plain Python: exact like NumPy's, and cheaper for a
        # few asperities (a NaN never gets here: the divergence guard raised before)
        lanes = self._lanes
        if flat is not None and lanes is not None:
            a, b = lanes
            dl = max(max(map(abs, flat[a + 2:b:4])), max(map(abs, flat[a + 3:b:4]))) * dt if b > a else 0.0
        else:
            lower = rows[layout.lower_rows]
            dl = max(map(abs, lower[:, 2:].ravel().tolist())) * dt if len(lower) else 0.0
        worst = max(dx / self.limit_x, dy / self.limit_y, dl / self.limit_l)
        if worst > self.worst_step:
            self.worst_step = worst
            if worst > 1.0:
                self._too_fast(dx, dy, dl)
        if self.crossing and steps > 0 and sx != last[1]:
            lo, hi = (sx, last[1]) if sx < last[1] else (last[1], sx)
            if not self._clear[0] < lo <= hi < self._clear[1]:  # else: no tip near an apex
                travel = max(dx, abs(last[3]) * dt)  # the step's travel: speeds now and before, mean displacement
                self._crossed(lo, hi, sy, rows[layout.lower_rows], travel)
                self._clear_around(sx)
        self._last = (step_now, sx, sy, svx)

    def _clear_around(self, x: float) -> None:
        """The open interval of slider positions around ``x`` in which no upper tip is over a
        lower apex (:attr:`_events`), narrowed by a margin far above the roundings of the sums
        :meth:`_crossed` compares: a sample whose interval lies inside it crosses nothing."""
        events = self._events
        if events is None:
            return
        k = bisect_right(events, x)
        self._clear = (events[k - 1] + self._margin if k else -math.inf,
                       events[k] - self._margin if k < len(events) else math.inf)

    def _crossed(self, lo: float, hi: float, sy: float, lower: np.ndarray, travel: float) -> None:
        """Raise if an upper tip passed (between the samples at ``lo`` and ``hi``) over a lower
        asperity it must have touched: standing at rest across its path, with an overlap window
        (the two triangles' widths at the overlap depth) over twice the step's ``travel``."""
        # the apexes each upper tip j passed: (lo, hi] + its offset, found by bisection in the
        # sorted apexes (as np.searchsorted(side="right"), without its per-call cost: most
        # samples cross none)
        apex = self._apex
        for j, offset in self._offsets:
            start, end = bisect_right(apex, lo + offset), bisect_right(apex, hi + offset)
            if end <= start:
                continue
            idx = np.arange(start, end)
            self.crossings += len(idx)
            depth = self.lower_top[idx] - (sy - self.depth[j])  # lower tips above the upper tip's path
            window = depth * (self.lower_slope[idx] + self.upper_slope[j])
            must = ((depth > CROSS_MARGIN) & (window > 2.0 * travel)
                    & (lower[idx, 1] == 0.0) & (lower[idx, 3] == 0.0))
            if np.any(must):
                k = int(np.argmax(must))
                self._tunnelled(int(idx[k]), int(j), float(depth[k]), float(window[k]), travel)

    # -- the errors --------------------------------------------------------------------------------
    def _where(self) -> str:
        return f"at t = {self.engine.time:.6g} s"

    def _fix(self) -> str:
        return (f"use a smaller `dt` (now {self.engine.dt:.3g} s), a gentler drive (`drive_force`, "
                "`drive_preload`) or a smaller `normal_load`")

    def _fell(self, clearance: float) -> None:
        L = self.engine.units.length
        raise SimulationError(
            f"the slider fell through the lower surface {self._where()}: its lowest tip is "
            f"{-clearance * L:.3g} m below the guard floor at the bottom of the lower tracks; the load "
            f"(`normal_load` = {self.engine.scene.slider.normal_load:.3g} N) drove it through faster "
            f"than the contacts could stop it; {self._fix()}", time=self.engine.time)

    def _too_fast(self, dx: float, dy: float, dl: float) -> None:
        L = self.engine.units.length
        if dx / self.limit_x >= max(dy / self.limit_y, dl / min(self.limit_x, self.limit_y)):
            body, moved, feature = "the slider", dx, self.fx
        elif dy / self.limit_y >= dl / min(self.limit_x, self.limit_y):
            body, moved, feature = "the slider (vertically)", dy, self.fy
        else:
            body, moved, feature = "a lower asperity", dl, min(self.fx, self.fy)
        raise SimulationError(
            f"the step cannot resolve the motion {self._where()}: {body} moved {moved * L:.3g} m in one "
            f"step, {moved / feature:.2g} times the smallest feature it could collide with "
            f"({feature * L:.3g} m, {'an asperity height' if feature == self.fy else 'the width of an asperity where the tips meet it'}; "
            f"at most {STEP_FRACTION:g} is resolved): it can pass through asperities "
            f"without touching them; {self._fix()}", time=self.engine.time)

    def _tunnelled(self, i: int, j: int, depth: float, window: float, travel: float) -> None:
        L = self.engine.units.length
        raise SimulationError(
            f"the slider passed through lower asperity {i} without touching it {self._where()}: upper "
            f"tip {j} runs {depth * L:.3g} m below that asperity's tip, where the two overlap over "
            f"{window * L:.3g} m, more than twice the {travel * L:.3g} m it moved in a step, yet left it "
            f"untouched; {self._fix()}", time=self.engine.time)

    # -- the report --------------------------------------------------------------------------------
    def report(self) -> dict:
        """Each check's outcome (a run that failed one raised): the worst value and its limit."""
        worst = self.worst_step * STEP_FRACTION  # in features
        out = {"step_resolution": {"passed": worst <= STEP_WARNING, "worst": worst, "limit": STEP_WARNING,
                                   "what": "largest step of a body / the smallest feature it could collide with"}}
        if worst > STEP_WARNING:
            out["step_resolution"]["warning"] = (
                f"a body moved up to {worst:.2g} of the smallest feature it could collide with in one step "
                f"(over {STEP_WARNING:g}): contacts are resolved by too few steps; use a smaller `dt`")
        if self.free:
            out["floor"] = {"passed": True, "worst": -self.lowest if math.isfinite(self.lowest) else 0.0,
                            "limit": FLOOR_TOLERANCE, "what": "deepest tip below the guard floor (bases)"}
        if self.crossing:
            out["contacts"] = {"passed": True, "worst": 0, "limit": 0, "crossings": self.crossings,
                               "what": "lower asperities passed untouched across an upper tip's path"}
        return out
