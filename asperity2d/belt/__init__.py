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

import importlib

#: Public names and the module each lives in, imported on first use: the command line's
#: ``belt`` parser and its bad-input errors (``asperity2d.belt.cli``) run without NumPy.
_LAZY = {"Event": "backend", "BeltResult": "result", "load": "result", "METHODS": "solver",
         "simulate_chain": "solver", "ChainSpec": "spec"}
_SUBMODULES = ("presets",)

__all__ = ["simulate_chain", "BeltResult", "Event", "ChainSpec", "load", "METHODS", "presets"]


def __getattr__(name):
    if name in _LAZY:
        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    if name in _SUBMODULES:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY) | set(_SUBMODULES))
