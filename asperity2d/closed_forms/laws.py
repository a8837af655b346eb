"""The closed-form checks of the asperity model's contact laws (:mod:`asperity2d.contact_laws`) on
the flat block.

Part of :mod:`asperity2d.closed_forms` (which lists the references).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from . import BASE, STEEL_STIFFNESS, G, Check, _register, current_engine, registered  # noqa: F401


# -- the asperity model's contact laws (asperity2d.contact_laws) ----------------------------------
#: The flat block of the contact-law checks: one flat block on one flat lower block, free under
#: 2 mN, on a drive whose damper (5e-4 N s/m, eight times critical on the 372 kN/m spring) holds
#: the block's speed at the drive's: steady sliding for every law, whatever the slope of mu(v).
LAW_BLOCK = dict(profile="flat", height=0.25e-6, lower_count=1, upper_count=1, track="free",
                 normal_load=2e-3, mu_static=0.4, mu_kinetic=0.3, drive_stiffness=3.72e5,
                 drive_damping=5e-4)
#: Each built-in contact law's parameters in the checks (SI).
LAW_CASES = {"static-kinetic": {}, "velocity-weakening": {"v_s": 3.0}, "viscous": {"viscosity": 0.01},
             "rate-state": {"rs_a": 0.01, "rs_b": 0.015, "d_c": 1e-9, "v_0": 1.0}}
#: The drive speeds (m/s) of the steady-sliding ladder.
LAW_SPEEDS = (1.0, 3.0, 10.0)


def steady_friction(scene, *, duration: float = 2e-8, window: float = 0.4) -> tuple[float, float]:
    """``(mu, v)``: the mean tangential contact force over the normal load, and the mean speed, of
    ``scene`` (a flat block, free) over the last ``window`` of a run of ``duration`` s."""
    from ..run import simulate

    result = simulate(scene, duration, record_every=50, progress=False)
    late = result.t >= result.t[-1] - window * duration
    return (float(np.mean(result.tangential_force[late])) / scene.slider.normal_load,
            float(np.mean(result.v[late])))


def contact_law_of(scene):
    """The contact law as the engine builds it for ``scene`` (internal units; ``steady`` in SI)."""
    from ..engine import Engine
    from ..run import default_dt

    return Engine(scene, default_dt(scene)).switch.law


def _law_steady(law: str) -> Check:
    from ..builders import make_scene

    worst = None
    for v in LAW_SPEEDS:
        scene = make_scene(contact_law=law, drive_velocity=v, **LAW_BLOCK, **LAW_CASES[law])
        expected = contact_law_of(scene).steady(v)
        measured, _ = steady_friction(scene)
        if worst is None or abs(measured / expected - 1) > abs(worst[1] / worst[0] - 1):
            worst = (expected, measured, v)
    expected, measured, v = worst
    return Check(
        name=f"flat block in steady sliding follows the {law} law's μ(v) (1, 3, 10 m/s; worst {v:g} m/s)",
        closed_form="F / N = μ_ss(V), the law's steady curve", expected=expected, measured=measured,
        unit="1", tolerance=1e-4,
        why="in steady sliding the contact impulse is μ times the normal one up to the solver's "
            "convergence (the samples scatter by 5e-5 relative, their mean over the window by "
            "less); the block's speed is the drive's to 1e-5, moving μ(v) by under 1e-6",
        source="the law's closed form (asperity2d.contact_laws)")


for _law in LAW_CASES:
    _register(f"law-steady-{_law}", functools.partial(_law_steady, _law))


@registered("rate-state-velocity-step")
def rate_state_velocity_step() -> Check:
    """The rate-and-state law stepped as the engine steps it through a velocity step 3 -> 9 m/s."""
    from ..builders import make_scene

    v1, v2 = 3.0, 9.0
    law = contact_law_of(make_scene(contact_law="rate-state", drive_velocity=v1, **LAW_BLOCK,
                                    **LAW_CASES["rate-state"]))
    s1, s2 = v1 / law.velocity, v2 / law.velocity
    mu, state = law.step(law.initial, s1, 1.0, True)
    for _ in range(int(30 * law.d_c / (s1 * law.dt))):  # 30 D_c of slip: theta at D_c / v1 to e^-30
        mu, state = law.step(state, s1, 1.0, False)
    jump, state = law.step(state, s2, 1.0, False)
    return Check(
        name="rate-and-state law: direct effect of a velocity step 3 -> 9 m/s (the engine's step)",
        closed_form="Δμ = a ln(v2 / v1)", expected=law.a * math.log(v2 / v1), measured=jump - mu, unit="1",
        tolerance=0.015,
        why="over its first step at v2 the state already evolves: θ falls by the factor "
            "1 - (1 - v1 / v2)(1 - e^(-v2 dt / D_c)) (0.69 % at the engine's 1.15 ps), lowering μ by "
            "b times that, 0.95 % of the jump; the regularisation differs from the logarithm by "
            "e^(-2 μ / a), nothing",
        source="Dieterich (1979), Ruina (1983); regularised as Rice, Lapusta & Ranjith (2001)")


@registered("rate-state-steady-change")
def rate_state_steady_change() -> Check:
    """The flat block's steady μ at 9 m/s against that at 3 m/s, both from runs."""
    from ..builders import make_scene

    mus = [steady_friction(make_scene(contact_law="rate-state", drive_velocity=v, **LAW_BLOCK,
                                      **LAW_CASES["rate-state"]))[0] for v in (3.0, 9.0)]
    p = LAW_CASES["rate-state"]
    return Check(
        name="rate-and-state law: steady change of the flat block's friction from 3 to 9 m/s",
        closed_form="Δμ_ss = (a - b) ln(v2 / v1)", expected=(p["rs_a"] - p["rs_b"]) * math.log(3.0),
        measured=mus[1] - mus[0], unit="1", tolerance=0.015,
        why="each steady μ is within 1e-4 relative of the law (law-steady checks): 3e-5 each on "
            "μ = 0.3, 1.1 % of the 5.5e-3 change at worst; the regularisation differs from the "
            "logarithm by e^(-2 μ / a), nothing",
        source="Dieterich (1979), Ruina (1983)")


