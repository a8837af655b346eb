"""Signals out of results, and resampling onto a uniform time grid.

Both models' results are plain SI arrays; :func:`signal` picks one scalar
series by name so every tool in :mod:`asperity2d.dynamics` takes ``(t, y)``:

* belt chains (:class:`~asperity2d.belt.BeltResult`), per mass ``mass``
  (0-based, like ``Event.mass``): ``"x"`` (m), ``"v"`` (m/s),
  ``"slip_velocity"`` (v - V, m/s), ``"acceleration"`` (m/s², exactly the net
  force over the mass: spring + damper + friction), ``"friction_force"``,
  ``"spring_force"``, ``"damper_force"`` (N);
* asperity runs (:class:`~asperity2d.result.Result`), the slider: ``"x"``,
  ``"v"``, ``"acceleration"`` (m/s², the horizontal force balance
  (drive_force - friction_force) / slider mass, exact on both tracks because
  the track is horizontal), ``"drive_force"``, ``"friction_force"``,
  ``"normal_force"`` (N).

Belt results are sampled uniformly *plus* at every switching instant, so
their grid is not uniform; spectra and sound need :func:`resample` first.
"""

from __future__ import annotations

import numpy as np

from ..errors import SceneError

BELT_SIGNALS = ("x", "v", "slip_velocity", "acceleration", "friction_force", "spring_force", "damper_force")
ASPERITY_SIGNALS = ("x", "v", "acceleration", "drive_force", "friction_force", "normal_force")
UNITS = {"x": "m", "v": "m/s", "slip_velocity": "m/s", "acceleration": "m/s²", "friction_force": "N",
         "spring_force": "N", "damper_force": "N", "drive_force": "N", "normal_force": "N"}


def is_belt(result) -> bool:
    """True for a belt-chain result (it carries per-mass ``stick_intervals``)."""
    return hasattr(result, "stick_intervals")


def belt_speed(result, t) -> np.ndarray:
    """Belt speed (m/s) of a belt result at times ``t``."""
    if result.chain is None:
        raise SceneError("`result` was saved with a callable belt speed, which cannot be re-evaluated")
    return np.asarray(result.chain.belt_velocity(np.asarray(t, dtype=float)), dtype=float)


def signal(result, name: str = "v", *, mass: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``(t, y)``: the series ``name`` of ``result`` (see the module docstring), SI units.

    Parameters
    ----------
    result : Result or BeltResult
        A run of either model.
    name : str, default "v"
        The series (``"x"``, ``"v"``, ``"friction"``, ...; see the module docstring).
    mass : int, default 0
        The mass of a belt chain (0-based).

    Returns
    -------
    tuple of numpy.ndarray
        ``(t, y)``.

    Raises
    ------
    SceneError
        An unknown name or mass.

    See Also
    --------
    asperity2d.dynamics.spectrum, asperity2d.dynamics.limit_cycle : what to do with it.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> len(t) == len(v), float(v.max())  # the mass never outruns the belt by much
    (True, 0.1)
    """
    if is_belt(result):
        if name not in BELT_SIGNALS:
            raise SceneError(f"`signal` must be one of {', '.join(BELT_SIGNALS)} for a belt chain, got {name!r}")
        if isinstance(mass, bool) or not isinstance(mass, (int, np.integer)) or not 0 <= mass < result.n:
            raise SceneError(f"`mass` must be an index 0..{result.n - 1}, got {mass!r}")
        t = result.t
        if name == "slip_velocity":
            return t, result.v[mass] - belt_speed(result, t)
        if name == "acceleration":
            if result.chain is None:
                raise SceneError("`result` has no chain (masses) to turn forces into an acceleration")
            force = result.spring_force[mass] + result.damper_force[mass] + result.friction_force[mass]
            return t, force / result.chain.masses[mass]
        return t, np.asarray(getattr(result, name)[mass], dtype=float)
    if name not in ASPERITY_SIGNALS:
        raise SceneError(f"`signal` must be one of {', '.join(ASPERITY_SIGNALS)} for an asperity run, got {name!r}")
    if name == "acceleration":
        return result.t, (result.drive_force - result.friction_force) / result.scene.slider.mass
    return result.t, np.asarray(getattr(result, name), dtype=float)


def check_series(t, y, *, minimum: int = 8) -> tuple[np.ndarray, np.ndarray]:
    """``t``, ``y`` as float arrays: 1-D, same length, finite, ``t`` non-decreasing (SceneError otherwise)."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    if t.ndim != 1 or y.shape != t.shape:
        raise SceneError(f"`t` and `y` must be 1-D of equal length, got shapes {t.shape} and {y.shape}")
    if t.size < minimum:
        raise SceneError(f"`y` must have at least {minimum} samples, got {t.size}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(y))):
        raise SceneError("`y` and `t` must be finite (no NaN or infinity)")
    if np.any(np.diff(t) < 0) or t[-1] <= t[0]:
        raise SceneError("`t` must be non-decreasing and span a positive time")
    return t, y


def resample(t, y, *, dt: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``y`` linearly interpolated onto a uniform grid of step ``dt`` (s) from ``t[0]``.

    ``dt`` defaults to the median sample spacing, which for belt results is
    the solver's uniform spacing (event times only add extra samples).
    Repeated times (an event sample that coincides with a uniform one) keep
    the last value. Linear interpolation errs by at most dt²/8 · max abs(y'');
    for exact values on a uniform grid run the belt solver with
    ``include_events=False`` instead.

    Parameters
    ----------
    t, y : array_like
        Times (s) and values.
    dt : float, optional
        Step (s).

    Returns
    -------
    tuple of numpy.ndarray
        The uniform times and the values there.

    See Also
    --------
    asperity2d.dynamics.spectrum : resamples first.

    Examples
    --------
    >>> from asperity2d import belt, dynamics
    >>> chain = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...             v_belt=0.1, x0=[0.0], v0=[0.1], t_end=20.0)
    >>> result = belt.simulate_chain(**chain)  # one mass, stick-slip on the belt
    >>> t, v = dynamics.signal(result, 'v')
    >>> tu, vu = dynamics.resample(t, v, dt=0.01)
    >>> len(tu), float(tu[1] - tu[0])
    (2001, 0.01)
    """
    t, y = check_series(t, y, minimum=2)
    keep = np.append(np.diff(t) > 0, True)
    t, y = t[keep], y[keep]
    if dt is None:
        dt = float(np.median(np.diff(t)))
    if not np.isfinite(dt) or dt <= 0:
        raise SceneError(f"`dt` must be > 0, got {dt!r}")
    count = int(np.floor((t[-1] - t[0]) / dt * (1 + 1e-12))) + 1
    grid = t[0] + dt * np.arange(count)
    return grid, np.interp(grid, t, y)
