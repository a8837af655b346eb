"""The closed-form checks of the belt chains (exact event-driven solver) and of the minimal
model of mode-coupling flutter.

Part of :mod:`asperity2d.closed_forms` (which lists the references).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from . import BASE, STEEL_STIFFNESS, G, Check, _register, current_engine, registered  # noqa: F401


# -- belt chains (exact event-driven solver) --------------------------------------------------------
_BELT = dict(m=1.0, k=10.0, mu_s=0.3, mu_k=0.2, V=0.1)  # kg, N/m, 1, 1, m/s


def one_dof_cycle(m, k, mu_s, mu_k, V):
    """Closed-form stick-slip cycle of a mass on a belt tied to a wall by spring k: Fs, Fk and the
    slip and stick durations (s)."""
    Fs, Fk = mu_s * m * G, mu_k * m * G
    w = math.sqrt(k / m)
    d = (Fs - Fk) / k  # slip starts d above the kinetic equilibrium Fk/k
    phi = math.atan2(d * w, V)
    return Fs, Fk, (2 * math.pi - 2 * phi) / w, 2 * d / V


@functools.lru_cache(maxsize=1)
def _belt_run():
    from ..belt import simulate_chain

    m, k, mu_s, mu_k, V = (_BELT[n] for n in ("m", "k", "mu_s", "mu_k", "V"))
    Fs, Fk, t_slip, t_stick = one_dof_cycle(m, k, mu_s, mu_k, V)
    t_first, cycles = Fs / (k * V), 100
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu_s, mu_k=mu_k, v_belt=V, x0=[0.0], v0=[V],
                       t_end=t_first + cycles * (t_slip + t_stick) + 0.5 * t_slip, n_samples=200)
    slips = [e for e in r.events if e.kind == "slip"]
    sticks = [e for e in r.events if e.kind == "stick"]
    return r, slips, sticks


_BELT_WHY = "event times and positions are located to machine precision; 1e-8 is the solver's contract"


@registered("belt-breakaway")
def belt_breakaway() -> Check:
    """The mass sticks until the spring force reaches the static limit."""
    r, slips, _ = _belt_run()
    k = _BELT["k"]
    forces = np.array([k * e.x for e in slips])
    Fs = _BELT["mu_s"] * _BELT["m"] * G
    return Check(
        name="mass on a belt: breaks away at the static limit (worst of 101 slips)",
        closed_form="k x = Fs = μs m g", expected=Fs,
        measured=float(forces[np.argmax(np.abs(forces - Fs))]), unit="N", tolerance=1e-8,
        why=_BELT_WHY, source="Den Hartog (1931); DESIGN.md section 6")


@registered("belt-force-drop")
def belt_force_drop() -> Check:
    """Den Hartog: the spring force drops by exactly 2 (Fs - Fk) over a slip."""
    r, slips, sticks = _belt_run()
    k = _BELT["k"]
    drops = np.array([k * (a.x - b.x) for a, b in zip(slips, sticks)])
    want = 2 * (_BELT["mu_s"] - _BELT["mu_k"]) * _BELT["m"] * G
    return Check(
        name="mass on a belt: spring force drop per slip (worst of 100)",
        closed_form="ΔF = 2 (Fs - Fk)", expected=want,
        measured=float(drops[np.argmax(np.abs(drops - want))]), unit="N", tolerance=1e-8,
        why=_BELT_WHY, source="Den Hartog (1931); DESIGN.md section 6")


@registered("belt-period")
def belt_period() -> Check:
    """The stick-slip period: harmonic slip back to belt speed, then a stick at belt speed."""
    r, slips, _ = _belt_run()
    _, _, t_slip, t_stick = one_dof_cycle(*(_BELT[n] for n in ("m", "k", "mu_s", "mu_k", "V")))
    times = np.array([e.t for e in slips])
    return Check(
        name="mass on a belt: stick-slip period (mean of 100 cycles)",
        closed_form="T = (2π - 2 atan(ω d / V)) / ω + 2 d / V, d = (Fs - Fk) / k",
        expected=t_slip + t_stick, measured=float(np.mean(np.diff(times))), unit="s", tolerance=1e-8,
        why=_BELT_WHY, source="Den Hartog (1931)")


@functools.lru_cache(maxsize=1)
def _free_decay():
    from ..belt import simulate_chain

    m, k, x0, mu = 1.0, 10.0, 2.0, 0.05  # about 10 cycles before it stops
    Fk = mu * m * G
    w = math.sqrt(k / m)
    r = simulate_chain([m], [k, 0.0], [0.0, 0.0], mu_s=mu, mu_k=mu, v_belt=0.0, x0=[x0], v0=[0.0],
                       t_end=30 * math.pi / w)
    reversals = [e for e in r.events if e.kind == "reverse"]
    return reversals, Fk, k, w


@registered("coulomb-decay-amplitude")
def coulomb_decay_amplitude() -> Check:
    """Coulomb free decay on a still surface: the amplitude falls by 4 Fk / k per cycle."""
    reversals, Fk, k, _ = _free_decay()
    amplitudes = np.abs([e.x for e in reversals])
    per_cycle = amplitudes[:-2] - amplitudes[2:]
    want = 4 * Fk / k
    return Check(
        name="Coulomb free decay: amplitude lost per cycle (worst cycle)",
        closed_form="Δx = 4 Fk / k", expected=want,
        measured=float(per_cycle[np.argmax(np.abs(per_cycle - want))]), unit="m", tolerance=1e-10,
        why="turning points are event-located to machine precision",
        source="Coulomb damping of a free oscillator; DESIGN.md section 6")


@registered("coulomb-decay-period")
def coulomb_decay_period() -> Check:
    """Coulomb friction does not change the period of free vibration."""
    reversals, _, _, w = _free_decay()
    return Check(
        name="Coulomb free decay: the period stays that of the free oscillator",
        closed_form="T = 2π / ω", expected=2 * math.pi / w,
        measured=float(2 * np.mean(np.diff([e.t for e in reversals]))), unit="s", tolerance=1e-10,
        why="turning points are event-located to machine precision",
        source="Coulomb damping of a free oscillator; DESIGN.md section 6")


def _chain_mode(j: int) -> Check:
    """Mode j of the 3-mass chain of the multi-DOF belt thesis' Table 2 (m = 1 kg, k = 10 N/m),
    frictionless, started in the mode's shape: its period from the simulated motion."""
    from ..belt import simulate_chain

    n, m, k = 3, 1.0, 10.0
    omega = 2 * math.sqrt(k / m) * math.sin(j * math.pi / (2 * (n + 1)))
    shape = [0.01 * math.sin(i * j * math.pi / (n + 1)) for i in range(1, n + 1)]
    periods = 20
    r = simulate_chain([m] * n, [k] * (n + 1), [0.0] * (n + 1), mu_s=0.0, v_belt=0.0, x0=shape,
                       v0=[0.0] * n, t_end=periods * 2 * math.pi / omega + 1.0, n_samples=40_001)
    x = r.x[0] / shape[0]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    crossings = r.t[up] - x[up] * (r.t[up + 1] - r.t[up]) / (x[up + 1] - x[up])  # linear interpolation
    f = 1.0 / np.mean(np.diff(crossings))
    return Check(
        name=f"belt chain normal mode {j} of 3 (Table 2 chain, frictionless)",
        closed_form="f_j = sqrt(k (2 - 2 cos(jπ/4)) / m) / 2π", expected=omega / (2 * math.pi),
        measured=float(f), unit="Hz", tolerance=1e-6,
        why="zero crossings interpolated linearly between samples 1/2000 of a period apart "
            "(error ~1e-8 of the period)",
        source="normal modes of a fixed-fixed chain of equal masses and springs")


