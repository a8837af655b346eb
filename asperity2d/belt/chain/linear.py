"""Closed-form motion of a whole chain between two switches (constant belt speed).

Between switches every mass is either stuck (x = x_s0 + V·tau, v = V exactly)
or slipping under a constant kinetic force. The slipping masses split into
independent *segments* -- maximal runs joined by a spring or damper -- since
a stuck mass acts on its neighbours as a wall moving at V. Each segment moves
as in :mod:`.phases.modal`; the eigendecompositions are cached per segment for the
whole run, so a switch costs O(L²) per segment of L masses, not O(L³).

When every segment has a modal form, the phase carries ``motion``: one
:class:`~.phases.modal.ModalForm` whose rows are x (n), v (n) and a (n), from which
the event functions are composed in closed form.
"""

from __future__ import annotations

import math

import numpy as np

from ..backend import RawRun
from .energy import modal_work, power_maps, quadrature_work
from ..phases.events import event_map
from .loop import event_loop
from .. import limits
from ..phases.modal import ModalForm, block_matrix, scale_columns
from ..phases.segment import Segment, SegmentModes
from ..spec import link_force

#: bounded memory on long chains: at most this many cached segments and mode patterns (and at most
#: :data:`~.limits.CACHE_BYTES` of each)
CACHE_SIZE = limits.CACHE_SIZE


def run_closed_form(spec, options) -> RawRun:
    """Event-driven run with closed-form phases (constant belt speed, piecewise-constant friction)."""
    segments: dict = {}
    templates: dict = {}
    sizes: dict = {}

    def make_phase(modes, x, v, t):
        key = np.asarray(modes, dtype=np.int8).tobytes()
        template = templates.get(key)
        if template is None:
            template = templates[key] = Template(spec, modes, segments)
            sizes[key] = limits.nbytes(template)
            limits.bound_cache(templates, sizes, CACHE_SIZE)
        return LinearPhase(template, x, v)

    return event_loop(spec, options, make_phase)


def _bound(cache):
    """Hold the segments' cache to ``CACHE_SIZE`` entries and :data:`~.limits.CACHE_BYTES`."""
    limits.bound_cache(cache, {key: limits.nbytes(entry) for key, entry in cache.items()}, CACHE_SIZE)


