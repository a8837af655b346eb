"""Lumped chains of masses on a moving belt with exact stick/slip switching (the multi-DOF belt thesis).

``simulate_chain(...) -> BeltResult`` is the entry point; ``presets`` holds the
thesis' parameter tables; ``regime`` classifies runs (steady sliding,
stick-slip, quasi-harmonic); ``load`` reads a saved result.

The map: two halves on a shared base, and the driver that joins them.

* **Shared** (here): ``limits`` (derived scales, budgets, the switching tolerance; the
  parameter rules are :mod:`asperity2d._inputs`'s) -> ``normal`` (NormalContact, the normal
  contact's parameters) -> ``chainfile`` (chain files: TOML in and out) -> ``spec`` (ChainSpec,
  ContactSpec and their scales) -> ``backend`` (the back-end contract: spec and RunOptions in,
  RawRun or ContactRun out; ``Backend``) -> ``result`` (BeltResult, its books and files).
* ``phases/`` -- what both halves run on: ``modal`` (closed-form phases), ``segment``,
  ``events`` (event functions), ``finder`` (locating switches, the touch rule).
* ``chain/`` -- the tangential chain's back ends: ``linear`` (closed-form phases, ``energy``),
  ``hybrid`` (integrated phases, state-variable laws), ``sign`` (the thesis' sign() method),
  sharing ``loop`` (the event loop) and ``modes`` (stick or slip at a switch).
* ``contact/`` -- the normal contact (``simulate_chain(..., normal=NormalContact(...))``:
  separated, sliding or sticking): ``loop`` over ``phase`` (phases from ``affine``) and
  ``modes`` (impacts, opening, closing) -> ``result`` (ContactResult); ``steady`` (steady
  sliding, flutter) and ``minimal`` (Hoffmann's minimal model in closed form).
* ``solver`` (``simulate_chain``, the ``METHODS`` table of both halves' back ends) ->
  ``regime``, ``period``; ``presets`` (the thesis' tables).

The halves never import each other (the import contract in ``pyproject.toml`` holds it).
"""

from .._lazy import exports

#: Public names and the module each lives in, imported on first use: the command line's
#: ``belt`` parser and its bad-input errors (``asperity2d.cli.belt``) run without NumPy.
_LAZY = {"Event": "backend", "BeltResult": "result", "load": "contact.result", "METHODS": "solver",
         "simulate_chain": "solver", "ChainSpec": "spec", "NormalContact": "normal", "ContactResult": "contact.result",
         "load_contact": "contact.result", "MinimalModel": "contact.minimal", "steady_sliding": "contact.steady",
         "ContactSpec": "spec", "Backend": "backend", "classify": "regime", "classify_contact": "regime",
         "regime_map": "regime", "belt_period": "period", "read_chain": "chainfile"}
_SUBMODULES = ("presets",)

__all__ = ["simulate_chain", "BeltResult", "Event", "ChainSpec", "load", "METHODS", "presets", "NormalContact",
           "ContactResult", "load_contact", "MinimalModel", "steady_sliding", "classify", "classify_contact",
           "regime_map", "belt_period", "ContactSpec", "Backend", "read_chain"]


__getattr__, __dir__ = exports(__name__, globals(), _LAZY, _SUBMODULES)
