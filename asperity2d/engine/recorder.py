"""The run's record and its divergence guard, kept in the engine's internal units (part of the
adapter, :mod:`asperity2d.engine`).

:class:`Recorder` samples an :class:`~.core.Engine`'s state into preallocated arrays (the
slider's columns and the lower asperities' displacements and contacts), checks at every sample
that the run has not diverged (kinetic energy against what the scene held and was given;
overlap), fills the SI view that stop conditions and observers see, and hands the record out in
SI (:meth:`Recorder.arrays`). :mod:`asperity2d.run` sees only SI values.

What a sample costs. Each sample is written once, in SI, into fixed-size blocks (never a
doubling array, never converted again at the end): the slider's eleven :data:`COLUMNS` are
88 B (float64), and -- unless the run is told not to keep them (``lower=False``) -- each lower
asperity adds 17 B (``lower_dx`` and ``lower_dy`` float64, ``lower_contact`` bool), so the
default 16-asperity scene costs 360 B a sample. :meth:`Recorder.arrays` hands out views of the
blocks; only a record that spans several blocks is joined once, block by block, each freed as
it is copied (peak: the record plus one block). A run streamed to disk (``sink``) writes each
full block out and reuses it, so its memory does not grow with its length.
"""

from __future__ import annotations

import math
from operator import add, mul

import numpy as np

from ..errors import SimulationError
from .run_checks import Validity

#: Up to this many bodies (batch rows) the divergence guard and the validity checks read the
#: bodies as one Python list per sample instead of through NumPy calls. Measured on a critical
#: force from rest at 16/4 (~700 ms of runs; the guard, at every 10th step, ~10 % of it; in-process
#: A/B, per-run minimum CPU on a shared machine): the validity checks 44 -> 31 ms, the energy
#: check 24 -> 19 ms -- NumPy's calls on a few rows cost far more in a run, their code cold after
#: ten Chipmunk steps, than in a loop of their own.
SMALL_N = 64

#: Divergence: deepest overlap (asperity bases); kinetic energy above this
#: multiple of the energy the scene held at t = 0 plus all the drive has put in.
MAX_OVERLAP = 0.5
ENERGY_FACTOR = 10.0
#: The slider's recorded columns, in the order of :attr:`Recorder._cols`.
COLUMNS = ("t", "x", "v", "y", "vy", "drive_x", "drive_force", "normal_force", "friction_force",
           "tangential_force", "contact_count")
#: A block of the record holds at most this many bytes (its samples: this over the bytes per
#: sample), except a run's first block, which holds up to :data:`FIRST_BLOCK_BYTES` when the run
#: says how many samples it will take (one block, no join, for most runs).
BLOCK_BYTES = 4 << 20
FIRST_BLOCK_BYTES = 64 << 20
#: Samples of the first block when the run does not say how many it will take.
FIRST_BLOCK = 256


class _Block:
    """``capacity`` samples of the record, SI: the slider's columns (one row each) and, with
    ``lower``, the lower asperities' displacements and contacts (one row per asperity)."""

    __slots__ = ("cols", "dx", "dy", "contact", "size")

    def __init__(self, capacity: int, n_lower: int, lower: bool):
        self.cols = np.empty((len(COLUMNS), capacity))
        n = n_lower if lower else 0
        self.dx, self.dy = np.empty((n, capacity)), np.empty((n, capacity))
        self.contact = np.empty((n, capacity), dtype=bool)
        self.size = 0

    @property
    def capacity(self) -> int:
        return self.cols.shape[1]


