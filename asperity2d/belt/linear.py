"""Closed-form motion of a whole chain between two switches (constant belt speed).

Between switches every mass is either stuck (x = x_s0 + V·tau, v = V exactly)
or slipping under a constant kinetic force. The slipping masses split into
independent *segments* -- maximal runs joined by a spring or damper -- since
a stuck mass acts on its neighbours as a wall moving at V. Each segment moves
as in :mod:`.modal`; the eigendecompositions are cached per segment for the
whole run, so a switch costs O(L²) per segment of L masses, not O(L³).

When every segment has a modal form, the phase carries ``motion``: one
:class:`~.modal.ModalForm` whose rows are x (n), v (n) and a (n), from which
the event functions are composed in closed form.
"""

from __future__ import annotations

import math

import numpy as np

from .backend import RawRun
from .loop import event_loop
from .modal import ModalForm, Segment, SegmentModes, block_matrix
from .spec import link_force

#: bounded memory on long chains: at most this many cached segment eigendecompositions
CACHE_SIZE = 512


def run_closed_form(spec, options) -> RawRun:
    """Event-driven run with closed-form phases (constant belt speed, piecewise-constant friction)."""
    cache: dict = {}

    def make_phase(modes, x, v, t):
        return LinearPhase(spec, modes, x, v, spec.v_belt, cache)

    return event_loop(spec, options, make_phase)


class LinearPhase:
    """The chain from one switch to the next: stuck masses ride the belt, segments move exactly.

    ``modes`` (n,) 0 stuck or ±1 slipping direction; ``x0``, ``v0`` (m, m/s) the
    state at the phase start; ``V`` (m/s) the belt speed; ``cache`` maps
    (lo, hi) to :class:`~.modal.SegmentModes`.
    """

    def __init__(self, spec, modes, x0, v0, V, cache):
        self.spec, self.V = spec, float(V)
        self.modes = np.asarray(modes)
        self.stuck = self.modes == 0
        self.x0, self.v0 = np.asarray(x0, dtype=float), np.asarray(v0, dtype=float)
        #: kinetic force on each slipping mass (N): opposes the relative velocity
        self.fric_slip = -self.modes * spec.kinetic_force
        self.segments = [self._segment(lo, hi, cache) for lo, hi in _runs(self.stuck, spec)]
        rate = max((s.modes.rate for s in self.segments), default=0.0)
        #: scan step (s): 1/16 of the fastest period, or no limit for an all-stuck chain
        self.step = 2 * math.pi / (16 * rate) if rate > 0 else math.inf
        self.motion = self._motion() if all(s.modes.exact for s in self.segments) else None

    def _segment(self, lo, hi, cache):
        spec, k, c, V = self.spec, self.spec.k, self.spec.c, self.V
        modes = cache.get((lo, hi))
        if modes is None:
            modes = cache[(lo, hi)] = SegmentModes(spec, lo, hi)
            if len(cache) > CACHE_SIZE:
                cache.pop(next(iter(cache)))
        p = self.fric_slip[lo : hi + 1].copy()
        q = np.zeros(hi - lo + 1)
        # a neighbour outside the segment is stuck (it moves as x_s0 + V·tau) or unlinked
        # (zero coefficients: its value does not matter); walls never move
        if lo > 0:
            p[0] += k[lo] * self.x0[lo - 1] + c[lo] * V
            q[0] += k[lo] * V
        if hi < spec.n - 1:
            p[-1] += k[hi + 1] * self.x0[hi + 1] + c[hi + 1] * V
            q[-1] += k[hi + 1] * V
        sl = slice(lo, hi + 1)
        return Segment(modes, lo, np.concatenate([self.x0[sl], self.v0[sl]]), p, q)

    def _motion(self) -> ModalForm:
        """Rows x, v, a (3n) of the whole chain as one modal form.

        Stuck rows: x = x0 + V·tau, v = V, a = 0. Segment rows: its modal form,
        and for a the v rows differentiated (d/dtau exp(lam·tau) = lam·exp(lam·tau);
        the particular solution's velocity is constant).
        """
        n = self.spec.n
        c0 = np.concatenate([self.x0, np.full(n, self.V), np.zeros(n)])
        c1 = np.concatenate([np.full(n, self.V), np.zeros(2 * n)])
        blocks, col = [], 0
        for seg in self.segments:
            rows, cols, values = seg.block(n, col)
            blocks += [(rows, cols, values), (n + rows[seg.L :], cols, values[seg.L :] * seg.modes.lam)]
            c0[rows], c1[rows] = seg.c0, seg.c1
            col += 2 * seg.L
        lam = np.concatenate([s.modes.lam for s in self.segments]) if self.segments else np.zeros(0, complex)
        return ModalForm(lam, block_matrix(blocks, (3 * n, col)), c0, c1)

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

    def belt_velocity(self, tau):
        return np.full(np.size(tau), self.V)

    def belt_acceleration(self, tau):
        return np.zeros(np.size(tau))

    def friction_force(self, x, v, a, tau):
        """Friction force on each mass (N): kinetic while slipping, the required static force while stuck."""
        f = np.repeat(self.fric_slip[:, None], np.size(tau), axis=1)
        f[self.stuck] = -self.spring_damper_force(x, v)[self.stuck]
        return f

    def spring_damper_force(self, x, v):
        return link_force(self.spec.k, x) + link_force(self.spec.c, v)


def _runs(stuck, spec):
    """(lo, hi) of each maximal run of slipping masses joined by a spring or damper."""
    n = spec.n
    linked = (spec.k[1:n] != 0) | (spec.c[1:n] != 0)
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