for _j in (1, 2, 3):
    _register(f"chain-mode-{_j}", functools.partial(_chain_mode, _j))


@registered("energy-books-belt")
def energy_books_belt() -> Check:
    """Belt work = change of kinetic and spring energy + friction and damper dissipation."""
    from ..belt import simulate_chain

    r = simulate_chain([1.0, 1.5, 0.7], [10.0, 20.0, 5.0, 10.0], [0.5, 0.0, 1.0, 0.3], mu_s=0.4,
                       mu_k=0.25, v_belt=0.2, x0=[0.05, -0.02, 0.07], v0=[0.04, 0.3, -0.1], t_end=15)
    return Check(
        name="energy books of a 3-mass chain with dampers, across stick-slip switches",
        closed_form="(belt work - Δ energy - dissipation) / belt work = 0", expected=0.0,
        measured=float(r.energy_balance_error()), unit="1", tolerance=1e-8,
        why="closed-form phases and exactly located switches: round-off only",
        source="conservation of energy")


@registered("minimal-mu-crit")
def minimal_mu_crit() -> Check:
    """Bisection on μ of 'the solver's sliding phase has a growing mode' against μ_crit."""
    from ..belt import MinimalModel, steady_sliding

    mm = MinimalModel()
    threshold = 1e-6 * mm.coalescence_frequency

    def grows(mu):
        return steady_sliding(**mm.chain(mu=mu, v_belt=5.0, t_end=1.0)).growth_rate > threshold

    lo, hi = 0.3, 0.6
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if grows(mid) else (mid, hi)
    return Check(
        name="Hoffmann's minimal model: flutter onset from the solver's sliding phase",
        closed_form="μ_crit = [(K11 - K22')² + 4κ²] / (4 s κ k_c)", expected=mm.mu_crit,
        measured=0.5 * (lo + hi), unit="1", tolerance=1e-6,
        why="near the onset the growth rate is ~sqrt(μ - μ_crit): the threshold 1e-6 ω_c is met "
            "within ~1e-10 of μ_crit",
        source="Hoffmann, Fischer, Allgaier & Gaul (2002)")


@registered("minimal-growth-rate")
def minimal_growth_rate() -> Check:
    """2 % above the damped onset, simulated steady sliding grows at Re(λ)."""
    from ..belt import MinimalModel, simulate_chain

    mm = MinimalModel(eta=150.0)
    mu = 1.02 * mm.mu_crit_damped()
    sigma = mm.growth_rate(mu)
    t_end = 2.0 / abs(sigma)
    r = simulate_chain(**mm.chain(mu=mu, v_belt=50.0, t_end=t_end, kick=1e-4, t_eval=[0.0, t_end],
                                  include_events=False))
    x, y, _ = mm.equilibrium(mu)
    m, c = mm.mass, mm.eta * mm.mass
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-mm.k_eff(mu) / m, -c / m * np.eye(2)]])
    lam, U = np.linalg.eig(A.T)  # left eigenvectors: the projection on the flutter pair is c e^(λt)
    j = int(np.argmax(lam.real))
    p = U[:, j] @ np.vstack([r.x[0] - x, r.y[0] - y, r.v[0], r.vy[0]])
    return Check(
        name="Hoffmann's minimal model: simulated flutter growth rate (2 % above the damped onset)",
        closed_form="σ = Re λ of the characteristic polynomial", expected=sigma,
        measured=math.log(abs(p[1]) / abs(p[0])) / t_end, unit="1/s", tolerance=1e-9,
        why="the projection is exact for the closed-form phase; only the state's round-off remains",
        source="Hoffmann, Fischer, Allgaier & Gaul (2002)")


