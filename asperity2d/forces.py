"""Force measures of a spring-driven run: the first breakaway (:func:`breakaway_force`), the
largest and the mean force at a stick-to-slip transition (:func:`peak_stick_force`,
:func:`mean_stick_force`), all read at :func:`~asperity2d.stick_slip_events`' transitions, and the
friction force against the slip speed (:func:`friction_traces`). Pure functions of a Result;
nothing simulates. ``asperity2d.analysis`` re-exports every name here.
"""

from __future__ import annotations

import numpy as np

from .errors import SceneError
from .events import Event, _asperity_run, _thresholds, stick_slip_events
from .scene import SpringDrive


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
