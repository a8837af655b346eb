"""The batched asperity engine: many scenes stepped in lockstep in one compiled loop.

Part of :mod:`asperity2d.engine` (the entry ``"batched"`` of ``asperity2d.engine.ENGINES``).
The model is the pymunk adapter's, rebuilt for this model alone: lower asperities are
translating bodies on vertical spring-damper tracks (groove joints with their travel limits),
the slider a translating body on a horizontal track or free under its normal load, driven by a
spring or a constant force; contacts are Chipmunk's (velocity-level sequential impulses with
warm starting, the same slop, position bias and iteration count) and the static/kinetic switch
with its hold rule follows every step, as in :mod:`.core`. The step itself is in
:mod:`.batched_kernel` (Numba, the optional ``[batch]`` extra).

What it covers, and refuses (one :class:`~asperity2d.errors.SceneError` line naming the option
and saying ``engine="pymunk"`` runs it): every profile (full and half triangles, flat tops),
random heights and measured profiles' asperities -- each asperity one strictly convex outline,
as Chipmunk keeps it -- with the guard floor and a measured profile's rigid valleys (the
substrate) as Chipmunk's static segments; Ooten's MATLAB lattice (its links Chipmunk's damped
springs between the peaks and to the walls, :mod:`.batched_links`); the ``static-kinetic``
contact law only. It settles as :meth:`.core.Engine.settle`
does (:meth:`Batch.settle`: the same phases, damping, hold and calm test), forks a settled scene
into many (:meth:`Batch.forks`, the critical force's trial runs) and stops a scene at the run
loop's stops (passed, :class:`asperity2d.Stuck`, a free slider off the far end).

A batch is refused up front when its arrays would pass :data:`MAX_BATCH_BYTES`; a scene that
diverges stops alone with its own ``SimulationError`` while its neighbours finish.
"""

from __future__ import annotations

import importlib.util
import math

import numpy as np

from .._version import __version__
from ..errors import SceneError, SimulationError
from ..units import Units, check_scales
from .run_checks import check_scene, off_surface_message, surface_end
from .space import COLLISION_SLOP, CORRECTION_PER_STEP, per_step_bias

#: How to get the compiled loop.
INSTALL = 'pip install "asperity2d[batch]"'
#: Largest batch (bytes of state, geometry and record) accepted in one call.
MAX_BATCH_BYTES = 2 << 30
#: The engine's name in the registry and in its results' meta.
ENGINE = "batched"
#: The error bias of settling's hold on the slider's x: pymunk's default for a joint
#: (``Constraint.error_bias``, Chipmunk's ``cpfpow(1 - 0.1, 60)`` in single precision), which
#: :meth:`asperity2d.engine.core.Engine.settle` leaves its hold at.
HOLD_ERROR_BIAS = 0.0017970074436457143
#: Why a scene's call ended, by the kernel's stop code: the statuses of the run loop.
STATUS = {0: "duration", 1: "passed", 2: "stuck", 3: "off-surface"}


def unavailable() -> str | None:
    """Why the batched engine cannot run here (None: it can)."""
    if importlib.util.find_spec("numba") is None:
        return f'engine="batched" needs Numba, which is not installed: {INSTALL}'
    return None


def _strictly_convex(points) -> bool:
    """Every vertex a strict corner, all turning the same way (what Chipmunk's hull keeps as given)."""
    pts = [tuple(map(float, p)) for p in points]
    n = len(pts)
    turns = [(pts[i][0] - pts[i - 1][0]) * (pts[(i + 1) % n][1] - pts[i - 1][1])
             - (pts[i][1] - pts[i - 1][1]) * (pts[(i + 1) % n][0] - pts[i - 1][0]) for i in range(n)]
    return n >= 3 and (all(t > 0.0 for t in turns) or all(t < 0.0 for t in turns))


def refusal(scene, *, settle: bool = False) -> str | None:
    """The scene option the batched engine does not implement (one line), or None (``settle``:
    whether the run settles first, which it implements)."""
    lower, contact = scene.lower, scene.contact
    tail = '; engine="pymunk" runs it'
    for what, outlines in (("lower", lower.outlines()), ("slider", scene.slider.outlines())):
        if not all(_strictly_convex(outline) for outline in outlines):
            return (f"`shapes`: a {what} asperity's outline is not strictly convex (collinear or reflex "
                    "vertices), which engine=\"batched\" does not implement" + tail)
    if scene.slider.start is not None:
        return "`slider_start` (a start of the scene's own) is not implemented on engine=\"batched\"" + tail
    if contact.law != "static-kinetic":
        return f"`contact_law` = {contact.law!r} is not implemented on engine=\"batched\" (static-kinetic only)" + tail
    return None