class Template:
    """What a phase needs that depends only on the chain and its mode pattern (cached per run).

    The segments and their modes; ``lam`` (S,) and ``shapes`` (3n, S): the
    rows x, v, a of every segment's modes, so that a phase's motion is
    ``Re((shapes·coef)·exp(lam·tau)) + c0 + c1·tau``; the event-function and
    power maps (linear in the state) and their products with ``shapes``.
    """

    def __init__(self, spec, modes, segments):
        n, V = spec.n, spec.v_belt
        self.spec, self.V = spec, float(V)
        self.modes = np.asarray(modes)
        stuck = self.modes.tolist()  # (plain ints: the pattern is read mass by mass below)
        self.stuck = self.modes == 0
        self.any_stuck = 0 in stuck
        #: kinetic force on each slipping mass (N): opposes the relative velocity
        self.fric_slip = -self.modes * spec.kinetic_force
        self.runs = []
        for lo, hi in _runs([mode == 0 for mode in stuck], spec):
            if (lo, hi) not in segments:
                segments[lo, hi] = SegmentModes(spec, lo, hi)
                _bound(segments)
            self.runs.append((lo, hi, segments[lo, hi]))
        rate = max((m.rate for _, _, m in self.runs), default=0.0)
        #: scan step (s): 1/16 of the fastest period, or no limit for an all-stuck chain
        self.step = 2 * math.pi / (16 * rate) if rate > 0 else math.inf
        self.exact = all(m.exact for _, _, m in self.runs)
        if not self.exact:
            return
        blocks, col = [], 0
        for lo, hi, m in self.runs:
            L, S = hi - lo + 1, m.lam.size
            # (ranges of consecutive indices, as :func:`~.phases.modal.block_matrix` takes them)
            cols = range(col, col + S)
            blocks += [(range(lo, hi + 1), cols, m.shapes[:L]), (range(n + lo, n + hi + 1), cols, m.shapes[L:]),
                       (range(2 * n + lo, 2 * n + hi + 1), cols, m.shapes[L:] * m.lam)]
            col += S
        # (one segment's eigenvalues are the pattern's own: never written to, so shared, not copied)
        self.lam = (self.runs[0][2].lam if len(self.runs) == 1 else
                    np.concatenate([m.lam for _, _, m in self.runs]) if self.runs else np.zeros(0, complex))
        self.shapes = block_matrix(blocks, (3 * n, col))
        self.kind, self.mass, self.event_map, self.event_offset = event_map(spec, self.modes, self.V)
        self.event_shapes = self.event_map @ self.shapes
        self.event_shapes_abs = abs(self.event_shapes)
        #: |lam|⁴ of the modes (the event functions' fourth-derivative bound, :class:`~.phases.events.ModalEvents`)
        self.lam_abs4 = np.abs(self.lam) ** 4
        #: whether any mode decays or grows (:func:`~.phases.modal.damped`): undamped phases skip exp(Re lam·tau);
        #: the pattern's eigenvalues are its segments', so it is any segment's (found once per segment)
        self.damped = any(m.damped for _, _, m in self.runs)
        #: the particular solution's (c0, c1) rows [x; v; a] of stuck masses, c0's x rows to be set to x0
        self.c0_stuck, self.c1_stuck = np.zeros(3 * n), np.zeros(3 * n)
        self.c0_stuck[n : 2 * n] = self.V
        self.c1_stuck[:n] = self.V
        #: per segment, the rows of its x and of its v in the state [x; v; a] (slices)
        self.segment_rows = [(slice(lo, hi + 1), slice(n + lo, n + hi + 1)) for lo, hi, _ in self.runs]
        self.power_map, self.power_offset, self.rate_map = power_maps(spec, self.stuck, self.fric_slip, self.V)
        self.power_shapes = self.power_map @ self.shapes
        self.rate_shapes = None if self.rate_map is None else self.rate_map @ self.shapes


