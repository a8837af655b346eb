"""A virtual tribometer: the friction law that emerges from the asperities.

The slider is velocity-controlled: a drive spring as stiff as the asperity
springs (372,000 N/m, ten times the asperity's 37,200: its stretch at the
friction force is ~5 nm, 0.5 % of a base, while its frequency stays at the
asperities', so dt is unchanged) whose far end moves at the commanded
velocity. The drive spring is evaluated symplectically (see ``Engine.step``).

* :func:`steady_curve` -- for every velocity of a ladder, slide +x, then
  reverse and slide -x over the same ground (both directions driven, no
  symmetry assumed); after a transient of ``transient`` (m) the mean
  friction force (contact force resisting the motion, N) is averaged over
  whole pitches of travel, with its spread (standard deviation of the
  per-pitch means, N).
* :func:`reversal_loops` -- from rest, small back-and-forth drive strokes of
  growing amplitude: force against slider displacement at reversals. On the
  Table 1 scene the slider does not move inside the static cone (the rigid
  contacts have no tangential compliance) and advances in nm micro-slips
  beyond it: there is no smooth elastic pre-sliding branch.
* :func:`energy_window` -- one steady window with an
  :meth:`~asperity2d.run.Run.meter_energy` attached: mean friction
  force x distance slid against the energy dissipated plus the change in
  stored energy.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from .._inputs import check_int, check_positive
from ..errors import SceneError
from ..scene import Scene

#: Scene parameters of the tribometer (make_scene overrides): Table 1 steel,
#: two upper tips at 1 mN each, a stiff drive.
TRIBOMETER_SCENE = dict(base=1e-6, mass=2.88e-16, stiffness=37_200.0, flank_angle=45.0, track="free",
                        lower_count=10, upper_count=2, normal_load=2e-3,
                        drive_stiffness=372_000.0)


@dataclass(frozen=True)
class Protocol:
    """What the tribometer does (SI).

    ``velocities`` (m/s, > 0): the ladder, each driven in +x and then -x.
    ``pitches``: whole pitches of travel averaged per direction;
    ``transient_pitches``: travel discarded after each start or reversal.
    ``samples_per_pitch``: force samples per pitch of travel.
    ``amplitudes`` (m): reversal stroke amplitudes; ``reversal_velocity`` (m/s).
    """

    velocities: tuple = (1.0, 3.0, 10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0)
    pitches: int = 2
    transient_pitches: float = 1.0
    samples_per_pitch: int = 400
    amplitudes: tuple = (5e-9, 2e-8, 5e-8, 1e-7)
    reversal_velocity: float = 1.0

    def __post_init__(self):
        vel = tuple(float(v) for v in np.atleast_1d(self.velocities))
        if not vel:
            raise SceneError("`velocities` must not be empty")
        for v in vel:
            check_positive("velocities", v)
        object.__setattr__(self, "velocities", vel)
        check_int("pitches", self.pitches, minimum=1)
        check_positive("transient_pitches", self.transient_pitches)
        check_int("samples_per_pitch", self.samples_per_pitch, minimum=4)
        amps = tuple(float(a) for a in np.atleast_1d(self.amplitudes))
        for amp in amps:
            check_positive("amplitudes", amp)
        object.__setattr__(self, "amplitudes", amps)
        check_positive("reversal_velocity", self.reversal_velocity)


def make_tribometer_scene(**overrides) -> Scene:
    """The tribometer's scene: :data:`TRIBOMETER_SCENE` updated with ``overrides``."""
    from ..builders import make_scene

    return make_scene(spacing=overrides.pop("spacing", "regular"), seed=overrides.pop("seed", 0),
                      drive="spring", **{**TRIBOMETER_SCENE, **overrides})


def _run(scene: Scene, velocity: float):
    """A settled run of ``scene`` with its drive at ``velocity`` (m/s)."""
    from ..run import Run

    run = Run(scene.replace(drive=dataclasses.replace(scene.drive, velocity=velocity)))
    run.settle()
    return run


def _stroke(run, velocity: float, distance: float, every: int) -> np.ndarray:
    """Drive at ``velocity`` (m/s, signed) for ``distance`` (m) of drive travel.

    Returns rows ``(drive_x, slider_x, friction_force, normal_force)`` (m, m,
    N, N) sampled every ``every`` steps; friction resists +x motion (> 0).
    """
    run.set_drive_velocity(velocity)
    steps = max(1, int(round(distance / (abs(velocity) * run.dt))))
    start = run.samples
    run.advance(steps * run.dt, record_every=every)
    r = run.result(start=start)
    return np.column_stack([r.drive_x, r.x, r.friction_force, r.normal_force])


def _window_stats(rows: np.ndarray, pitch: float, pitches: int, sign: float) -> tuple[float, float, float]:
    """Mean and per-pitch spread of the force resisting the motion over whole pitches,
    and the fraction of samples with the slider in contact (normal force > 0)."""
    force = sign * rows[:, 2]
    travel = np.abs(rows[:, 1] - rows[0, 1])
    means = [force[(travel >= j * pitch) & (travel < (j + 1) * pitch)].mean() for j in range(pitches)]
    means = [m for m in means if np.isfinite(m)]
    return float(np.mean(means)), float(np.std(means)), float(np.mean(rows[:, 3] > 0))


