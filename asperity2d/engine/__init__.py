"""The asperity engines: the pymunk adapter (the only place that imports pymunk) and the batched engine.

* :mod:`.core` — :class:`Engine`: an asperity scene stepped with a fixed dt
  (drive, load, track projection, settling), composed of
* :mod:`.space` — building the space (:func:`~.space.build` -> :class:`~.space.Layout`), and
* :mod:`.contacts` — one batch read of the contacts per step, the stick/slip
  switch and the contact forces;
* :mod:`.native` — the per-step calls into Chipmunk (step, force, batched
  reads) without pymunk's per-call Python layer, chosen by a capability check,
  with pymunk's public API as the fallback (``ASPERITY2D_PYMUNK_NATIVE=0``);
* :mod:`.recorder` — the run's record and divergence guard in internal units,
  handed out in SI (:class:`~.recorder.Recorder`);
* :mod:`.run_checks` — what no run may show (a step longer than the contact it must resolve,
  a slider below the floor, a tip through an untouched asperity): checked before a scene is
  built and at every sample, beside the divergence guard;
* :mod:`.registry` — the engines (:data:`ENGINES`: ``"pymunk"``, the reference, and
  ``"batched"``) and the contract each keeps;
* :mod:`.batched` and :mod:`.batched_kernel` — the batched engine: many scenes of the model's
  common case stepped in lockstep in one compiled loop (Numba, the ``[batch]`` extra), no pymunk;
* :mod:`.energy` — per-step energy accounting (:class:`~.energy.EnergyMeter`)
  and the contacts' work (:class:`~.energy.ContactWork`).
"""

from .core import PYMUNK_VERSION, Engine
from .registry import ENGINES, check_engine

__all__ = ["Engine", "ENGINES", "PYMUNK_VERSION", "check_engine"]
