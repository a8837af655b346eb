"""The pymunk adapter: the only place that imports pymunk.

* :mod:`.asperity` — asperity scenes (:class:`Engine`);
* :mod:`.belt` — masses on a moving belt, for cross-checks of the exact solver.
"""

from .asperity import PYMUNK_VERSION, Engine

__all__ = ["Engine", "PYMUNK_VERSION"]