def _kernel():
    why = unavailable()
    if why is not None:
        raise SceneError(why)
    from . import batched_kernel

    return batched_kernel


class Batch:
    """``scenes`` built into arrays (internal units) for the compiled loop, all at rest at t = 0.

    ``dts`` (s), one per scene; ``iterations`` as pymunk's solver iterations; ``samples``: how
    many samples each scene's record holds; ``record_every``: steps between samples.
    """

    def __init__(self, scenes, dts, *, iterations: int = 20, record_every: int = 10, samples: int = 1,
                 engaged: bool = False):
        kernel = _kernel()
        self.engaged = bool(engaged)
        self.kernel = kernel
        self.scenes = list(scenes)
        B = len(self.scenes)
        if B == 0:
            raise SceneError("`scenes` is empty: give at least one scene")
        for scene in self.scenes:
            why = refusal(scene)
            if why is not None:
                raise SceneError(why)
        N = max(s.lower.count for s in self.scenes)
        U = max(s.slider.count for s in self.scenes)
        V = max(max(len(o) for o in s.lower.outlines()) for s in self.scenes)
        W = max(max(len(o) for o in s.slider.outlines()) for s in self.scenes)
        S = max(_segment_count(scene) for scene in self.scenes)
        K = max(_link_count(scene) for scene in self.scenes)
        need = self.nbytes_for(B, N, U, samples, vertices=max(V, W), segments=S, links=K)
        if need > MAX_BATCH_BYTES:
            raise SceneError(
                f"a batch of {B} scenes ({N} lower and {U} upper asperities, {samples} samples each) needs "
                f"{need / 2**30:.1f} GiB, more than the {MAX_BATCH_BYTES / 2**30:.0f} GiB one batch may take: "
                "run it in smaller batches (fewer scenes or samples)")
        self.units = []
        self.record_every, self.samples = record_every, samples
        f8 = lambda *shape: np.zeros(shape)  # noqa: E731
        self.lp, self.lv, self.lvb, self.gj = f8(B, N, 2), f8(B, N, 2), f8(B, N, 2), f8(B, N, 2)
        self.sp, self.sv, self.svb, self.sgj = f8(B, 2), f8(B, 2), f8(B, 2), f8(B, 2)
        self.c_n = np.zeros((B, U, N), np.int64)
        self.c_key = np.zeros((B, U, N, 2), np.int64)
        self.c_jn, self.c_jt = f8(B, U, N, 2), f8(B, U, N, 2)
        self.stuck, self.present = np.zeros((B, N), np.bool_), np.zeros((B, N), np.bool_)
        self.slid, self.mu = f8(B, N), f8(B, N)
        self.nstep = np.zeros(B, np.int64)
        self.fail, self.fail_step = np.zeros(B, np.int64), np.zeros(B, np.int64)
        self.lx0, self.lverts, self.lnorms = f8(B, N), f8(B, N, V, 2), f8(B, N, V, 2)
        self.nv_l, self.nv_u = np.zeros((B, N), np.int64), np.zeros((B, U), np.int64)
        self.lm_inv, self.lk, self.lc = np.ones((B, N)), f8(B, N), f8(B, N)
        self.ldown, self.lup = f8(B, N), f8(B, N)
        self.n_lower, self.n_upper = np.zeros(B, np.int64), np.zeros(B, np.int64)
        self.uverts, self.unorms = f8(B, U, W, 2), f8(B, U, W, 2)
        self.s_m_inv = f8(B)
        self.fixed = np.zeros(B, np.bool_)
        self.track_y, self.g_x, self.g_y = f8(B), f8(B), f8(B)
        self.spring = np.zeros(B, np.bool_)
        self.dk, self.dc, self.dv, self.dorigin, self.dforce, self.load = f8(B), f8(B), f8(B), f8(B), f8(B), f8(B)
        self.dt, self.dt_s, self.iterations = f8(B), f8(B), np.full(B, iterations, np.int64)
        self.bias_coef, self.joint_bias_coef, self.restitution = f8(B), f8(B), f8(B)
        self.mu_s, self.mu_k, self.v_stick, self.slip_dist = f8(B), f8(B), f8(B), f8(B)
        self.switch_on = np.zeros(B, np.bool_)
        self.stop_x = np.full(B, np.inf)
        # the static segments: the floor, then a profile's valleys (each line's segments in order)
        self.seg_a, self.seg_b, self.seg_n = f8(B, S, 2), f8(B, S, 2), f8(B, S, 2)
        self.n_seg, self.seg_mu = np.zeros(B, np.int64), f8(B)
        self.s_n = np.zeros((B, U, S), np.int64)
        self.s_key = np.zeros((B, U, S, 2), np.int64)
        self.s_jn, self.s_jt = f8(B, U, S, 2), f8(B, U, S, 2)
        self.first = np.ones(B, np.bool_)
        # settling (Batch.settle) and the stops (Batch.set_stops): off but while asked for
        self.settling, self.damp, self.push = np.zeros(B, np.bool_), np.ones(B), f8(B)
        self.hold, self.hold_x, self.hold_j, self.hold_coef = np.zeros(B, np.bool_), f8(B), f8(B, 2), f8(B)
        self.stop_code = np.zeros(B, np.int64)
        self.stuck_v, self.stuck_dwell, self.slow_since = f8(B), f8(B), np.full(B, -1.0)
        self.v_unit, self.off_x = f8(B), np.full(B, np.inf)
        self.track_y0 = f8(B)  # the fixed track's working height (track_y starts above it when engaged)
        # Ooten's MATLAB lattice: per link its bodies (-1: the static body), its ends' anchors
        # (a wall's on the static body), its rest length, stiffness and damping
        self.lat, self.n_link = np.zeros(B, np.bool_), np.zeros(B, np.int64)
        self.link_ab, self.link_p, self.link_kc = np.full((B, K, 2), -1, np.int64), f8(B, K, 4), f8(B, K, 3)
        self.rec = np.zeros((B, kernel.N_REC, samples))
        self.rec_at = np.zeros(B, np.int64)
        for b, (scene, dt) in enumerate(zip(self.scenes, dts)):
            self._load(b, scene, float(dt))
        self._initial = self._sample0()

    @staticmethod
    def nbytes_for(B: int, N: int, U: int, samples: int, *, vertices: int = 3, segments: int = 1,
                   links: int = 1) -> int:
        """Bytes of a batch's arrays: state and geometry per scene (outlines of up to
        ``vertices`` vertices, ``segments`` static segments, room for ``links`` lattice links),
        and its record."""
        per_lower = 8 * (4 * 2 + 4 + 2 * vertices * 2 + 6) + 2
        per_pair = 8 * 1 + 8 * 2 * 3
        per_scene = N * per_lower + U * N * per_pair + U * 8 * (4 * vertices + 1) + 8 * 56 + 8 * 9 * samples \
            + segments * (8 * 6 + U * 8 * 5) + 9 + links * 8 * 9
        return B * per_scene

    def _load(self, b: int, scene, dt: float) -> None:
        u = Units.for_scene(scene)
        check_scales(scene, u)
        check_scene(scene, dt, u)
        self.units.append(u)
        lower, slider, contact, drive = scene.lower, scene.slider, scene.contact, scene.drive
        n, m = lower.count, slider.count
        self.n_lower[b], self.n_upper[b] = n, m
        x0 = lower.tips() / u.length
        self.lx0[b, :n] = x0
        self.lp[b, :n, 0] = x0
        for i, outline in enumerate(lower.outlines()):
            v, nrm = _hull([(vx / u.length, vy / u.length) for vx, vy in outline])
            self.nv_l[b, i] = len(v)
            self.lverts[b, i, :len(v)], self.lnorms[b, i, :len(v)] = v, nrm
        self.lm_inv[b, :n] = 1.0 / (np.asarray(lower.mass, float) / u.mass)
        if lower.is_lattice:
            self._links(b, lower, u, x0)
        self.lk[b, :n] = np.asarray(lower.stiffness, float) / u.stiffness
        self.lc[b, :n] = np.asarray(lower.damping, float) / u.damping
        self.ldown[b, :n] = lower.travel_down / u.length
        self.lup[b, :n] = lower.travel_up / u.length
        apex = slider.tips() / u.length
        for j, (c, outline) in enumerate(zip(apex, slider.outlines())):
            v, nrm = _hull([(c + x / u.length, y / u.length) for x, y in outline])
            self.nv_u[b, j] = len(v)
            self.uverts[b, j, :len(v)], self.unorms[b, j, :len(v)] = v, nrm
        self.s_m_inv[b] = 1.0 / (slider.mass / u.mass)
        # where the slider starts: as space.build places a fixed-track slider (not engaged) or a
        # free one (over the first valley, just clear of the tips)
        h_up = slider.depth / u.length
        height = lower.top / u.length
        left = float(np.ravel(lower.runs()[0])[0]) / u.length
        if slider.track == "fixed" and not self.engaged:
            right = float(np.ravel(slider.runs()[1])[-1]) / u.length
            sx = x0[0] - left - right - apex[-1] - 0.1
            sy = height - slider.interference / u.length + h_up
            self.fixed[b] = True
        else:  # over the first valley, just clear of the tips (a fixed track engaged: its track raised there)
            flat = lower.profile.kind == "flat"
            x_tip = 0.5 * (x0[0] + x0[1]) if n > 1 else x0[0] - (0.0 if flat else 0.5 * left)
            sx = x_tip - apex[0]
            sy = height + h_up + 1e-3
            self.fixed[b] = slider.track == "fixed"
        self.sp[b] = sx, sy
        self.track_y[b] = sy
        self.track_y0[b] = height - slider.interference / u.length + h_up if self.fixed[b] else sy
        self.v_unit[b] = u.velocity
        self.hold_coef[b] = 1.0 - math.pow(HOLD_ERROR_BIAS, dt / u.time)
        if slider.track == "free":
            self.off_x[b] = surface_end(_Layout(scene, u))[0]
        self.g_y[b] = -scene.gravity / u.acceleration
        if drive.__class__.__name__ == "SpringDrive":
            self.spring[b] = True
            self.dk[b], self.dc[b] = drive.stiffness / u.stiffness, drive.damping / u.damping
            self.dv[b] = drive.velocity / u.velocity
            self.dorigin[b] = sx + drive.preload / u.force / self.dk[b]
        else:
            self.dforce[b] = drive.force / u.force
        self.load[b] = slider.normal_load / u.force if slider.track == "free" else 0.0
        h = dt / u.time
        self.dt[b] = h
        self.dt_s[b] = dt
        bias = per_step_bias(CORRECTION_PER_STEP, h)
        self.bias_coef[b] = 1.0 - math.pow(bias, h)
        self.joint_bias_coef[b] = 1.0 - math.pow(bias, h)
        self.restitution[b] = contact.restitution * 1.0
        self.mu_s[b], self.mu_k[b] = contact.mu_static, contact.mu_kinetic
        self.mu[b, :n] = contact.mu_kinetic
        self.slip_dist[b] = (1e-3 * u.length if contact.slip_distance is None else contact.slip_distance) / u.length
        if contact.stick_speed is not None:
            self.v_stick[b] = contact.stick_speed / u.velocity
        else:
            v = 1e-4
            if self.spring[b]:
                v = min(v, 0.1 * drive.velocity / u.velocity)
            self.v_stick[b] = v
        self.switch_on[b] = contact.mu_static != contact.mu_kinetic
        # as space._build_floor: the floor from far left to far right of the scene and the slider's
        # way, then the substrate's segments; each segment's normal as Chipmunk's
        # (cpvrperp(cpvnormalize(b - a)), with cpvnormalize's + DBL_MIN)
        y = scene.floor / u.length
        extent = (sx, float(x0[-1]) + float(apex[-1] - apex[0]) + 1.0)
        lo = min(float(x0[0]) - 1e6, min(extent) - 1e5)
        hi = max(1e6 - float(x0[0]), max(extent) + 1e5)
        segments = [((lo, y), (hi, y))]
        for line in scene.lower.substrate or ():
            pts = [(vx / u.length, vz / u.length) for vx, vz in line]
            segments += list(zip(pts[:-1], pts[1:]))
        for k, ((ax, ay), (bx, by)) in enumerate(segments):
            dx, dy = bx - ax, by - ay
            inv = 1.0 / (math.sqrt(dx * dx + dy * dy) + 2.2250738585072014e-308)
            self.seg_a[b, k], self.seg_b[b, k] = (ax, ay), (bx, by)
            self.seg_n[b, k] = dy * inv, -(dx * inv)
        self.n_seg[b] = len(segments)
        self.seg_mu[b] = contact.mu_kinetic  # the floor's and valleys' coefficient, as build gives it

    def _links(self, b: int, lower, u: Units, x) -> None:
        """Scene ``b``'s lattice links as :mod:`asperity2d.engine.space`'s lattice builds them:
        wall-peak 1, peak 1-peak 2, ..., peak n-wall, those of zero stiffness and damping left out;
        a wall's end is a point of the static body one mean pitch outside the end peak."""
        self.lat[b] = True
        pitch = lower.spacing.mean_pitch / u.length
        e = 0
        for j, (k, c) in enumerate(zip(lower.lateral_stiffness, lower.lateral_damping)):
            if k == 0 and c == 0:
                continue
            if j == 0:
                ends, anchors, rest = (-1, 0), (x[0] - pitch, 0.0, 0.0, 0.0), pitch
            elif j == len(x):
                ends, anchors, rest = (len(x) - 1, -1), (0.0, 0.0, x[-1] + pitch, 0.0), pitch
            else:
                ends, anchors, rest = (j - 1, j), (0.0, 0.0, 0.0, 0.0), x[j] - x[j - 1]
            self.link_ab[b, e], self.link_p[b, e] = ends, anchors
            self.link_kc[b, e] = rest, k / u.stiffness, c / u.damping
            e += 1
        self.n_link[b] = e

    def _sample0(self) -> np.ndarray:
        out = np.zeros((len(self.scenes), self.kernel.N_REC))
        out[:, 0], out[:, 2] = self.sp[:, 0], self.sp[:, 1]
        out[:, 4] = np.where(self.spring, self.dk * (self.dorigin - self.sp[:, 0]) + self.dc * self.dv, self.dforce)
        return out

    def set_stop(self, b: int, passed: bool) -> None:
        """Stop scene ``b`` when the slider's rear tip has passed the last lower tip by half a
        base (``passed``, the :class:`asperity2d.Passed` condition), or never."""
        scene, u = self.scenes[b], self.units[b]
        if passed:
            last = scene.lower.tips()[-1] / u.length
            base = scene.lower.profile.base / u.length
            self.stop_x[b] = last + 0.5 * base - _rear(self, b)
        else:
            self.stop_x[b] = math.inf

    def settle(self, push, max_time, *, damping_per_period: float = 0.5, rest_speed: float = 1e-7) -> np.ndarray:
        """:meth:`asperity2d.engine.core.Engine.settle` for every scene at once: the same phases
        (a free slider's drop with its x held, a fixed track lowered into place when
        ``engaged``, the spring drive's equilibrium, the ``push[b]`` (N) along +x), the same
        global damping, windows, calm test and shares of ``max_time[b]`` (s), each scene on its
        own schedule (``max_time[b]`` None: scene ``b`` does not settle); then every velocity is
        zeroed and the contacts at rest start stuck. Returns each scene's time spent (s)."""
        B = len(self.scenes)
        plan = []
        for b, scene in enumerate(self.scenes):
            u = self.units[b]
            if max_time[b] is None:  # this scene does not settle
                plan.append({"phases": [], "spent": 0})
                continue
            lowering = bool(self.fixed[b]) and self.track_y[b] != self.track_y0[b]
            phases = (["drop"] if scene.slider.track == "free" or lowering else []) + \
                (["spring"] if self.spring[b] else []) + (["push"] if push[b] else [])
            dt = float(self.dt_s[b])
            period = max(1, int(scene.slowest_period() / dt))
            share = max(2, int(max_time[b] / dt) // max(1, len(phases)))
            rate = -math.log(damping_per_period) / (2.0 * math.pi)  # per internal time unit
            slowest = 2.0 * math.pi * u.time / scene.slowest_period()
            # Chipmunk damps v by cpfpow(space.damping, dt) every step
            self.damp[b] = math.pow(math.exp(-min(rate, 2.0 * slowest)), float(self.dt[b]))
            plan.append({"phases": phases, "at": 0, "done": 0, "calm": 0, "spent": 0, "period": period,
                         "window": max(1, period // 4), "share": share, "lowering": lowering,
                         "y_start": float(self.track_y[b]), "push": float(push[b]) / u.force})
        self.hold_x[:] = self.sp[:, 0]
        live = [b for b in range(B) if plan[b]["phases"]]
        while live:
            steps = np.zeros(B, np.int64)
            for b in live:
                p = plan[b]
                phase = p["phases"][p["at"]]
                if phase == "drop" and not self.hold[b]:
                    self.hold[b], self.hold_j[b] = True, 0.0
                elif phase != "drop" and self.hold[b]:
                    self.hold[b] = False
                n = min(p["window"], p["share"] - p["done"])
                if phase == "drop" and p["lowering"]:  # Engine._lower_track
                    fraction = min(1.0, (p["done"] + n) / p["period"])
                    self.track_y[b] = p["y_start"] + fraction * (self.track_y0[b] - p["y_start"])
                self.push[b] = p["push"] if phase == "push" else 0.0
                steps[b] = n
            self.settling[:] = steps > 0
            self.advance(steps)
            for b in list(live):
                p = plan[b]
                p["done"] += int(steps[b])
                n_low = int(self.n_lower[b])
                fastest = max(float(np.abs(self.lv[b, :n_low]).max(initial=0.0)), float(np.abs(self.sv[b]).max()))
                p["calm"] = p["calm"] + 1 if fastest < rest_speed else 0
                if self.fail[b] != 0 or not (p["done"] < p["share"] and p["calm"] < 4):
                    p["spent"] += p["done"]
                    p["at"], p["done"], p["calm"] = p["at"] + 1, 0, 0
                    if p["at"] == len(p["phases"]) or self.fail[b] != 0:
                        live.remove(b)
        self.settling[:] = False
        self.hold[:] = False
        self.damp[:] = 1.0
        self.push[:] = 0.0
        for b in range(B):
            if not plan[b]["phases"]:  # as Engine.settle with nothing to do: untouched
                continue
            self.lv[b] = 0.0
            self.sv[b] = 0.0
            if self.switch_on[b]:  # contacts at rest start stuck, with mu_static (the switch at zero slip)
                touching = self.c_n[b].sum(axis=0) > 0
                self.present[b] = touching
                self.stuck[b] = touching
                self.slid[b] = 0.0
                self.mu[b] = np.where(touching, self.mu_s[b], self.mu_k[b])
        return np.array([p["spent"] * float(self.dt_s[b]) for b, p in enumerate(plan)])

    def forks(self, forces, rows) -> "Batch":
        """A new batch whose scene ``k`` goes on from this batch's scene ``rows[k]`` as it is now
        (its arrays copied, but the joints' accumulated impulses, as the reference's fork) under
        the constant force ``forces[k]`` (N): the critical force's trial runs
        (:meth:`asperity2d.Run.fork` and ``set_drive_force``)."""
        from ..scene import ConstantForce

        rows = np.asarray(rows, np.int64)
        out = object.__new__(Batch)
        out.kernel, out.engaged, out.record_every, out.samples = self.kernel, self.engaged, self.record_every, 1
        out.scenes = [self.scenes[r].replace(drive=ConstantForce(force=float(f))) for r, f in zip(rows, forces)]
        out.units = [self.units[r] for r in rows]
        for name, value in vars(self).items():
            if isinstance(value, np.ndarray):
                setattr(out, name, value[rows])  # (advanced indexing copies)
        out.rec = np.zeros((len(rows), self.kernel.N_REC, 1))
        out.rec_at[:] = 0
        # as the reference's fork: its copy of the space (a pickle) keeps the contacts and their
        # impulses but not the joints' accumulated impulses, so the fork's first step warm-starts
        # its grooves from zero (measured: with this a free slider's fork follows pymunk's to the
        # bit; without it the two part by 4e-5 of a base in the second step)
        out.gj[:] = 0.0
        out.sgj[:] = 0.0
        out.hold_j[:] = 0.0
        out.spring[:] = False
        out.dforce[:] = [float(f) / u.force for f, u in zip(forces, out.units)]
        out._initial = out._sample0()
        return out

    def set_stops(self, *, passed, stuck=None) -> None:
        """The run loop's stop conditions, per scene: ``passed[b]`` (the slider passed the surface)
        and ``stuck[b]`` = ``(speed m/s, dwell s)`` of :class:`asperity2d.Stuck`, or None."""
        for b in range(len(self.scenes)):
            self.set_stop(b, bool(passed[b]))
            rule = None if stuck is None else stuck[b]
            self.stuck_v[b], self.stuck_dwell[b] = (0.0, 0.0) if rule is None else rule

    def advance_for(self, durations) -> list[str]:
        """Advance scene ``b`` for ``durations[b]`` (s; 0: not at all) as one call of
        :meth:`asperity2d.Run.advance` does (its steps, its stops at its samples, the
        :class:`~asperity2d.Stuck` stop's memory reset): each scene's status."""
        steps = np.array([int(math.ceil(d / dt - 1e-9)) if d > 0 else 0 for d, dt in zip(durations, self.dt_s)],
                         np.int64)
        self.stop_code[:] = 0
        self.slow_since[:] = -1.0
        self.advance(steps)
        return [STATUS[int(c)] for c in self.stop_code]

    def advance(self, steps) -> None:
        """Advance scene ``b`` by ``steps[b]`` steps (all scenes in one compiled call)."""
        k = self.kernel
        k.advance(np.asarray(steps, np.int64), self.record_every, self.rec_at, self.rec, self.lp, self.lv,
                  self.lvb, self.gj, self.sp, self.sv, self.svb, self.sgj, self.c_n, self.c_key, self.c_jn,
                  self.c_jt, self.stuck, self.slid, self.mu, self.present, self.nstep, self.fail,
                  self.fail_step, self.lx0, self.lverts, self.lnorms, self.nv_l, self.lm_inv, self.lk, self.lc,
                  self.ldown, self.lup, self.n_lower, self.uverts, self.unorms, self.nv_u, self.n_upper, self.s_m_inv,
                  self.fixed, self.track_y, self.g_x, self.g_y, self.spring, self.dk, self.dc, self.dv,
                  self.dorigin, self.dforce, self.load, self.dt, self.iterations, COLLISION_SLOP,
                  self.bias_coef, self.joint_bias_coef, self.restitution, self.mu_s, self.mu_k,
                  self.v_stick, self.slip_dist, self.switch_on, self.seg_a, self.seg_b, self.seg_n, self.n_seg,
                  self.seg_mu, self.s_n, self.s_key, self.s_jn, self.s_jt, self.stop_x, self.first,
                  self.settling, self.damp, self.push, self.hold, self.hold_x, self.hold_j, self.hold_coef,
                  self.stop_code, self.stuck_v, self.stuck_dwell, self.slow_since, self.v_unit, self.dt_s,
                  self.off_x, self.lat, self.n_link, self.link_ab, self.link_p, self.link_kc, k.groups(len(self.dt)))

    def error(self, b: int, *, offset: int = 0) -> SimulationError | None:
        """Scene ``b``'s own failure (None if it ran), naming it as scene ``offset + b``."""
        code = int(self.fail[b])
        if code == 0:
            return None
        k = self.kernel
        t = self.fail_step[b] * self.dt_s[b]
        why = {k.NONFINITE: "its state became non-finite", k.OVERLAP: "a contact overlapped more than half a base",
               k.PAIRS: f"a slider tip touched more than {k.PAIRS_PER_TIP} lower asperities at once"}[code]
        return SimulationError(f"scene {offset + b} ({self.scenes[b].name}) stopped at t = {t:.4g} s: {why}")

    def result(self, b: int, *, status: str, meta: dict) -> tuple[dict, dict]:
        """Scene ``b``'s record: the arrays of a :class:`~asperity2d.Result` (SI; no
        lower-asperity samples) and its meta."""
        u, scene = self.units[b], self.scenes[b]
        m = int(self.rec_at[b])
        rec = np.concatenate([self._initial[b][:, None], self.rec[b, :, :m]], axis=1)
        steps = np.arange(m + 1) * self.record_every
        t = steps * self.dt_s[b]  # as the recorder: step count x dt (s)
        drive_x = (self.dorigin[b] + self.dv[b] * steps * self.dt[b]) * u.length if self.spring[b] \
            else np.full(m + 1, math.nan)
        n = scene.lower.count
        arrays = dict(t=t, x=rec[0] * u.length, v=rec[1] * u.velocity, y=rec[2] * u.length,
                      vy=rec[3] * u.velocity, drive_x=drive_x, drive_force=rec[4] * u.force,
                      normal_force=rec[6] * u.force, friction_force=-rec[5] * u.force,
                      tangential_force=rec[7] * u.force, contact_count=rec[8].copy(),
                      lower_dx=np.empty((n, 0)), lower_dy=np.empty((n, 0)),
                      lower_contact=np.empty((n, 0), dtype=bool))
        meta = {"engine": ENGINE, "dt": float(self.dt_s[b]), "record_every": self.record_every,
                "iterations": int(self.iterations[b]), "steps": int(self.nstep[b]), "settle_time": 0.0,
                "units": u.to_dict(), "asperity2d_version": __version__, "numpy_version": np.__version__,
                "record_lower": False, **meta}
        return arrays, meta


def _segment_count(scene) -> int:
    """The static segments of a scene: the floor and its substrate's."""
    return 1 + sum(max(0, len(line) - 1) for line in (scene.lower.substrate or ()))


def _link_count(scene) -> int:
    """Room for a scene's lattice links (one per gap and wall; one slot for a scene without)."""
    return scene.lower.count + 1 if scene.lower.is_lattice else 1


class _Layout:
    """What :func:`~asperity2d.engine.run_checks.surface_end` reads of an engine, for a scene
    as :class:`Batch` places it."""

    def __init__(self, scene, u: Units):
        from types import SimpleNamespace

        self.scene, self.units = scene, u
        self.layout = SimpleNamespace(lower_apex_x=scene.lower.tips() / u.length,
                                      upper_apex=scene.slider.tips() / u.length)


def _rear(batch: Batch, b: int) -> float:
    """x of the slider's rear apex relative to the slider's position (internal units)."""
    return float(batch.scenes[b].slider.tips()[0] / batch.units[b].length)


def _hull(points) -> tuple[np.ndarray, np.ndarray]:
    """A convex outline's vertices in Chipmunk's hull order (``cpConvexHull``: counter-clockwise
    from the lowest x, then y) and each vertex's plane normal (of the edge that ends at it,
    outward, unit: ``cpPolyShape``'s planes)."""
    pts = [tuple(map(float, p)) for p in points]
    count = len(pts)
    area = sum(pts[i][0] * pts[(i + 1) % count][1] - pts[(i + 1) % count][0] * pts[i][1] for i in range(count))
    if area < 0:
        pts = pts[::-1]
    if not _strictly_convex(pts):  # the hull keeps only strict corners: refused, as by refusal()
        raise SceneError("`shapes`: an asperity's outline is not strictly convex (collinear or reflex "
                         'vertices), which engine="batched" does not implement; engine="pymunk" runs it')
    start = min(range(count), key=lambda i: pts[i])
    pts = pts[start:] + pts[:start]
    v = np.array(pts)
    n = np.empty((count, 2))
    for i in range(count):
        ax, ay = v[i - 1]
        bx, by = v[i]
        dx, dy = bx - ax, by - ay  # cpvnormalize(cpvrperp(b - a)): rperp(d) = (d.y, -d.x)
        length = math.sqrt(dy * dy + dx * dx)
        n[i] = dy * (1.0 / length), -dx * (1.0 / length)
    return v, n


#: One call runs its scenes in batches of at most this many bytes (:meth:`Batch.nbytes_for`):
#: the record dominates (72 B a sample and scene), and results do not depend on the batching.
CHUNK_BYTES = 256 << 20


def batch_size(scenes, steps: int, *, record_every: int = 10) -> int:
    """How many of ``scenes`` :func:`run` steps in one batch when the longest runs ``steps``
    steps: as many as keep the batch's arrays (:meth:`Batch.nbytes_for`, its record included)
    within :data:`CHUNK_BYTES`, at least one."""
    N = max(s.lower.count for s in scenes)
    U = max(s.slider.count for s in scenes)
    V = max(max(len(o) for o in s.lower.outlines()) for s in scenes)
    W = max(max(len(o) for o in s.slider.outlines()) for s in scenes)
    S = max(_segment_count(s) for s in scenes)
    K = max(_link_count(s) for s in scenes)
    per_scene = Batch.nbytes_for(1, N, U, max(1, steps // record_every), vertices=max(V, W), segments=S,
                                 links=K)
    return max(1, min(len(scenes), CHUNK_BYTES // max(1, per_scene)))


def run(scenes, dts, durations, *, record_every: int = 10, iterations: int = 20, passed=None, stuck=None,
        settle=None):
    """Run each scene for its duration (s): per scene, in order, its record ``(arrays, meta)``
    (:meth:`Batch.result`) or the SimulationError that stopped it.

    ``passed[b]``: stop scene ``b`` when its slider has passed the surface (the default stop);
    ``stuck[b]``: ``(speed, dwell)`` of the :class:`asperity2d.Stuck` stop, or None; ``settle[b]``:
    settle it first for at most this long (s, :meth:`Batch.settle` without a push), or None.
    Scenes run in batches of at most :data:`CHUNK_BYTES` (a scene that alone is over
    :data:`MAX_BATCH_BYTES` is refused by :class:`Batch`).
    """
    scenes = list(scenes)
    B = len(scenes)
    dts = [float(d) for d in dts]
    passed = [False] * B if passed is None else [bool(p) for p in passed]
    stuck = [None] * B if stuck is None else list(stuck)
    settle = [None] * B if settle is None else list(settle)
    steps = [max(0, int(math.ceil(d / dt - 1e-9))) for d, dt in zip(durations, dts)]
    size = batch_size(scenes, max(steps), record_every=record_every)
    out = []
    for start in range(0, B, size):
        part = slice(start, start + size)
        out += _run_chunk(scenes[part], dts[part], steps[part], record_every, iterations, passed[part],
                          stuck[part], settle[part], start)
    return out


def _run_chunk(scenes, dts, steps, record_every, iterations, passed, stuck, settle, offset):
    from .._format import si

    samples = max(1, max(steps) // record_every)
    batch = Batch(scenes, dts, iterations=iterations, record_every=record_every, samples=samples)
    batch.set_stops(passed=passed, stuck=stuck)
    spent = np.zeros(len(scenes))
    if any(t is not None for t in settle):
        spent = batch.settle(np.zeros(len(scenes)), settle)
        batch._initial = batch._sample0()  # the record starts from the settled state
    batch.advance(steps)
    out = []
    for b in range(len(scenes)):
        err = batch.error(b, offset=offset)
        if err is not None:
            out.append(err)
            continue
        status = STATUS[int(batch.stop_code[b])]
        t = float(batch.nstep[b] * batch.dt_s[b])
        if status == "off-surface":
            message = off_surface_message(_Layout(scenes[b], batch.units[b]), float(batch.sp[b, 0]), t)
        elif status == "duration":
            message = "reached the requested duration"
        else:
            message = f"stop condition {status!r} met at t = {si(t, 's', 4)}"
        out.append(batch.result(b, status=status, meta={"status": status, "message": message,
                                                        "settle_time": float(spent[b])}))
    return out
