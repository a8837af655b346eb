"""Exceptions raised by asperity2d.

Both derive from standard exceptions so callers can catch them broadly:
``SceneError`` is a ``ValueError`` (bad parameters), ``SimulationError`` a
``RuntimeError`` (a run that went wrong numerically).
"""


class SceneError(ValueError):
    """An invalid scene, drive, chain or run parameter.

    The message names the parameter in backticks, e.g.
    "`mass` must be > 0, got -1.0". A ``ValueError``; raised before anything runs.

    See Also
    --------
    asperity2d.SimulationError : a run that went wrong, not its parameters.

    Examples
    --------
    >>> import asperity2d as a
    >>> try:
    ...     a.make_scene(lower_cont=4)
    ... except a.SceneError as error:
    ...     print(error)
    unknown scene parameter `lower_cont` (did you mean `lower_count`?)
    >>> issubclass(a.SceneError, ValueError)
    True
    """


class SimulationError(RuntimeError):
    """A run diverged (NaN, runaway energy, deep penetration).

    ``time`` is the simulated time in seconds at which it was detected. A
    ``RuntimeError``. A step the package knows to be too coarse is refused earlier, as a
    :class:`~asperity2d.SceneError`; one forced through with ``unsafe_dt=True`` may diverge.

    Parameters
    ----------
    message : str
        What went wrong, and what to change.
    time : float, optional
        Simulated time (s) at which it was detected.

    See Also
    --------
    asperity2d.SceneError : bad parameters.
    asperity2d.simulate : its ``dt`` and ``unsafe_dt``.

    Examples
    --------
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> try:
    ...     a.simulate(scene, dt=1e-9, unsafe_dt=True)
    ... except a.SimulationError as error:
    ...     print(error)
    ...     print(f"detected at {error.time:.2g} s")
    run diverged at t = 6e-08 s: kinetic energy ... use a smaller dt (now 1e-09 s, default T/50) ...
    detected at 6e-08 s
    """

    def __init__(self, message: str, time: float | None = None):
        super().__init__(message)
        self.time = time