class Recorder:
    """Samples of ``engine``'s state (SI) and the divergence guard's books (internal units).

    :attr:`max_overlap` and :attr:`max_drift` are the largest overlap and track drift seen at
    the samples (base lengths); :attr:`size` the number of samples. ``lower=False`` keeps only
    the slider's columns (the lower asperities' arrays then have no samples). ``sink``, if
    given, receives every full block (``sink.write(cols, dx, dy, contact)``, SI arrays with
    one sample per column) and the block is reused: the record lives on disk, not here.
    ``like``: the recorder of the run this one's engine was copied from (a fork), whose
    validity checks' precomputed limits are reused.
    """

    def __init__(self, engine, *, lower: bool = True, sink=None, like: "Recorder | None" = None):
        self.engine = engine
        self.lower = bool(lower)
        self.sink = sink
        self._like = like
        self.reset()

    @property
    def bytes_per_sample(self) -> int:
        """Memory one sample takes (B): 88 for the slider's columns, 17 per lower asperity
        when they are kept."""
        n = self.engine.scene.lower.count if self.lower else 0
        return 8 * len(COLUMNS) + 17 * n

    def reset(self) -> None:
        """An empty record and fresh books (a fork starts here)."""
        u, e = self.engine.units, self.engine
        self._blocks: list[_Block] = []
        self._hint: int | None = None  # samples the run said it will take (sizes the first block)
        self._si = (e.dt, u.length, u.velocity, u.force)  # time, length, velocity, force
        self.size = 0
        self._last_sampled_step = -1
        self.max_overlap = 0.0
        self.max_drift = 0.0
        self._energy = None  # the divergence guard's books, opened at the first sample
        masses = self.engine.layout.masses
        # up to SMALL_N bodies the per-sample checks work on plain lists
        self._masses = masses.tolist() if len(masses) <= SMALL_N else None
        # the physical-validity checks, beside the guard (a fork's: from its parent's, ``like``)
        like, self._like = self._like, None
        self.validity = Validity(self.engine) if like is None else like.validity.fresh(self.engine)

    def _check_energy(self, rows: np.ndarray, drive_force: float, flat: list | None = None) -> None:
        """Raise SimulationError if the bodies hold far more kinetic energy than the scene
        had at the first sample plus every joule the drive, the load and gravity could have
        put in since (internal units; also catches NaN and inf). ``flat``: ``rows`` as a flat
        list, when the caller has it (a few bodies)."""
        e = self.engine
        layout, d = e.layout, e.drive
        if self._masses is not None:
            # a few bodies: plain Python on one list (see SMALL_N); the sum's order differs from
            # BLAS's, so the last bits of this bound may differ -- it is compared with 10 x the
            # energy, and reaches no result
            if flat is None:
                flat = rows.ravel().tolist()
            vx, vy = flat[2::4], flat[3::4]
            kinetic = 0.5 * sum(map(mul, self._masses, map(add, map(mul, vx, vx), map(mul, vy, vy))))
        else:
            v = rows[:, 2:]
            kinetic = 0.5 * float(np.dot(layout.masses, np.einsum("ij,ij->i", v, v)))
        b = self._energy
        if b is None:
            sx, sy = rows.item(layout.slider_row, 0), rows.item(layout.slider_row, 1)
            k = np.asarray(e.scene.lower.stiffness) / e.units.stiffness
            potential = 0.5 * float(np.dot(k, rows[layout.lower_rows, 1] ** 2))
            if d.spring:
                potential += 0.5 * d.k * (d.position(e.step_count, e.dt_internal) - sx) ** 2
            floor = 1e-3 * 0.5 * float(k.min()) * layout.lower_height ** 2
            self._energy = {"held": kinetic + potential + floor, "input": 0.0, "x": sx, "y": sy,
                            "f": abs(drive_force), "step": e.step_count, "heights": rows[:, 1].copy(),
                            "g": -layout.space.gravity.y}
            return
        r = layout.slider_row
        sx, sy, svx, svy = rows.item(r, 0), rows.item(r, 1), rows.item(r, 2), rows.item(r, 3)
        steps = e.step_count - b["step"]
        g = b["g"]
        if d.spring:  # the far end's power |F| |v| over the samples' interval, F at its larger end
            b["input"] += max(b["f"], abs(drive_force)) * abs(d.v) * steps * e.dt_internal
        else:
            b["input"] += abs(d.force) * abs(sx - b["x"])
        b["input"] += e.load_internal * abs(sy - b["y"])
        if g:  # gravity's work on every body
            b["input"] += g * float(np.dot(layout.masses, np.abs(rows[:, 1] - b["heights"])))
            b["heights"] = rows[:, 1].copy()
        b["x"], b["y"], b["f"], b["step"] = sx, sy, abs(drive_force), e.step_count
        # pymunk moves a body with its old velocity, then updates the velocity: kinetic energy is
        # ahead of the displacement that paid for it by one step, so allow one step of that work
        # (gravity's share only with gravity: without, a NaN or inf velocity already makes the
        # kinetic energy fail the test below)
        ahead = e.dt_internal * ((0.0 if d.spring else abs(d.force * svx)) + e.load_internal * abs(svy)
                                 + (g * float(np.dot(layout.masses, np.abs(rows[:, 3]))) if g else 0.0))
        limit = ENERGY_FACTOR * (b["held"] + b["input"] + ahead)
        if not kinetic <= limit:  # also true for NaN
            u = e.units
            raise SimulationError(
                f"run diverged at t = {e.time:.6g} s: kinetic energy {kinetic * u.energy:.3g} J is over "
                f"{ENERGY_FACTOR:g} x the {limit / ENERGY_FACTOR * u.energy:.3g} J the scene held and "
                f"was given; use a smaller dt (now {e.dt:.3g} s, default T/50) or more iterations",
                time=e.time)

    def _guard(self, rows: np.ndarray, drive_force: float, overlap: float) -> None:
        """Raise SimulationError if the run has diverged: kinetic energy (:meth:`_check_energy`)
        or asperities overlapping by ``overlap`` (base lengths) over ``MAX_OVERLAP``."""
        flat = rows.ravel().tolist() if self._masses is not None else None  # read once, for both checks
        self._check_energy(rows, drive_force, flat)
        if overlap > MAX_OVERLAP:
            e = self.engine
            raise SimulationError(
                f"run diverged at t = {e.time:.6g} s: asperities overlap by {overlap:.2f} of a base; "
                f"use a smaller dt (now {e.dt:.3g} s) or more iterations", time=e.time)
        if overlap > self.max_overlap:
            self.max_overlap = overlap
        self.validity.check(rows, flat)

    def check(self) -> None:
        """The divergence guard alone on the engine's current state (a run that keeps no record)."""
        e = self.engine
        rows, r = e.bodies_internal(), e.layout.slider_row
        self._guard(rows, e.drive_force_internal(rows.item(r, 0), rows.item(r, 2)),
                    e.arbiters_internal().max_overlap())

    def sample(self) -> None:
        """Record the engine's current state and check it has not diverged."""
        e = self.engine
        if e.step_count == self._last_sampled_step:
            return
        rows = e.bodies_internal()
        layout = e.layout
        sx, sy, svx, svy = rows[layout.slider_row].tolist()
        drive_force = e.drive_force_internal(sx, svx)
        arbiters = e.arbiters_internal()
        fx, fy, ft, count, overlap = arbiters.forces(e.dt_internal)
        self._guard(rows, drive_force, overlap)
        lower = rows[layout.lower_rows]
        dx = lower[:, 0] - layout.lower_x0
        drift = float(np.abs(dx).max()) if len(dx) and layout.tracked else 0.0
        if layout.fixed_slider:
            drift = max(drift, abs(sy - layout.slider_y_track))
        self.max_drift = max(self.max_drift, drift)
        block = self._blocks[-1] if self._blocks else None
        if block is None or block.size == block.capacity:
            block = self._new_block()
        i = block.size
        drive_x = e.drive.position(e.step_count, e.dt_internal) if e.drive.spring else math.nan
        # SI once, here: the same products the record was always scaled by (bit for bit)
        st, sl, sv, sf = self._si
        block.cols[:, i] = (e.step_count * st, sx * sl, svx * sv, sy * sl, svy * sv, drive_x * sl,
                            drive_force * sf, fy * sf, -fx * sf, ft * sf, float(count))
        if self.lower:
            np.multiply(dx, sl, out=block.dx[:, i])
            np.multiply(lower[:, 1], sl, out=block.dy[:, i])
            block.contact[:, i] = arbiters.touched(len(dx))
        block.size = i + 1
        self.size += 1
        self._last_sampled_step = e.step_count

    def reserve(self, samples: int) -> None:
        """The run is about to take up to ``samples`` more samples: a record that has no block
        yet gets one that holds them all, up to :data:`FIRST_BLOCK_BYTES` (a streamed record:
        :data:`BLOCK_BYTES`), so most runs record into one block and are never joined."""
        if not self._blocks:
            self._hint = max(1, int(samples))

    def _new_block(self) -> _Block:
        """The block the next sample goes into: a streamed record writes its full block out and
        reuses it; a record in memory keeps it and starts another."""
        per = self.bytes_per_sample
        if self.sink is not None:
            if self._blocks:
                self._flush()
                return self._blocks[-1]
            cap = BLOCK_BYTES // per
            if self._hint is not None:
                cap = min(cap, self._hint)
        elif self._blocks:
            cap = max(FIRST_BLOCK, BLOCK_BYTES // per)
        elif self._hint is not None:
            cap = min(self._hint, FIRST_BLOCK_BYTES // per)
        else:
            cap = FIRST_BLOCK
        block = _Block(max(1, cap), self.engine.scene.lower.count, self.lower)
        self._blocks.append(block)
        return block

    def _flush(self) -> None:
        """Hand the samples not yet written to the sink (a streamed record) and empty the block."""
        if self.sink is None or not self._blocks:
            return
        block = self._blocks[-1]
        m = block.size
        if m:
            self.sink.write(block.cols[:, :m], block.dx[:, :m], block.dy[:, :m], block.contact[:, :m])
        block.size = 0

    def probe(self, probe) -> None:
        """Fill ``probe`` (:class:`asperity2d.run.Probe`) with the current state, SI."""
        e = self.engine
        u = e.units
        sx, sy, svx, _ = e.bodies_internal()[e.layout.slider_row].tolist()
        probe.t = e.step_count * e.dt
        probe.x, probe.v, probe.y = sx * u.length, svx * u.velocity, sy * u.length
        probe.drive_force = e.drive_force_internal(sx, svx) * u.force
        probe.rear_apex_x = (sx + e.layout.upper_apex[0]) * u.length

    def last_apex_x(self) -> float:
        """x of the lower surface's last apex (m)."""
        e = self.engine
        return float(e.layout.lower_apex_x[-1]) * e.units.length

    def arrays(self, start: int = 0) -> dict[str, np.ndarray]:
        """The samples from ``start`` on, SI: the :data:`COLUMNS` (s, m, m/s, N, count) and
        ``lower_dx``, ``lower_dy`` (m), ``lower_contact`` (bool), each lower asperity a row
        (no samples without ``lower``). Read-only views of the record, not copies (a streamed
        record: :meth:`flush` first, then read the file)."""
        if self.sink is not None:
            raise RuntimeError("a streamed record is read from its file (flush, then load it)")
        block = self._join()
        m = self.size
        n = self.engine.scene.lower.count
        if block is None:
            block = _Block(0, n, self.lower)
        arrays = {name: block.cols[j, start:m] for j, name in enumerate(COLUMNS)}
        if self.lower:
            arrays.update(lower_dx=block.dx[:, start:m], lower_dy=block.dy[:, start:m],
                          lower_contact=block.contact[:, start:m])
        else:  # not recorded: no samples
            arrays.update(lower_dx=np.empty((n, 0)), lower_dy=np.empty((n, 0)),
                          lower_contact=np.empty((n, 0), dtype=bool))
        for a in arrays.values():
            a.flags.writeable = False  # shared with the record: a later result() must not see edits
        return arrays

    def flush(self) -> None:
        """Write every sample taken so far to the sink (a streamed record)."""
        self._flush()

    def _join(self) -> _Block | None:
        """The record as one block: joined (block by block, each freed once copied) if it
        spans several; later samples go to a new block."""
        blocks = self._blocks
        if len(blocks) <= 1:
            return blocks[0] if blocks else None
        n = self.engine.scene.lower.count
        joined = _Block(self.size, n, self.lower)
        j = 0
        while blocks:
            block = blocks.pop(0)
            m = block.size
            joined.cols[:, j:j + m] = block.cols[:, :m]
            if self.lower:
                joined.dx[:, j:j + m] = block.dx[:, :m]
                joined.dy[:, j:j + m] = block.dy[:, :m]
                joined.contact[:, j:j + m] = block.contact[:, :m]
            j += m
            del block
        joined.size = j
        blocks.append(joined)
        return joined
