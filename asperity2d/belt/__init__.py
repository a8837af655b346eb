"""Lumped chains of masses on a moving belt with exact stick/slip switching (seed 001).

``simulate_chain(...) -> BeltResult`` is the entry point; ``presets`` holds the
thesis' parameter tables; ``regime`` classifies runs (steady sliding,
stick-slip, quasi-harmonic); ``load`` reads a saved result.
"""

from .result import BeltResult, Event, load
from .solver import simulate_chain
from .spec import ChainSpec

__all__ = ["simulate_chain", "BeltResult", "Event", "ChainSpec", "load"]
