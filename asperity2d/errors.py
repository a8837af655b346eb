"""Exceptions raised by asperity2d.

Both derive from standard exceptions so callers can catch them broadly:
``SceneError`` is a ``ValueError`` (bad parameters), ``SimulationError`` a
``RuntimeError`` (a run that went wrong numerically).
"""


class SceneError(ValueError):
    """An invalid scene, drive, chain or run parameter.

    The message names the parameter in backticks, e.g.
    "`mass` must be > 0, got -1.0".
    """


class SimulationError(RuntimeError):
    """A run diverged (NaN, runaway energy, deep penetration).

    ``time`` is the simulated time in seconds at which it was detected.
    """

    def __init__(self, message: str, time: float | None = None):
        super().__init__(message)
        self.time = time