@dataclass(frozen=True)
class SteadyCurve:
    """Steady-sliding friction (N) against velocity (m/s), both directions.

    ``velocity`` holds -v and +v points sorted ascending; ``force`` the mean
    friction force (signed: resisting +x motion is positive, so it has the
    sign of the velocity); ``spread`` the standard deviation of the
    per-pitch means; ``normal_load`` (N); ``contact`` the fraction of the
    window's samples with the slider touching the lower surface (below 1
    the slider lifts off the tips: not steady contact sliding). ``None``
    means not measured (treated as always in contact).
    """

    velocity: np.ndarray
    force: np.ndarray
    spread: np.ndarray
    normal_load: float
    meta: dict = field(default_factory=dict)
    contact: np.ndarray | None = None

    def to_dict(self) -> dict:
        contact = None if self.contact is None else np.asarray(self.contact).tolist()
        return {"velocity_m_per_s": self.velocity.tolist(), "friction_force_N": self.force.tolist(),
                "spread_N": self.spread.tolist(), "contact_fraction": contact,
                "normal_load_N": self.normal_load, **self.meta}


def steady_curve(scene: Scene, protocol: Protocol = Protocol()) -> SteadyCurve:
    """Mean steady friction at every ladder velocity, driven +x then -x."""
    pitch = scene.lower.spacing.mean_pitch
    v_out, f_out, s_out, c_out = [], [], [], []
    for v in protocol.velocities:
        run = _run(scene, v)
        every = max(1, int(pitch / protocol.samples_per_pitch / (v * run.dt)))
        for sign in (1.0, -1.0):
            _stroke(run, sign * v, protocol.transient_pitches * pitch, every)
            rows = _stroke(run, sign * v, protocol.pitches * pitch, every)
            mean, spread, contact = _window_stats(rows, pitch, protocol.pitches, sign)
            v_out.append(sign * v)
            f_out.append(sign * mean)
            s_out.append(spread)
            c_out.append(contact)
    order = np.argsort(v_out)
    return SteadyCurve(np.asarray(v_out)[order], np.asarray(f_out)[order], np.asarray(s_out)[order],
                       float(scene.slider.normal_load),
                       {"pitch_m": pitch, "pitches": protocol.pitches,
                        "transient_pitches": protocol.transient_pitches},
                       np.asarray(c_out)[order])


@dataclass(frozen=True)
class ReversalLoops:
    """Pre-sliding hysteresis: slider displacement (m) from rest and friction force (N) along the strokes."""

    displacement: np.ndarray
    force: np.ndarray
    drive: np.ndarray
    normal_load: float
    amplitudes: tuple

    def breakaway_displacement(self) -> float:
        """Displacement (m) at which the force first reaches 95 % of its maximum."""
        f = np.abs(self.force)
        i = int(np.argmax(f >= 0.95 * f.max()))
        return float(abs(self.displacement[i]))


def reversal_loops(scene: Scene, protocol: Protocol = Protocol(), *, samples_per_stroke: int = 200) -> ReversalLoops:
    """From rest, strokes 0 -> +a -> -a -> +a for each amplitude a (drive travel, m)."""
    v = protocol.reversal_velocity
    run = _run(scene, v)
    x0 = run.slider_state()[0]
    d0 = run.drive_position()
    parts = []
    position = 0.0
    for amp in protocol.amplitudes:
        every = max(1, int(amp / samples_per_stroke / (v * run.dt)))
        for target in (amp, -amp, amp):
            move = target - position
            if move != 0:
                parts.append(_stroke(run, math.copysign(v, move), abs(move), every))
            position = target
        # back to zero for the next amplitude
        parts.append(_stroke(run, -v, amp, every))
        position = 0.0
    rows = np.concatenate(parts)
    return ReversalLoops(displacement=rows[:, 1] - x0, force=rows[:, 2], drive=rows[:, 0] - d0,
                         normal_load=float(scene.slider.normal_load), amplitudes=protocol.amplitudes)


def energy_window(scene: Scene, *, velocity: float, pitches: int = 2, transient_pitches: float = 1.0) -> dict:
    """Energy balance over ``pitches`` of steady sliding at ``velocity`` (m/s).

    Returns the meter's report plus ``distance_m`` (slider travel),
    ``friction_times_distance_J`` (exact time-mean contact friction force x
    distance) and ``balance_error`` = abs(F·d - (dissipated + stored change)) /
    (F·d). The two differ from the meter's exact balance (drive work =
    dissipated + stored change) only by the slider's momentum change and
    the drive spring's stretch change over the window.
    """
    pitch = scene.lower.spacing.mean_pitch
    run = _run(scene, velocity)
    every = 1000
    _stroke(run, velocity, transient_pitches * pitch, every)
    meter = run.meter_energy()
    x0 = run.slider_state()[0]
    _stroke(run, velocity, pitches * pitch, every)
    report = meter.report()
    meter.detach()
    distance = run.slider_state()[0] - x0
    fd = report["mean_friction_force_N"] * distance
    rhs = report["dissipated_J"] + report["stored_energy_change_J"]
    report.update(distance_m=distance, friction_times_distance_J=fd,
                  balance_error=abs(fd - rhs) / abs(fd), velocity_m_per_s=velocity)
    return report
