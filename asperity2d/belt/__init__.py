"""Lumped chains of masses on a moving belt with exact stick/slip switching (seed 001).

``simulate_chain(...) -> BeltResult`` is the entry point; ``presets`` holds the
thesis' parameter tables; ``regime`` classifies runs (steady sliding,
stick-slip, quasi-harmonic); ``load`` reads a saved result.

Modules, in data-flow order: ``validate`` (parameter rules and budgets) ->
``spec`` (ChainSpec and its scales) -> ``backend`` (the back-end contract:
RunOptions in, RawRun out) -> back-ends ``linear`` (closed-form phases from
``modal``), ``hybrid`` (integrated phases, state-variable laws), ``sign``
(the thesis' sign() method), sharing ``loop`` (the event loop), ``events``
(event functions), ``finder`` (locating switches, the touch rule) and
``modes`` (stick or slip at a switch) -> ``solver`` (``simulate_chain``, the
``METHODS`` table) -> ``result`` (BeltResult) -> ``regime``, ``plots``.
"""

from . import presets
from .backend import Event
from .result import BeltResult, load
from .solver import METHODS, simulate_chain
from .spec import ChainSpec

__all__ = ["simulate_chain", "BeltResult", "Event", "ChainSpec", "load", "METHODS", "presets"]