def spring_block_growth(scene, *, dampings, settle: float = 2e-8, duration: float = 4e-8,
                        kick: float = 0.01) -> list[float]:
    """The growth rates (1/s) of small oscillations of a flat block in steady sliding.

    ``scene`` (a flat block, free) slides steadily on its drive's damper for ``settle`` s; then,
    in a fork of that run for each of ``dampings`` (N s/m), the damper takes that value and the
    drive speeds up by ``kick`` (a small velocity step, which starts an oscillation about the new
    steady sliding); each rate is the slope of the log of the peaks of abs(v - V) over the last
    three quarters of ``duration`` s.
    """
    from ..run import Run

    run = Run(scene, record_every=4)  # >= 40 samples a period in the checks
    run.settle()
    run.advance(settle)
    v = scene.drive.velocity * (1 + kick)
    rates = []
    for damping in dampings:
        fork = run.fork()
        engine = fork.engine
        engine.drive.c = damping / engine.units.damping
        fork.set_drive_velocity(v)
        fork.advance(duration)
        r = fork.result()
        s = np.abs(r.v - v)
        peaks = np.flatnonzero((s[1:-1] > s[:-2]) & (s[1:-1] >= s[2:])) + 1
        t = r.t[peaks]
        keep = t > t[0] + 0.25 * (t[-1] - t[0])
        rates.append(float(np.polyfit(t[keep], np.log(s[peaks][keep]), 1)[0]))
    return rates


def _crossing(x, rates) -> float:
    """Where the growth rate changes sign between the two points ``x`` (linear), NaN if it does not."""
    (x1, x2), (g1, g2) = x, rates
    return x1 + (x2 - x1) * g1 / (g1 - g2) if g1 * g2 < 0 else math.nan


@registered("rate-state-critical-stiffness")
def rate_state_critical_stiffness() -> Check:
    """A spring-block with the rate-and-state law, at 0.9 and 1.1 times Rice & Ruina's k_c."""
    from ..builders import make_scene

    p, N, V = LAW_CASES["rate-state"], LAW_BLOCK["normal_load"], 3.0
    a, b, d_c = p["rs_a"], p["rs_b"], p["d_c"]
    m = make_scene(**LAW_BLOCK).slider.mass
    k_c = N * (b - a) / d_c * (1 + m * V ** 2 / (N * a * d_c))
    ks = (0.9 * k_c, 1.1 * k_c)
    rates = [spring_block_growth(make_scene(contact_law="rate-state", drive_velocity=V,
                                            **{**LAW_BLOCK, "drive_stiffness": k,
                                               "drive_damping": 4 * math.sqrt(k * m),
                                               "drive_preload": 0.3 * N}, **p), dampings=[0.0])[0]
             for k in ks]
    return Check(
        name="rate-and-state spring-block: steady sliding turns unstable at the critical stiffness",
        closed_form="k_c = N (b - a) / D_c · (1 + m V² / (N a D_c))", expected=k_c,
        measured=_crossing(ks, rates), unit="N/m", tolerance=0.02,
        why="the growth rate is measured at 0.9 and 1.1 k_c (it must grow below, decay above) and "
            "its zero found between them linearly: 0.9/1.1 and 0.95/1.05 put it within 0.3 % of "
            "each other; the kick's 1 % step keeps the oscillation near the linear regime",
        source="Rice & Ruina (1983)")


@registered("velocity-weakening-critical-damping")
def velocity_weakening_critical_damping() -> Check:
    """A spring-block with the velocity-weakening law, its damper 0.9 and 1.1 times -N μ'(V)."""
    from ..builders import make_scene
    from ..friction.laws import Stribeck

    N, V, v_s = LAW_BLOCK["normal_load"], 3.0, LAW_CASES["velocity-weakening"]["v_s"]
    # the belt chains' own criterion: steady sliding is unstable where c + N μ'(V) < 0
    c_crit = -N * float(Stribeck(mu_s=0.4, mu_k=0.3, v_s=v_s, delta=1.0).slope(V))
    scene = make_scene(contact_law="velocity-weakening", drive_velocity=V, v_s=v_s, **LAW_BLOCK)
    cs = (0.9 * c_crit, 1.1 * c_crit)
    rates = spring_block_growth(scene, dampings=cs, duration=6e-9, kick=0.005)
    return Check(
        name="velocity weakening: a spring-block oscillates and grows where N μ'(V) outweighs its damper",
        closed_form="c_crit = -N μ'(V) = N (μs - μk) e^(-V / v_s) / v_s", expected=c_crit,
        measured=_crossing(cs, rates), unit="N s/m", tolerance=0.02,
        why="the growth rate -(c + N μ'(V)) / 2m is linear in c, so its zero between 0.9 and 1.1 "
            "c_crit is exact but for the curvature of μ(v) over the oscillation (a 0.5 % kick, "
            "growing 8-fold) and the decay's approach to the solver's noise floor",
        source="the belt model's criterion (asperity2d.belt.regime); Den Hartog's negative damping")