class LinearPhase:
    """The chain from one switch to the next: stuck masses ride the belt, segments move exactly.

    ``template`` the mode pattern's :class:`Template`; ``x0``, ``v0`` (m, m/s) the state
    at the phase start. ``motion`` (rows x, v, a) and ``coef`` exist when every segment
    has a modal form.
    """

    def __init__(self, template, x0, v0):
        spec, V = template.spec, template.V
        self.template, self.spec, self.V = template, spec, V
        self.modes, self.stuck, self.fric_slip, self.step = template.modes, template.stuck, template.fric_slip, template.step
        self.x0, self.v0 = np.asarray(x0, dtype=float), np.asarray(v0, dtype=float)
        k, c, n = spec.k, spec.c, spec.n
        self.segments = []
        for lo, hi, modes in template.runs:
            p = self.fric_slip[lo : hi + 1].copy()
            q = np.zeros(hi - lo + 1)
            # a neighbour outside the segment is stuck (it moves as x_s0 + V·tau) or unlinked
            # (zero coefficients: its value does not matter); walls never move
            if lo > 0:
                p[0] += k[lo] * self.x0[lo - 1] + c[lo] * V
                q[0] += k[lo] * V
            if hi < n - 1:
                p[-1] += k[hi + 1] * self.x0[hi + 1] + c[hi + 1] * V
                q[-1] += k[hi + 1] * V
            y0 = np.concatenate([self.x0[lo : hi + 1], self.v0[lo : hi + 1]])
            self.segments.append(Segment(modes, lo, y0, p, q))
        self.motion = None
        if template.exact:
            # stuck rows: x = x0 + V·tau, v = V, a = 0; segment rows: particular solution + modes
            c0, c1 = template.c0_stuck.copy(), template.c1_stuck.copy()
            c0[:n] = self.x0
            for seg, (x_rows, v_rows) in zip(self.segments, template.segment_rows):
                L = seg.L
                c0[x_rows], c0[v_rows], c1[x_rows], c1[v_rows] = seg.c0[:L], seg.c0[L:], seg.c1[:L], seg.c1[L:]
            # (one segment's amplitudes are the phase's own: never written to, so shared, not copied)
            self.coef = (self.segments[0].coef if len(self.segments) == 1 else
                         np.concatenate([s.coef for s in self.segments]) if self.segments else np.zeros(0, complex))
            self.motion = ModalForm(template.lam, scale_columns(template.shapes, self.coef), c0, c1, template.damped)

    def form(self, shapes, rows_map, offset) -> ModalForm:
        """The modal form of ``rows_map @ [x; v; a] + offset`` given ``shapes = rows_map @ template.shapes``."""
        m = self.motion
        return ModalForm(m.lam, scale_columns(shapes, self.coef), rows_map @ m.c0 + offset, rows_map @ m.c1, m.damped)

    def evaluate(self, tau):
        """Positions, velocities, accelerations (each (n, T)) at ``tau`` (s) after the phase start."""
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        n = self.spec.n
        if self.motion is not None:
            y = self.motion.at(tau)
            return y[:n], y[n : 2 * n], y[2 * n :]
        x = self.x0[:, None] + self.V * tau[None, :]
        v = np.full((n, tau.size), self.V)
        for seg in self.segments:
            y = seg.evaluate(tau)
            x[seg.lo : seg.lo + seg.L] = y[: seg.L]
            v[seg.lo : seg.lo + seg.L] = y[seg.L :]
        a = (self.spring_damper_force(x, v) + self.fric_slip[:, None]) / self.spec.m[:, None]
        a[self.stuck] = 0.0
        return x, v, a

    def sample(self, tau):
        """Positions, velocities, friction forces (n, T) and work integrals (3, T, J) at ``tau`` (s)."""
        tau = np.asarray(tau, dtype=float)
        if self.motion is None:
            x, v, a = self.evaluate(tau)
            return x, v, self.friction_force(x, v, a, tau), quadrature_work(self, tau)
        n = self.spec.n
        # the rows x and v only (recording needs no accelerations): each row's value is its own
        # sum, the same numbers as among all rows (:class:`~.phases.events.ModalEvents`); the work
        # integrals reuse these times' exponentials
        m = self.motion
        growth = m.growth(tau)
        y = ModalForm(m.lam, m.B[: 2 * n], m.c0[: 2 * n], m.c1[: 2 * n], m.damped).at(tau, growth)
        x, v = y[:n], y[n:]
        return x, v, self.friction_force(x, v, None, tau), modal_work(self, tau, growth)

    def belt_velocity(self, tau):
        return np.full(np.size(tau), self.V)

    def belt_acceleration(self, tau):
        return np.zeros(np.size(tau))

    def friction_force(self, x, v, a, tau):
        """Friction force on each mass (N): kinetic while slipping, the required static force while stuck."""
        f = np.empty((self.fric_slip.size, np.size(tau)))
        f[...] = self.fric_slip[:, None]
        if self.template.any_stuck:  # (an all-slipping phase needs no spring forces)
            f[self.stuck] = -self.spring_damper_force(x, v)[self.stuck]
        return f

    def spring_damper_force(self, x, v):
        """Spring plus damper force on each mass (N), at states ``x``, ``v`` (n, T)."""
        f = link_force(self.spec.k, x)
        # without dampers the damper force is a signed zero: it changes no non-zero spring force,
        # so it is added only where it could set the sign of a zero (the same numbers, fewer calls)
        if self.spec.damped or np.count_nonzero(f) < f.size:
            f = f + link_force(self.spec.c, v)
        return f


def _runs(stuck, spec):
    """(lo, hi) of each maximal run of slipping masses joined by a spring or damper (``stuck``: a list of bools)."""
    n, linked = spec.n, spec.linked
    out, i = [], 0
    while i < n:
        if stuck[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and not stuck[j + 1] and linked[j]:
            j += 1
        out.append((i, j))
        i = j + 1
    return out
