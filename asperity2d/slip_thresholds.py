"""The detector's thresholds in closed form: the spring-driven block's stick-slip cycle
(:func:`spring_block_slip`, :class:`SpringBlockSlip`), a scene's cycle (:func:`scene_slip`) and the
default thresholds of :func:`~asperity2d.stick_slip_events` it sets (:func:`slip_speed_threshold`,
:func:`slip_scale`, the ``*_FRACTION`` and ``*_PERIODS`` constants). Pure functions of a scene;
nothing simulates. ``asperity2d.analysis`` re-exports every name here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SceneError
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
