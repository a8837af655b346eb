"""Stick–slip events, breakaway force and friction traces: pure functions of a Result.

Everything here reads a :class:`~asperity2d.result.Result` and returns plain
data (floats, dicts of arrays, lists of frozen :class:`Event` records); nothing
simulates. :func:`synthetic_stick_slip` is a seeded generator of a spring-driven
stick–slip series whose true events are known (in the spirit of ruptures'
``pw_constant``), used to test the detector.

Segmentation (Ooten's stick–slip: the slider stops, the drive spring loads
it, it breaks away and slips): a sample is *stick* when the slider is nearly at
rest, ``|v| < stick_speed``, and *slip* when it moves clearly faster than the
drive, ``v > slip_speed``; in between the previous state holds (hysteresis).
The slip speed follows the scene (``slip_speed_threshold``): a block that
loses no friction swings on the drive spring from rest to exactly 2 V, and a
real slip peaks above that by an amount the closed form of a spring-driven
block gives (:func:`spring_block_slip`), so the threshold sits between the two.
Slips shorter than ``min_slip`` or moving the slider less than
``min_slip_distance`` are noise (micro-slips of one contact); sticks in which
the slider is slow for less than ``min_stick`` inside a slip are bounces off
asperities, not re-sticking. Both rules look at time and distance, not at
sample counts, so the events do not depend on how often the run was recorded.
The distance rule follows the scene's own scale (``slip_scale``): a tenth
of the smallest of the asperity base, the lower surface's mean pitch and the
drive spring's stretch over one slip, so a flat block's 30 nm slips count
while an asperity's nanometre micro-slips do not.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .builders import make_scene
from .errors import SceneError
from .result import Result
from .scene import SpringDrive

#: Default stick threshold as a multiple of the drive velocity V.
STICK_SPEED_FRACTION = 0.5
#: The slip threshold's bounds, as multiples of V (``slip_speed_threshold``). A slider that
#: loses no friction (steady sliding, mu_s = mu_k, or a hold that never releases) swings on an
#: undamped drive spring from rest to exactly 2 V: that is the level of no slip. Measured on the
#: flat block of ``tests/test_analysis.py`` with mu_s = mu_k = 0.35, the start's transient lifts
#: the first swings to at most 2.18 V, so the threshold stays at least 0.25 V above 2 V. Above,
#: it never exceeds 3 V, the fixed threshold it replaces: every asperity scene's slips (the flank
#: barrier released, peaks of tens of V) clear that by far, so their events are unchanged.
NO_SLIP_PEAK_FRACTION = 2.0
SLIP_MARGIN_FRACTION = 0.25
SLIP_SPEED_FRACTION = 3.0
#: Default minimum durations as fractions of the slider's period on the drive spring.
MIN_STICK_PERIODS = 0.5
MIN_SLIP_PERIODS = 0.1
#: Default minimum slip distance as a fraction of the scene's slip scale (``slip_scale``).
#: A real slip on Ooten's scenes moves the slider 0.4-10 um; a contact letting go of one
#: flank moves it 2-30 nm in under a nanosecond, near the 0.55 ns ``min_slip``, so whether it
#: counted depended on where the samples fell (measured: two extra "events" at
#: record_every=10 that record_every=1 did not see, on the same trajectory). On an asperity
#: surface the scale is the base (0.1 base = 100 nm: above those micro-slips); on a flat block
#: the drive spring's stretch over a slip is far smaller (27 nm on a 3 mN block, mu 0.5/0.35,
#: on 37.2 kN/m) and sets it.
MIN_SLIP_FRACTION = 0.1


def _barrier_and_kinetic(scene) -> tuple[float, float]:
    """(static barrier, kinetic level) of the drive force (N): the flank law ``L tan(theta + atan
    mu_s)`` and ``mu_k L`` for the free slider under load ``L`` (``mu_s L`` on flat blocks, theta =
    0); ``n k_l delta tan(theta + atan mu_s)`` and 0 on the fixed track, which carries no load."""
    theta = math.radians(scene.lower.profile.flank_angle)
    wedge = math.tan(min(theta + math.atan(scene.contact.mu_static), math.radians(89.0)))
    if scene.slider.track == "free":
        return scene.slider.normal_load * wedge, scene.contact.mu_kinetic * scene.slider.normal_load
    return scene.slider.count * max(scene.lower.stiffness) * scene.slider.interference * wedge, 0.0


def slip_scale(scene) -> float:
    """The length (m) a stick-slip of ``scene`` is measured against: the smallest of the asperity
    base, the lower surface's mean pitch and, on a spring drive, the drive spring's stretch over
    one slip, ``2 (F_peak - F_kinetic) / k`` (the spring force swings symmetrically about the
    kinetic level).

    ``F_peak`` is the static barrier plus the overshoot ``V sqrt(k m)``: the peak of this model's
    hold rule, where a stuck contact keeps mu_s until it has slid its ``slip_distance`` and the
    force keeps rising until the slider catches up with the drive (:func:`spring_block_slip` gives
    the peak for any hold; this scale needs only its size). The barrier is the flank law ``L
    tan(theta + atan mu_s)`` for the free slider under load ``L`` (``mu_s L`` on flat blocks, theta
    = 0) and ``n k_l delta tan(theta + atan mu_s)`` on the fixed track. ``F_kinetic`` is the
    sliding friction ``mu_k L`` of the free slider (0 on the fixed track, which carries no load).
    On Ooten's asperity scenes the stretch is micrometres and the base sets the scale; on a flat
    block the stretch does.
    """
    base = scene.base
    scale = min(base, scene.lower.spacing.mean_pitch)
    drive = scene.drive
    if not isinstance(drive, SpringDrive):
        return scale
    barrier, kinetic = _barrier_and_kinetic(scene)
    peak = barrier + drive.velocity * math.sqrt(drive.stiffness * scene.slider.mass)
    return min(scale, 2.0 * (peak - kinetic) / drive.stiffness)


@dataclass(frozen=True)
class SpringBlockSlip:
    """One steady stick-slip cycle of a block on a spring drive, in closed form (SI units).

    Attributes
    ----------
    peak_force : float
        Largest drive force of the cycle (N).
    force_drop : float
        Peak less the lowest drive force during the slip (N).
    restick_force : float
        Drive force where the block sticks again (N).
    peak_speed : float
        Largest block speed in the slip (m/s).
    stick_duration, slip_duration : float
        Time stuck and time slipping (s); their sum is the period.
    release_phase : float
        omega t (rad) at which the hold releases, counted from the breakaway: 0 for the classical
        instant switch, at least pi/2 when the hold rule sets the peak; ``nan`` if it never does.
    released : bool
        False when the block swings back to rest before sliding its hold distance: it never
        drops to the kinetic force, peaks at exactly 2 V and makes no slip.
    """

    peak_force: float
    force_drop: float
    restick_force: float
    peak_speed: float
    stick_duration: float
    slip_duration: float
    release_phase: float
    released: bool

    @property
    def period(self) -> float:
        """Stick plus slip (s)."""
        return self.stick_duration + self.slip_duration


def spring_block_slip(*, stiffness: float, mass: float, velocity: float, static_force: float,
                      kinetic_force: float, hold_distance: float = 0.0) -> SpringBlockSlip:
    """The closed-form stick-slip cycle of a block on a spring whose far end moves at ``velocity``,
    with this model's hold rule.

    The block (mass m) is stuck until the spring (stiffness k) pulls with ``static_force`` F_s;
    its contact then keeps F_s until the block has slid ``hold_distance`` d (this model's rule: a
    stuck contact keeps mu_s until it has slid ``slip_distance``), and slides at
    ``kinetic_force`` F_k after that until it comes to rest, where it sticks again. With omega =
    sqrt(k / m), the hold lasts until omega t = theta, ``theta - sin(theta) = omega d / V``; it
    leaves the spring force F_s + V sqrt(k m) sin(theta) and the block speed V (1 - cos(theta)), and
    the slip at F_k is harmonic about F_k with amplitude

        A = sqrt((V sqrt(k m) sin(theta) + F_s - F_k)**2 + k m V**2 cos(theta)**2).

    Two limits, each the peak force in its own regime:

    * **classical** (d = 0, theta = 0; J. P. Den Hartog's spring-driven block, the instant switch
      to kinetic friction): the peak is ``F_k + sqrt((F_s - F_k)**2 + k m V**2)``, reached once
      the block has caught up with the drive, and the drop is twice the amplitude;
    * **hold rule** (omega d / V >= pi/2 - 1, theta >= pi/2: the block catches up with the drive,
      0.57 V / omega into the slip, before it has slid d): the peak is ``F_s + V sqrt(k m)``, the
      force's overshoot while the contact still holds F_s, and the drop is ``F_s - F_k + V sqrt(k
      m) + A``.

    In between (0 < theta < pi/2) the peak is ``F_k + A``. The block's peak speed is ``V + A /
    sqrt(k m)`` (or the hold's own 2 V when it lasts past theta = pi and that is more); it sticks
    again at ``F_k - sqrt(A**2 - k m V**2)``, and if A is under V sqrt(k m) (a release late in a
    swing with a small gap) it never comes back to rest but slides on about V (``restick_force``
    and ``stick_duration`` NaN, the slip endless). When omega d / V >= 2 pi the hold outlasts a
    whole swing: the block swings from rest to 2 V and back at F_s, with no
    friction drop (``released`` False). The model itself counts the hold's slip on until the slip
    speed falls under the contact's ``stick_speed``, which a swing that only touches rest may not
    do, so there it can release after several swings: the closed form does not describe that case.

    Parameters
    ----------
    stiffness : float
        Drive spring stiffness k (N/m), > 0.
    mass : float
        Block mass m (kg), > 0.
    velocity : float
        Drive speed V (m/s), > 0.
    static_force, kinetic_force : float
        The static barrier F_s and the sliding force F_k (N), F_s >= F_k >= 0.
    hold_distance : float, default 0.0
        Slip (m) before the contact drops to F_k (0: the classical instant switch).

    Returns
    -------
    SpringBlockSlip

    Raises
    ------
    SceneError
        A value out of range (named).

    Examples
    --------
    Classical and hold-rule peaks of a 3 mN block (mu 0.5 / 0.35) on 37.2 kN/m at 5 m/s:

    >>> from asperity2d.analysis import spring_block_slip
    >>> block = dict(stiffness=37.2e3, mass=2.88e-15, velocity=5.0, static_force=1.5e-3,
    ...              kinetic_force=1.05e-3)
    >>> classical = spring_block_slip(**block)
    >>> held = spring_block_slip(**block, hold_distance=1e-9)
    >>> f"{classical.peak_force * 1e3:.4f} mN, {held.peak_force * 1e3:.4f} mN"
    '1.5030 mN, 1.5518 mN'
    >>> f"{classical.peak_speed / 5.0:.2f} V, {held.peak_speed / 5.0:.2f} V"
    '9.75 V, 10.69 V'
    """
    k = _positive("stiffness", stiffness)
    m = _positive("mass", mass)
    V = _positive("velocity", velocity)
    Fk = _nonnegative("kinetic_force", kinetic_force)
    Fs = _nonnegative("static_force", static_force)
    d = _nonnegative("hold_distance", hold_distance)
    if Fs < Fk:
        raise SceneError(f"`static_force` ({Fs!r}) must be >= `kinetic_force` ({Fk!r})")
    omega, impedance = math.sqrt(k / m), math.sqrt(k * m)
    swing = V * impedance  # the overshoot a free swing on the spring adds to the force
    reach = omega * d / V  # theta - sin(theta) at the release
    if reach >= 2.0 * math.pi:  # back at rest before the hold has slid d: no friction drop
        return SpringBlockSlip(peak_force=Fs + swing, force_drop=2.0 * swing, restick_force=Fs,
                               peak_speed=2.0 * V, stick_duration=0.0, slip_duration=2.0 * math.pi / omega,
                               release_phase=math.nan, released=False)
    from scipy.optimize import brentq

    theta = 0.0 if reach == 0 else brentq(lambda th: th - math.sin(th) - reach, 0.0, 2.0 * math.pi,
                                          xtol=1e-15, rtol=4 * np.finfo(float).eps)
    excess = swing * math.sin(theta) + (Fs - Fk)  # spring force above F_k at the release
    lag = -V * math.cos(theta)  # block speed less V at the release
    amplitude = math.hypot(excess, impedance * lag)
    held_peak = Fs + swing if theta >= math.pi / 2 else -math.inf  # reached while still held
    peak = max(held_peak, Fk + amplitude)
    # a hold that outlasts half a swing (theta > pi) has already carried the block at 2 V
    fastest = max(V + amplitude / impedance, 2.0 * V if theta > math.pi else 0.0)
    if amplitude < swing:  # released late in a swing with a small gap: it never comes back to rest
        return SpringBlockSlip(peak_force=peak, force_drop=peak - (Fk - amplitude), restick_force=math.nan,
                               peak_speed=fastest, stick_duration=math.nan, slip_duration=math.inf,
                               release_phase=theta, released=True)
    restick = Fk - math.sqrt(amplitude ** 2 - swing ** 2)
    start = math.atan2(impedance * lag, excess)  # phase of (force, speed) at the release
    end = math.pi + math.asin(swing / amplitude)  # back at rest, force falling
    return SpringBlockSlip(peak_force=peak, force_drop=peak - (Fk - amplitude), restick_force=restick,
                           peak_speed=fastest, stick_duration=(Fs - restick) / (k * V),
                           slip_duration=(theta + end - start) / omega, release_phase=theta, released=True)


def _positive(name: str, value) -> float:
    value = float(value)
    if not (math.isfinite(value) and value > 0):
        raise SceneError(f"`{name}` must be a finite number > 0, got {value!r}")
    return value


def _nonnegative(name: str, value) -> float:
    value = float(value)
    if not (math.isfinite(value) and value >= 0):
        raise SceneError(f"`{name}` must be a finite number >= 0, got {value!r}")
    return value


def scene_slip(scene) -> SpringBlockSlip | None:
    """The closed-form cycle (:func:`spring_block_slip`) of ``scene``'s slider on its drive spring,
    with the scene's static barrier and kinetic level (as :func:`slip_scale`) and its contacts' hold
    distance (``slip_distance``, default 0.001 base); None without a spring drive."""
    drive = scene.drive
    if not isinstance(drive, SpringDrive):
        return None
    barrier, kinetic = _barrier_and_kinetic(scene)
    hold = scene.contact.slip_distance
    hold = 1e-3 * scene.base if hold is None else hold  # the engine's default (engine.contacts)
    return spring_block_slip(stiffness=drive.stiffness, mass=scene.slider.mass, velocity=drive.velocity,
                             static_force=barrier, kinetic_force=min(kinetic, barrier), hold_distance=hold)


def _min_stick(scene, period: float | None) -> float | None:
    """The default ``min_stick`` (s): half the slider's period on the drive spring, or half the
    closed-form stick of ``scene_slip`` when that is shorter. A flat block with a small
    static/kinetic gap sticks for less than half a period (mu 0.36 / 0.35 on the test block: 0.29
    of a period), so a whole-period rule took its real sticks for bounces; on asperity scenes the
    drive reloads a whole flank barrier and the stick lasts hundreds of periods: unchanged."""
    if period is None:
        return None
    cycle = scene_slip(scene)
    if cycle is None or not cycle.released:
        return MIN_STICK_PERIODS * period
    return min(MIN_STICK_PERIODS * period, 0.5 * cycle.stick_duration)


def slip_speed_threshold(scene) -> float | None:
    """The default ``slip_speed`` (m/s) of :func:`stick_slip_events` for ``scene``; None without a
    spring drive.

    A slider that loses no friction swings on the drive spring from rest to exactly 2 V (V the
    drive speed): that is the speed of no slip. A real slip of the scene peaks at the closed-form
    ``peak_speed`` of ``scene_slip`` (the spring-driven block with the hold rule: V plus the
    slip's amplitude over sqrt(k m)). The threshold is halfway between the two, at least
    ``SLIP_MARGIN_FRACTION`` V above 2 V (the start's transient, measured up to 2.18 V with no
    friction drop) and at most 3 V (every asperity scene's slips, tens of V, clear that; so their
    events do not move). On the flat block of ``tests/test_analysis.py`` with mu 0.36 / 0.35 the
    closed form's peak is 2.58 V, the threshold 2.29 V.
    """
    drive = scene.drive
    if not isinstance(drive, SpringDrive):
        return None
    V = drive.velocity
    cycle = scene_slip(scene)
    above = 0.5 * (cycle.peak_speed / V - NO_SLIP_PEAK_FRACTION)
    above = min(max(above, SLIP_MARGIN_FRACTION), SLIP_SPEED_FRACTION - NO_SLIP_PEAK_FRACTION)
    return (NO_SLIP_PEAK_FRACTION + above) * V


@dataclass(frozen=True)
class Event:
    """One stick–slip cycle (SI units).

    ``t_stick`` (s): start of the stick phase; ``t_slip`` (s): stick-to-slip
    transition (the sample where the drive force peaks, just before the slider
    overtakes the drive); ``t_end`` (s): end of the slip (re-stick, or the end
    of the run when ``complete`` is False); ``force_peak`` (N): drive force at
    ``t_slip``; ``force_drop`` (N): peak minus the lowest drive force during
    the slip; ``slip_distance`` (m): slider travel from ``t_slip`` to ``t_end``;
    ``stick_duration`` (s) = ``t_slip - t_stick``.

    Attributes
    ----------
    t_stick, t_slip, t_end : float
        Start of the stick, the stick-to-slip transition, end of the slip (s).
    force_peak, force_drop : float
        Drive force at ``t_slip`` and its fall during the slip (N).
    slip_distance : float
        Slider travel during the slip (m).
    stick_duration : float
        ``t_slip - t_stick`` (s).
    complete : bool, default True
        False when the run ended during the slip.

    See Also
    --------
    asperity2d.stick_slip_events : the events of a run.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> event = a.stick_slip_events(result)[0]
    >>> event.complete, f"{event.force_drop * 1e3:.3g} mN"
    (True, '9.21 mN')
    """

    t_stick: float
    t_slip: float
    t_end: float
    force_peak: float
    force_drop: float
    slip_distance: float
    stick_duration: float
    complete: bool = True


#: the columns of :func:`events_table`, in order: :class:`Event`'s fields
EVENT_COLUMNS = ("t_stick", "t_slip", "t_end", "force_peak", "force_drop", "slip_distance", "stick_duration",
                 "complete")


def events_table(events, path=None) -> dict:
    """Events as a table: column name -> array, one row per event; written as CSV to ``path`` if given.

    No pandas needed; with pandas, ``pandas.DataFrame(events_table(events))`` is the data frame.

    Parameters
    ----------
    events : sequence of Event
        Events of a run (:func:`stick_slip_events`).
    path : str or os.PathLike, optional
        A ``.csv`` file to write (atomically): a header line of ``EVENT_COLUMNS``, SI units,
        ``complete`` as 1 or 0.

    Returns
    -------
    dict
        ``EVENT_COLUMNS`` -> NumPy array (float64; ``complete`` bool), each with one entry per event.

    Examples
    --------
    >>> import asperity2d as a
    >>> events = a.stick_slip_events(a.simulate(a.make_scene(lower_count=4, upper_count=2)))
    >>> table = a.events_table(events, "events.csv")
    >>> [f"{f * 1e3:.3g} mN" for f in table["force_drop"]], table["complete"].tolist()
    (['9.21 mN', '11.7 mN'], [True, False])
    >>> open("events.csv").readline().strip()
    't_stick,t_slip,t_end,force_peak,force_drop,slip_distance,stick_duration,complete'
    """
    from ._io import atomic_write

    rows = list(events)
    if not all(isinstance(e, Event) for e in rows):
        raise SceneError("`events` must be a sequence of Event (stick_slip_events(result))")
    table = {name: np.array([getattr(e, name) for e in rows], dtype=bool if name == "complete" else float)
             for name in EVENT_COLUMNS}
    if path is not None:
        if not str(path).lower().endswith(".csv"):
            raise SceneError(f"`path` must end in .csv, got {str(path)!r}")
        columns = np.column_stack([table[n].astype(float) for n in EVENT_COLUMNS]) if rows else np.zeros((0, 8))

        def write(fh):
            np.savetxt(fh, columns, delimiter=",", header=",".join(EVENT_COLUMNS), comments="", fmt="%.17g")

        atomic_write(path, write)
    return table


def _asperity_run(result) -> None:
    """Raise SceneError unless ``result`` is an asperity run (a Result, or a record read lazily)."""
    if getattr(result, "kind", "asperity") != "asperity" or getattr(result, "scene", None) is None:
        what = "a belt chain" if getattr(result, "kind", None) == "belt" else type(result).__name__
        hint = ("; a chain's sticks and slips are its `stick_intervals` and `events` (asperity2d.belt)"
                if what == "a belt chain" else "")
        raise SceneError(f"`result` must be an asperity run (asperity2d.simulate), got {what}{hint}")


def _drive_scales(result) -> tuple[float | None, float | None]:
    """(drive velocity m/s, slider period on the drive spring s), or Nones."""
    _asperity_run(result)
    drive = result.scene.drive
    if not isinstance(drive, SpringDrive):
        return None, None
    return drive.velocity, 2.0 * math.pi * math.sqrt(result.scene.slider.mass / drive.stiffness)


def _runs(state: np.ndarray) -> list[list[int]]:
    """Runs of equal values as [value, start, stop) lists."""
    if len(state) == 0:
        return []
    cuts = np.flatnonzero(np.diff(state)) + 1
    starts = np.concatenate(([0], cuts))
    stops = np.concatenate((cuts, [len(state)]))
    return [[int(state[a]), int(a), int(b)] for a, b in zip(starts, stops)]


def _merge(runs: list[list[int]]) -> list[list[int]]:
    out: list[list[int]] = []
    for run in runs:
        if out and out[-1][0] == run[0]:
            out[-1][2] = run[2]
        else:
            out.append(list(run))
    return out


def _thresholds(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance) -> dict:
    """The detector's thresholds (SI): the given ones, the scene's defaults for the rest."""
    speed, period = _drive_scales(result)
    defaults = {"stick_speed": (stick_speed, STICK_SPEED_FRACTION, speed),
                "slip_speed": (slip_speed, 1.0, slip_speed_threshold(result.scene)),
                "min_stick": (min_stick, 1.0, _min_stick(result.scene, period)),
                "min_slip": (min_slip, MIN_SLIP_PERIODS, period),
                "min_slip_distance": (min_slip_distance, MIN_SLIP_FRACTION, slip_scale(result.scene))}
    values = {}
    for name, (given, fraction, scale) in defaults.items():
        if given is None:
            if scale is None:
                raise SceneError(f"`{name}` must be given for a run without a spring drive")
            given = fraction * scale
        if not math.isfinite(given) or given < 0:
            raise SceneError(f"`{name}` must be a finite number >= 0, got {given!r}")
        values[name] = float(given)
    if values["slip_speed"] <= values["stick_speed"]:
        raise SceneError(f"`slip_speed` ({values['slip_speed']!r}) must be > "
                         f"`stick_speed` ({values['stick_speed']!r})")
    return values


def stick_slip_events(result, *, stick_speed: float | None = None, slip_speed: float | None = None,
                      min_stick: float | None = None, min_slip: float | None = None,
                      min_slip_distance: float | None = None) -> list[Event]:
    """Segment the slider's motion into stick–slip events.

    Parameters
    ----------
    result : Result
        A run (spring drive for the defaults; any drive with explicit values).
    stick_speed : float, optional
        abs(v) below this (m/s) is stick. Default: 0.5 x the drive velocity.
    slip_speed : float, optional
        v above this (m/s) is slip. Default: ``slip_speed_threshold``, from
        the scene's own scales: halfway between 2 V (a slider that loses no
        friction, released from rest on the drive spring, peaks at exactly
        2 V) and the closed-form peak speed of the scene's slips, between
        2.25 V and 3 V.
    min_stick : float, optional
        A stick shorter than this (s) between two slips is a bounce, merged
        into the slip. Default: half the slider's period on the drive spring,
        or half the closed-form stick (``scene_slip``) if shorter.
    min_slip : float, optional
        A slip shorter than this (s) is ignored. Default: 0.1 of that period.
    min_slip_distance : float, optional
        A slip moving the slider less than this (m) is ignored. Default: 0.1
        of ``slip_scale`` (the asperity base on Ooten's scenes, the drive
        spring's stretch over a slip on a flat block).

    Returns
    -------
    list of Event
        In time order. The last one has ``complete=False`` when the run ended
        during its slip. A slip needs a stick before it: motion before the
        first stick is not an event.

    Raises
    ------
    SceneError
        A threshold is negative or not finite, ``slip_speed`` is not above
        ``stick_speed``, or a default is needed for a run without a spring drive.

    See Also
    --------
    asperity2d.breakaway_force : one force out of these events.
    asperity2d.peak_stick_force
    asperity2d.mean_stick_force
    asperity2d.event_statistics : their counts, means and regularity.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> events = a.stick_slip_events(result)
    >>> len(events)
    2
    >>> first = events[0]
    >>> print(f"slips at {first.t_slip:.3g} s under {first.force_peak * 1e3:.3g} mN, "
    ...       f"moves {first.slip_distance * 1e6:.3g} um")
    slips at 1.39e-07 s under 6.33 mN, moves 2.43 um
    """
    values = _thresholds(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance)
    speed, _ = _drive_scales(result)
    t, v, x, force = (np.asarray(a, dtype=float) for a in (result.t, result.v, result.x,
                                                             result.drive_force))
    if len(t) < 2:
        return []
    # +1 slip, -1 stick, 0 dead band (keeps the previous state); leading 0: unknown.
    label = np.where(v > values["slip_speed"], 1, np.where(np.abs(v) < values["stick_speed"], -1, 0))
    idx = np.where(label != 0, np.arange(len(v)), 0)
    np.maximum.accumulate(idx, out=idx)
    state = np.where(label[idx] != 0, label[idx], 0)
    runs = _runs(state)
    edge = np.append(t, t[-1] + (t[-1] - t[-2]))  # run [a, b) lasts edge[b] - edge[a]

    def noise(r):  # a slip too short in time or in distance (from the sample before it)
        moved = x[min(r[2], len(x) - 1)] - x[max(r[1] - 1, 0)]
        return edge[r[2]] - edge[r[1]] < values["min_slip"] or moved < values["min_slip_distance"]

    runs = _merge([[-1 if (r[0] == 1 and noise(r)) else r[0], r[1], r[2]] for r in runs])
    # A stick is judged by the time the slider is really slow in it, not by the run's length:
    # the hysteresis holds "stick" through the dead band, so a slider swinging freely on the
    # drive spring after a slip (no contact, v from -1.4 V to 3.4 V, measured) would otherwise
    # log a "stick" every drive period (events 110 nm = V x period apart at 0.2-0.8 mN).
    slow_time = np.concatenate(([0.0], np.cumsum(np.diff(edge) * (np.abs(v) < values["stick_speed"]))))
    for i, r in enumerate(runs):
        if r[0] == -1 and i > 0 and runs[i - 1][0] == 1 and slow_time[r[2]] - slow_time[r[1]] < values["min_stick"]:
            r[0] = 1  # a bounce inside a slip (or a stop too short to trust at the end)
    runs = _merge(runs)

    drive_velocity = speed if speed is not None else 0.0
    events = []
    for i in range(1, len(runs)):
        (prev, s0, _), (kind, a, b) = runs[i - 1], runs[i]
        if kind != 1 or prev != -1:
            continue
        # Onset: the drive force peaks where the slider overtakes the drive; search the
        # samples from the last one not yet faster than the drive to the first fast one.
        slow = np.flatnonzero(v[s0:a] <= max(drive_velocity, values["stick_speed"]))
        lo = s0 + (int(slow[-1]) if len(slow) else a - s0 - 1)
        onset = lo + int(np.argmax(force[lo:a + 1]))
        complete = b < len(t)
        end = b if complete else len(t) - 1
        peak = float(force[onset])
        events.append(Event(
            t_stick=float(t[s0]), t_slip=float(t[onset]), t_end=float(t[end]),
            force_peak=peak, force_drop=peak - float(np.min(force[onset:end + 1])),
            slip_distance=float(x[end] - x[onset]), stick_duration=float(t[onset] - t[s0]),
            complete=complete))
    return events


def event_statistics(events: list[Event]) -> dict:
    """Summary of stick–slip events.

    Returns a dict: ``count``; ``force_drop_mean`` / ``force_drop_std`` (N)
    and ``slip_distance_mean`` (m) over complete events (an unfinished last
    slip has a truncated drop); ``stick_duration_mean`` / ``_std`` (s) over all
    events; ``interval_mean`` (s) and ``regularity``: the coefficient of
    variation (std / mean) of the intervals between successive ``t_slip``
    (0 for perfectly periodic stick–slip). Standard deviations use ddof=1;
    quantities with too few events are NaN.

    Parameters
    ----------
    events : list of Event
        The events of one run, in time order (:func:`~asperity2d.stick_slip_events`).

    Returns
    -------
    dict
        The keys above, each a float (``count``: an int); SI units.

    See Also
    --------
    asperity2d.stick_slip_events : the events.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> stats = a.event_statistics(a.stick_slip_events(result))
    >>> stats["count"], f"{stats['force_drop_mean'] * 1e3:.3g} mN"
    (2, '9.21 mN')
    >>> stats["regularity"]  # two events make one interval: no spread to measure
    nan
    """
    def mean_std(values):
        a = np.asarray(values, dtype=float)
        mean = float(a.mean()) if len(a) else math.nan
        return mean, (float(a.std(ddof=1)) if len(a) > 1 else math.nan)

    complete = [e for e in events if e.complete]
    drop_mean, drop_std = mean_std([e.force_drop for e in complete])
    stick_mean, stick_std = mean_std([e.stick_duration for e in events])
    intervals = np.diff([e.t_slip for e in events])
    interval_mean, interval_std = mean_std(intervals)
    return {
        "count": len(events),
        "force_drop_mean": drop_mean, "force_drop_std": drop_std,
        "slip_distance_mean": mean_std([e.slip_distance for e in complete])[0],
        "stick_duration_mean": stick_mean, "stick_duration_std": stick_std,
        "interval_mean": interval_mean,
        "regularity": interval_std / interval_mean if interval_mean > 0 else math.nan,
    }


def breakaway_force(result, *, stick_speed: float | None = None, slip_speed: float | None = None,
                    min_stick: float | None = None, min_slip: float | None = None,
                    min_slip_distance: float | None = None) -> float:
    """The first breakaway: drive force (N) at the first stick-to-slip transition of a
    spring-driven run.

    A free
    slider under load L on 45° flanks and regular spacing breaks away at the
    quasi-static L tan(45° + atan mu_s). On Ooten's fixed track the first
    breakaway is the front tip entering the surface alone, the same for every
    spacing: see :func:`~asperity2d.peak_stick_force` and :func:`~asperity2d.mean_stick_force` for the
    engaged slider.

    Parameters
    ----------
    result : Result
        A spring-driven run (``make_scene(drive="spring")``, the default).
    stick_speed, slip_speed, min_stick, min_slip, min_slip_distance : float, optional
        The event thresholds (m/s, s, m) of :func:`~asperity2d.stick_slip_events`, with its defaults.

    Returns
    -------
    float
        The drive force (N) at the first stick-to-slip transition.

    Raises
    ------
    SceneError
        The run is not spring-driven, or never breaks away (named `result`).

    See Also
    --------
    asperity2d.peak_stick_force : the largest force at a transition (the engaged slider).
    asperity2d.mean_stick_force : their mean.
    asperity2d.critical_force : the smallest constant force that carries the slider across.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> f"{a.breakaway_force(result) * 1e3:.3g} mN"
    '6.33 mN'
    """
    return _spring_events(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance)[0].force_peak


def _spring_events(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance) -> list[Event]:
    if not isinstance(getattr(getattr(result, "scene", None), "drive", None), SpringDrive):
        raise SceneError("`result` must come from a spring-driven run (drive=\"spring\")")
    events = stick_slip_events(result, stick_speed=stick_speed, slip_speed=slip_speed,
                               min_stick=min_stick, min_slip=min_slip,
                               min_slip_distance=min_slip_distance)
    if not events:
        small = stick_slip_events(result, stick_speed=stick_speed, slip_speed=slip_speed,
                                  min_stick=min_stick, min_slip=min_slip, min_slip_distance=0.0)
        if small:
            limit = _thresholds(result, stick_speed, slip_speed, min_stick, min_slip,
                                min_slip_distance)["min_slip_distance"]
            longest = max(e.slip_distance for e in small)
            raise SceneError(f"`result` has {len(small)} stick-to-slip transition(s), every one moving the "
                             f"slider less than `min_slip_distance` = {limit:.3g} m (the longest "
                             f"{longest:.3g} m): pass a smaller `min_slip_distance` to count them")
        raise SceneError("`result` has no stick-to-slip transition (the slider never broke away)")
    return events


def peak_stick_force(result, *, stick_speed: float | None = None, slip_speed: float | None = None,
                     min_stick: float | None = None, min_slip: float | None = None,
                    min_slip_distance: float | None = None) -> float:
    """Largest drive force (N) at a stick-to-slip transition over the run: the force that
    breaks the slider loose at its worst position on the surface.

    On Ooten's fixed track the first breakaway (:func:`~asperity2d.breakaway_force`)
    happens while only the front tip has entered the surface; this is the
    measure of the engaged slider. On a regular surface all n tips meet their
    lower asperities at once and it is the quasi-static flank law for all of
    them, n k delta tan(theta + atan mu_s).

    Parameters
    ----------
    result : Result
        A spring-driven run (``make_scene(drive="spring")``, the default).
    stick_speed, slip_speed, min_stick, min_slip, min_slip_distance : float, optional
        The event thresholds (m/s, s, m) of :func:`~asperity2d.stick_slip_events`, with its defaults.

    Returns
    -------
    float
        The largest drive force (N) at a stick-to-slip transition.

    Raises
    ------
    SceneError
        The run is not spring-driven, or never breaks away (named `result`).

    See Also
    --------
    asperity2d.breakaway_force : the first transition only.
    asperity2d.mean_stick_force : the mean over the transitions.

    Examples
    --------
    On a regular surface the peak is, within 1 %, the flank law for both tips at once:

    >>> import math
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> result = a.simulate(scene)
    >>> f"{a.peak_stick_force(result) * 1e3:.3g} mN"
    '17.2 mN'
    >>> flank = math.tan(math.radians(45) + math.atan(scene.contact.mu_static))
    >>> law = scene.slider.count * scene.lower.stiffness[0] * scene.slider.interference * flank
    >>> f"{law * 1e3:.3g} mN"
    '17.3 mN'
    """
    events = _spring_events(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance)
    return max(e.force_peak for e in events)


def mean_stick_force(result, *, stick_speed: float | None = None, slip_speed: float | None = None,
                     min_stick: float | None = None, min_slip: float | None = None,
                    min_slip_distance: float | None = None) -> float:
    """Mean drive force (N) at the stick-to-slip transitions of the run: the typical force
    at which the slider breaks loose over a pass.

    Less sensitive than :func:`~asperity2d.peak_stick_force` to the one worst position of a pass (which
    position a pass sticks at is chaotic), so it needs fewer seeds for a verdict.

    Parameters
    ----------
    result : Result
        A spring-driven run (``make_scene(drive="spring")``, the default).
    stick_speed, slip_speed, min_stick, min_slip, min_slip_distance : float, optional
        The event thresholds (m/s, s, m) of :func:`~asperity2d.stick_slip_events`, with its defaults.

    Returns
    -------
    float
        The mean drive force (N) at the stick-to-slip transitions.

    Raises
    ------
    SceneError
        The run is not spring-driven, or never breaks away (named `result`).

    See Also
    --------
    asperity2d.peak_stick_force, asperity2d.breakaway_force, asperity2d.stick_slip_events

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> f"{a.mean_stick_force(result) * 1e3:.3g} mN"
    '11.8 mN'
    """
    events = _spring_events(result, stick_speed, slip_speed, min_stick, min_slip, min_slip_distance)
    return float(np.mean([e.force_peak for e in events]))


def friction_traces(result, *, bins: int = 40, dynamic_range: float = 1e4) -> dict[str, np.ndarray]:
    """Friction force against displacement and velocity, for plots.

    Returns arrays (SI): ``time``, ``displacement`` (x - x[0], m),
    ``velocity`` (m/s), ``friction_force``, ``tangential_force`` and
    ``drive_force`` (N); and a binned friction–velocity curve over positive
    velocities from ``dynamic_range`` below the fastest one up to it
    (log-spaced bins; slower samples are left out): ``velocity_centers``
    (m/s), ``friction_mean`` (N) and ``bin_count``.

    Parameters
    ----------
    result : Result
        Any run.
    bins : int, default 40
        Number of log-spaced velocity bins (empty bins are dropped).
    dynamic_range : float, default 1e4
        Ratio of the fastest velocity to the slowest one binned (> 1).

    Returns
    -------
    dict of str to numpy.ndarray
        The arrays above.

    Raises
    ------
    SceneError
        ``bins`` < 1 or ``dynamic_range`` <= 1.

    See Also
    --------
    asperity2d.stick_slip_events : the same run cut into cycles.

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> traces = a.friction_traces(result, bins=8)
    >>> sorted(traces)  # doctest: +NORMALIZE_WHITESPACE
    ['bin_count', 'displacement', 'drive_force', 'friction_force', 'friction_mean', 'tangential_force',
     'time', 'velocity', 'velocity_centers']
    >>> len(traces["velocity_centers"]) <= 8
    True
    """
    _asperity_run(result)
    if int(bins) < 1:
        raise SceneError(f"`bins` must be >= 1, got {bins!r}")
    x, v = np.asarray(result.x, dtype=float), np.asarray(result.v, dtype=float)
    friction = np.asarray(result.friction_force, dtype=float)
    out = {"time": np.asarray(result.t, dtype=float), "displacement": x - x[0], "velocity": v,
           "friction_force": friction,
           "tangential_force": np.asarray(result.tangential_force, dtype=float),
           "drive_force": np.asarray(result.drive_force, dtype=float)}
    if not dynamic_range > 1:
        raise SceneError(f"`dynamic_range` must be > 1, got {dynamic_range!r}")
    moving = v > (v.max() / dynamic_range if len(v) else 0.0)
    moving &= v > 0
    if moving.sum() >= 2 and v[moving].max() > v[moving].min():
        edges = np.geomspace(v[moving].min(), v[moving].max() * (1 + 1e-12), int(bins) + 1)
        which = np.digitize(v[moving], edges) - 1
        count = np.bincount(which, minlength=int(bins))[: int(bins)]
        total = np.bincount(which, weights=friction[moving], minlength=int(bins))[: int(bins)]
        keep = count > 0
        out["velocity_centers"] = np.sqrt(edges[:-1] * edges[1:])[keep]
        out["friction_mean"] = total[keep] / count[keep]
        out["bin_count"] = count[keep]
    else:
        out["velocity_centers"] = out["friction_mean"] = np.empty(0)
        out["bin_count"] = np.empty(0, dtype=int)
    return out


def synthetic_stick_slip(*, n_events: int = 8, seed: int = 0, noise: float = 0.0,
                         samples_per_stick: tuple[int, int] = (80, 160), samples_per_slip: int = 20,
                         scene=None):
    """A spring-driven stick–slip series with known events (ground truth).

    The slider creeps at 3 % of the drive velocity V while stuck; each slip is
    a half-sine velocity pulse peaking at 40 V for ``samples_per_slip``
    samples, so slip onsets are exact sample indices; the drive force is the
    spring force k (x_drive - x). ``noise`` adds Gaussian noise of that many V
    to v and of that many "force rises per sample" to the force. Stick lengths
    are drawn with ``numpy.random.default_rng(seed)``.

    Returns ``(result, truth)`` where ``truth`` holds the onset sample
    indices ``slip_index`` and the re-stick indices ``end_index``.
    """
    scene = make_scene(lower_count=2, upper_count=1) if scene is None else scene
    V, k = scene.drive.velocity, scene.drive.stiffness
    dt = 1e-3 * scene.base / V
    rng = np.random.default_rng(seed)
    pieces, slip_index, end_index, n = [], [], [], 0
    for _ in range(n_events):
        stick = int(rng.integers(samples_per_stick[0], samples_per_stick[1] + 1))
        pieces.append(np.full(stick, 0.03 * V))
        slip_index.append(n + stick - 1)  # last stick sample: the force peak
        pulse = 40.0 * V * np.sin(np.pi * np.arange(1, samples_per_slip + 1) / (samples_per_slip + 1))
        pieces.append(pulse)
        n += stick + samples_per_slip
        end_index.append(n)  # first sample of the next stick
    pieces.append(np.full(samples_per_stick[0], 0.03 * V))
    v = np.concatenate(pieces)
    t = dt * np.arange(len(v))
    x = np.concatenate(([0.0], np.cumsum(v[1:] * dt)))
    drive_x = V * t
    force = k * (drive_x - x) + rng.normal(0.0, noise * k * V * dt, len(v))
    v = v + rng.normal(0.0, noise * V, len(v))
    zeros, lower = np.zeros_like(t), np.zeros((scene.lower.count, len(t)))
    result = Result(t=t, x=x, v=v, y=zeros, vy=zeros, drive_x=drive_x, drive_force=force,
                    normal_force=zeros, friction_force=force, tangential_force=zeros,
                    contact_count=zeros, lower_dx=lower, lower_dy=lower, lower_contact=lower > 0,
                    scene=scene, meta={"dt": dt, "record_every": 1, "status": "synthetic"})
    return result, {"slip_index": np.array(slip_index), "end_index": np.array(end_index)}


# -- contact states: separated, sliding, sticking (the belt chains' vocabulary) --------------------------
@dataclass(frozen=True)
class ContactStates:
    """How the slider touched the lower surface over a run, in the belt chains' three states (SI).

    ``fractions``: time fractions {"separated", "sliding", "sticking"} (sum 1): no contact; contact
    with abs(v) >= ``stick_speed``; contact with abs(v) < ``stick_speed`` (the lower surface does not move
    along x, so v is the slip velocity). ``hops``: contact lost and regained (complete airborne
    intervals); ``passes``: slider travel over the span of the lower tips; ``hops_per_pass``;
    ``touching`` (T,): lower asperities touching at each sample; ``touching_mean`` its time
    average; ``separated_intervals``: the (t_lost, t_regained) intervals out of contact (s; the last
    may run to the end), which for the free slider (``track == "free"``) are its lift-offs.
    Times are sample times: each sample stands for the interval to the next one.
    """

    fractions: dict
    hops: int
    passes: float
    hops_per_pass: float
    touching: np.ndarray
    touching_mean: float
    separated_intervals: list
    stick_speed: float
    track: str

    @property
    def lift_off(self) -> list:
        """The free slider's lift-off intervals (empty on the fixed track, where it cannot lift)."""
        return self.separated_intervals if self.track == "free" else []

    def to_dict(self) -> dict:
        return {"fractions": dict(self.fractions), "hops": self.hops, "passes": self.passes,
                "hops_per_pass": self.hops_per_pass, "touching_mean": self.touching_mean,
                "touching_max": int(self.touching.max()) if self.touching.size else 0,
                "separated_intervals": [list(iv) for iv in self.separated_intervals],
                "lift_off_count": len(self.lift_off), "stick_speed": self.stick_speed, "track": self.track}


def contact_states(result, *, stick_speed: float | None = None) -> ContactStates:
    """Separated / sliding / sticking time fractions, hops and touching tips of an asperity run.

    ``stick_speed`` (m/s) defaults to 0.5 x the drive velocity (as :func:`~asperity2d.stick_slip_events`); a
    constant-force run needs it given.
    """
    _asperity_run(result)
    t = np.asarray(result.t, dtype=float)
    if t.size < 2:
        raise SceneError(f"`result` must have at least 2 samples, got {t.size}")
    result.require_lower("counting the touching asperities")
    if stick_speed is None:
        speed, _ = _drive_scales(result)
        if speed is None:
            raise SceneError("`stick_speed` must be given for a constant-force drive (no drive velocity)")
        stick_speed = STICK_SPEED_FRACTION * speed
    if not (isinstance(stick_speed, (int, float, np.floating)) and np.isfinite(stick_speed) and stick_speed > 0):
        raise SceneError(f"`stick_speed` must be > 0, got {stick_speed!r}")
    weight = np.diff(t, append=t[-1])  # sample k stands for [t_k, t_k+1)
    contact = np.asarray(result.contact_count) > 0
    slow = np.abs(np.asarray(result.v, dtype=float)) < stick_speed
    total = float(weight.sum())
    fractions = {"separated": float(weight[~contact].sum() / total),
                 "sliding": float(weight[contact & ~slow].sum() / total),
                 "sticking": float(weight[contact & slow].sum() / total)}
    runs = _runs(contact.astype(int))
    separated = [(float(t[a]), float(t[b]) if b < t.size else float(t[-1])) for value, a, b in runs if value == 0]
    hops = sum(1 for k, (value, a, b) in enumerate(runs) if value == 0 and 0 < k < len(runs) - 1)
    touching = np.asarray(result.lower_contact).sum(axis=0).astype(int)
    tips = result.scene.lower.tips()
    span = float(np.max(tips) - np.min(tips)) if tips.size > 1 else 0.0
    passes = float(abs(result.x[-1] - result.x[0]) / span) if span > 0 else float("nan")
    return ContactStates(fractions=fractions, hops=int(hops), passes=passes,
                         hops_per_pass=hops / passes if passes > 0 else float("nan"), touching=touching,
                         touching_mean=float(np.sum(weight * touching) / total), separated_intervals=separated,
                         stick_speed=float(stick_speed), track=result.scene.slider.track)
