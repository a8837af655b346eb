"""Lumped chains of masses on a moving belt with exact stick/slip switching (the multi-DOF belt thesis).

``simulate_chain(...) -> BeltResult`` is the entry point; ``presets`` holds the
thesis' parameter tables; ``regime`` classifies runs (steady sliding,
stick-slip, quasi-harmonic); ``load`` reads a saved result.

Modules, in data-flow order: ``limits`` (derived scales and budgets; the parameter rules are
:mod:`asperity2d._inputs`'s) ->
``spec`` (ChainSpec and its scales) -> ``backend`` (the back-end contract:
RunOptions in, RawRun out) -> back-ends ``linear`` (closed-form phases from
``modal``), ``hybrid`` (integrated phases, state-variable laws), ``sign``
(the thesis' sign() method), sharing ``loop`` (the event loop), ``events``
(event functions), ``finder`` (locating switches, the touch rule) and
``modes`` (stick or slip at a switch) -> ``solver`` (``simulate_chain``, the
``METHODS`` table) -> ``result`` (BeltResult) -> ``regime``, ``plots``.

A normal degree of freedom (``simulate_chain(..., normal=NormalContact(...))``:
separated, sliding or sticking) runs through ``normal`` (NormalContact,
ContactSpec) -> ``contact`` (driver, steady-sliding linearisation) ->
``contact_loop`` over ``contact_phase`` (phases in closed form from ``affine``,
the non-symmetric first-order solution) and ``contact_modes`` (impacts,
opening, closing at a switch) -> ``contact_result`` (ContactResult);
``minimal`` holds Hoffmann's minimal model and its closed forms.
"""

from .._lazy import exports

#: Public names and the module each lives in, imported on first use: the command line's
#: ``belt`` parser and its bad-input errors (``asperity2d.cli.belt``) run without NumPy.
_LAZY = {"Event": "backend", "BeltResult": "result", "load": "contact_result", "METHODS": "solver",
         "simulate_chain": "solver", "ChainSpec": "spec", "NormalContact": "normal", "ContactResult": "contact_result",
         "load_contact": "contact_result", "MinimalModel": "minimal", "steady_sliding": "contact",
         "ContactSpec": "spec", "Backend": "backend", "classify": "regime", "classify_contact": "regime",
         "regime_map": "regime", "belt_period": "period"}
_SUBMODULES = ("presets",)

__all__ = ["simulate_chain", "BeltResult", "Event", "ChainSpec", "load", "METHODS", "presets", "NormalContact",
           "ContactResult", "load_contact", "MinimalModel", "steady_sliding", "classify", "classify_contact",
           "regime_map", "belt_period", "ContactSpec", "Backend"]


__getattr__, __dir__ = exports(__name__, globals(), _LAZY, _SUBMODULES)
