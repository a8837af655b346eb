"""The asperity model's contact laws (asperity2d.contact_laws) under the contract that sees the contact.

* every law in the registry -- an outside one included -- against its own steady curve on the
  flat block (the generic walk);
* the laws with a C version: the C loop is the Python loop to the bit;
* the rate-and-state state: the exact solution of the ageing law over a step;
* the parameters: SI fields of the scene's contact, validated with one line naming them, through
  make_scene, TOML and repr.
"""

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pytest

import asperity2d as a
from asperity2d import closed_forms
from asperity2d.contact_laws import (LAWS, ContactLaw, LawEntry, LawParameter, RateState, register_law,
                                     unregister_law)
from asperity2d.engine import Engine, kernel
from asperity2d.run import default_dt


# -- an outside law, as a contributor writes it ----------------------------------------------------
@dataclass(frozen=True)
class LinearWeakening(ContactLaw):
    """mu = max(mu_k, mu_s - g |v|): a linear fall at the slope ``g`` (s/m), floored at mu_kinetic."""

    mu_s: float
    mu_k: float
    g: float
    velocity: float
    parameters = (LawParameter("lw_slope", 0.002, "s/m", "linear weakening: the slope of mu(v)"),)

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed, slip_distance, dt):
        return cls(contact.mu_static, contact.mu_kinetic, cls.parameter(contact, "lw_slope") * units.velocity,
                   units.velocity)

    @property
    def idle(self):
        return self.mu_k

    def step(self, state, slip, impulse, new):
        return max(self.mu_k, self.mu_s - self.g * abs(slip)), ()

    def steady(self, v):
        return self.step((), v / self.velocity, 0.0, False)[0]


@pytest.fixture
def outside_law():
    register_law(LawEntry("linear-weakening", "asperity", LinearWeakening, "a linear fall"))
    yield "linear-weakening"
    unregister_law("linear-weakening")


def _asperity_laws():
    return [name for name, e in LAWS.items() if e.model == "asperity"]


def _walk(name):
    """The flat block in steady sliding at 5 m/s under the law ``name``: (measured, its steady mu)."""
    scene = a.make_scene(contact_law=name, drive_velocity=5.0, **closed_forms.LAW_BLOCK,
                         **closed_forms.LAW_CASES.get(name, {}))
    measured, v = closed_forms.steady_friction(scene)
    assert v == pytest.approx(5.0, rel=1e-4)  # it slides at the drive's speed
    return measured, closed_forms.contact_law_of(scene).steady(5.0)


def test_every_registered_contact_law_meets_its_own_steady_curve(outside_law):
    """The generic walk: every asperity law in the registry (the outside one too) on the flat block
    in steady sliding at 5 m/s (not one of the validation's speeds) gives its ``steady(v)``:
    tolerance 1e-4, as the closed-form checks (the solver's convergence; the block's speed is the
    drive's to 1e-5)."""
    names = _asperity_laws()
    assert {"static-kinetic", "velocity-weakening", "viscous", "rate-state", outside_law} <= set(names)
    for name in names:
        measured, expected = _walk(name)
        assert measured == pytest.approx(expected, rel=1e-4), name
    # the outside law's curve was met where it differs from Coulomb's: 0.4 - 0.002 x 5 = 0.39
    assert _walk(outside_law)[1] == pytest.approx(0.39, rel=1e-12)


def test_a_law_without_a_c_version_steps_in_python_and_says_so(outside_law):
    scene = a.make_scene(contact_law=outside_law, lower_count=4, upper_count=2)
    engine = Engine(scene, default_dt(scene))
    engine.step(5)
    assert engine._kernel is None and engine.loop_reason == "the contact law LinearWeakening has no C implementation"
    # every law of the package has one: none of them says so
    for name in ("static-kinetic", "velocity-weakening", "viscous", "rate-state"):
        engine = Engine(a.make_scene(contact_law=name, lower_count=4, upper_count=2), default_dt(scene))
        engine.step(5)
        assert engine.loop_reason is None, name
        assert (engine._kernel is not None) == kernel.KERNEL, name


# rate-state twice: its default a = 0.01 keeps x (RateState.coefficient) under 30, where mu is
# a asinh(e^x); a = 0.005 (mu_0 / a = 40) puts every contact past it, on the x + ln 2 form; D_c
# = 4 nm is ~1 step of slip at 400 m/s, so theta is between its old value and D_c / v each step
C_LAWS = [("velocity-weakening", {"v_s": 50.0}), ("viscous", {"viscosity": 0.002}),
          ("rate-state", {"d_c": 4e-9}), ("rate-state", {"rs_a": 0.005, "rs_b": 0.0075, "d_c": 4e-9})]


@pytest.mark.skipif(not kernel.KERNEL, reason=f"the C loop is not usable here: {kernel.KERNEL_REASON}")
@pytest.mark.parametrize("law,params", C_LAWS)
@pytest.mark.parametrize("scene_args", [dict(drive_velocity=400.0),
                                        dict(track="free", spacing="random", seed=2, drive_velocity=400.0)])
def test_a_c_law_steps_the_same_in_both_loops_to_the_bit(law, params, scene_args):
    """Ooten's track (and a free random one) at 400 m/s, 1500 steps: bodies, coefficients and
    what pymunk holds are the same in the C loop and in the Python reference."""
    scene = a.make_scene(contact_law=law, **params, **scene_args)
    out = {}
    for loop in ("C", "python"):
        engine = Engine(scene, default_dt(scene), engaged=scene.slider.track == "fixed")
        engine.settle(20 * scene.slowest_period(), push=2e-3)
        if loop == "python":
            engine._kernel = None
        else:
            assert engine._kernel is not None and engine.loop_reason is None
        engine.step(700)
        if loop == "C":  # 100 steps in Python in between: the law's state goes to the lists and back
            held, engine._kernel = engine._kernel, None
            engine.step(100)
            engine._kernel = held
        else:
            engine.step(100)
        engine.step(700)
        mu = engine.switch.mu
        assert [s.friction for s in engine.layout.lower_shapes] == mu.tolist()
        out[loop] = (engine.bodies_internal().copy(), mu, engine.switch.state)
    np.testing.assert_array_equal(out["C"][0], out["python"][0])
    np.testing.assert_array_equal(out["C"][1], out["python"][1])
    np.testing.assert_array_equal(out["C"][2], out["python"][2])  # rate-state's theta (NaN: not touching)
    # the coefficients moved with the slip speed: more than the two values of a switch
    assert len(set(out["C"][1].tolist())) > 2


@pytest.mark.skipif(not kernel.KERNEL, reason=f"the C loop is not usable here: {kernel.KERNEL_REASON}")
def test_the_c_rate_state_step_is_the_reference_on_every_branch():
    """The C loop's rate-and-state step (``asp_rate_state_step``, the function its loop calls)
    against RateState.step, bit for bit, on the branches a run seldom reaches: slip speed 0
    (theta ages by dt, mu = 0), a contact just formed, creep at 1e-300 (a denormal-range
    log), x past 30 (the x + ln 2 form) and just under it, an underflowing exp(-v dt / D_c),
    and an aged state. Both call the same libm (Python's math.log, exp, expm1 and asinh are
    libm's; checked bit-equal here), so no tolerance: equal or not."""
    ffi, lib = kernel.ffi, kernel.lib
    for law in (RateState(a=0.01, b=0.015, d_c=1e-9, v_0=1.0, mu_0=0.3, dt=1e-12),
                RateState(a=0.005, b=0.0075, d_c=3e-3, v_0=2e-4, mu_0=0.2, dt=0.7)):
        ctx = ffi.new("asp_ctx *")
        for name in ("a", "b", "d_c", "v_0", "mu_0", "dt"):
            setattr(ctx, f"rs_{name}", getattr(law, name))
        theta_c = ffi.new("double *")
        xs = []
        for v in (0.0, 1e-300, 1e-12, 1e-3, 0.37, 1.0, 3.0, 1e4, 1e12):
            for theta in (1e-30, law.d_c / law.v_0, 2.5e-9, 1.0, 1e8):
                for new in (False, True):
                    mu, (theta_py,) = law.step((theta,), v, 1.0, new)
                    theta_c[0] = theta
                    mu_c = lib.asp_rate_state_step(ctx, new, v, theta_c)
                    assert (mu_c, theta_c[0]) == (mu, theta_py), (v, theta, new)
                    if v > 0:  # RateState.coefficient's x
                        ln_state = math.log(law.v_0 * theta_py / law.d_c)
                        xs.append(math.log(v / (2 * law.v_0)) + (law.mu_0 + law.b * ln_state) / law.a)
        assert min(xs) < 30.0 < max(xs)  # both forms of the coefficient were compared


def test_the_rate_state_state_follows_the_ageing_laws_exact_solution():
    law = RateState(a=0.01, b=0.015, d_c=1e-9, v_0=1.0, mu_0=0.3, dt=1e-12)
    theta0, v = 5e-9, 3.0
    state = (theta0,)
    for _ in range(400):
        _, state = law.step(state, -v, 1.0, False)  # the sign of the slip does not matter
    ss = law.d_c / v
    assert state[0] == pytest.approx(ss + (theta0 - ss) * math.exp(-v * 400e-12 / law.d_c), rel=1e-12, abs=0)
    for _ in range(10):  # at rest the contact ages one step per step
        _, state = law.step(state, 0.0, 1.0, False)
    assert state[0] == pytest.approx(ss + (theta0 - ss) * math.exp(-1.2) + 1e-11, rel=1e-12, abs=0)
    # stable whatever the step: a step of 1000 D_c / v lands on the steady state, not past it
    coarse = RateState(a=0.01, b=0.015, d_c=1e-9, v_0=1.0, mu_0=0.3, dt=1e-6)
    mu, (theta,) = coarse.step((theta0,), v, 1.0, False)
    assert theta == pytest.approx(ss, rel=1e-12, abs=0) and mu == pytest.approx(coarse.steady(v), rel=1e-12)
    # creep: over a step at eps = v dt / D_c << 1 the contact ages by dt less eps (theta + dt / 2),
    # to O(eps^2) -- theta keeps its precision at any creep speed (the form
    # D_c / v + (theta - D_c / v) e^(-eps) cancels to ~ulp(D_c / v): 0 at 1e-300, and log(0))
    for creep in (1e-8, 1e-300):
        eps = creep * 1e-12 / law.d_c
        _, (aged,) = law.step((theta0,), creep, 1.0, False)
        assert aged == pytest.approx(theta0 + 1e-12 - eps * (theta0 + 0.5e-12), rel=1e-15, abs=0)
    # regularised: 0 at rest, never negative, the logarithmic form where v / v_0 e^(mu / a) >> 1
    assert law.coefficient(0.0, 1e-9) == 0.0 and law.coefficient(1e-30, 1e-9) >= 0.0
    assert law.steady(3.0) == pytest.approx(0.3 + (0.01 - 0.015) * math.log(3.0), rel=1e-14)
    # a contact forms at the reference state: mu_0 at v_0
    mu, (theta,) = law.step(law.initial, 1.0, 1.0, True)
    assert mu == pytest.approx(0.3, rel=1e-14) and theta == pytest.approx(1e-9, rel=1e-14, abs=0)


@pytest.mark.parametrize("law,params", [("velocity-weakening", {"v_s": 2.5}), ("viscous", {"viscosity": 0.01}),
                                        ("rate-state", {"rs_a": 0.012, "rs_b": 0.02, "d_c": 2e-9, "mu_0": 0.25}),
                                        ("static-kinetic", {})])
def test_law_parameters_round_trip_through_toml_and_repr(tmp_path, law, params):
    scene = a.make_scene(contact_law=law, lower_count=4, upper_count=2, **params)
    assert scene.contact.law == law and dict(scene.contact.law_params) == params
    scene.to_toml(tmp_path / "s.toml")
    from asperity2d.scene_io import read_scene

    assert read_scene(tmp_path / "s.toml")[0] == scene
    assert eval(repr(scene.contact), {"Contact": a.Contact}) == scene.contact  # "Copy as Python"
    # make_scene's arguments in a TOML file name the law and its parameters the same way
    lines = [f'contact_law = "{law}"', "lower_count = 4", "upper_count = 2"]
    lines += [f"{k} = {v!r}" for k, v in params.items()]
    (tmp_path / "args.toml").write_text("\n".join(lines) + "\n")
    assert read_scene(tmp_path / "args.toml")[0] == scene
    # the default law's scene file reads as it did before laws had parameters
    if law == "static-kinetic":
        assert "law" not in (tmp_path / "s.toml").read_text()


def test_an_outside_laws_parameters_go_through_law_params(outside_law, tmp_path):
    scene = a.make_scene(contact_law=outside_law, lw_slope=0.004, lower_count=4, upper_count=2)
    assert scene.contact.law_params == (("lw_slope", 0.004),)
    assert a.make_scene(contact_law=outside_law, law_params={"lw_slope": 0.004}, lower_count=4,
                        upper_count=2) == scene
    scene.to_toml(tmp_path / "s.toml")
    from asperity2d.scene_io import read_scene

    assert read_scene(tmp_path / "s.toml")[0] == scene


@pytest.mark.parametrize("kwargs,message", [
    (dict(contact_law="rate-state", d_c=-1e-9), r"^`d_c` must be > 0, got -1e-09$"),
    (dict(contact_law="rate-state", rs_b=math.nan), r"^`rs_b` must be a finite number, got nan$"),
    (dict(contact_law="viscous", viscosity="thick"), r"^`viscosity` must be a real number, got 'thick'$"),
    (dict(v_s=1.0), r"^`v_s` is a parameter of the contact law 'velocity-weakening', and `contact_law` is "
                    r"'static-kinetic': set contact_law='velocity-weakening' or drop it$"),
    (dict(contact_law="viscous", law_params={"d_c": 1.0}),
     r"^`d_c` is not a parameter of the contact law 'viscous' \(its parameters: viscosity\)$"),
    (dict(contact_law="viscous", viscosity=0.1, law_params={"viscosity": 0.2}),
     r"^`viscosity` given both as a keyword and in `law_params`: give one$"),
    (dict(contact_law="stick"), r"^`contact_law` must be one of static-kinetic, velocity-weakening, viscous, "
                                r"rate-state, got 'stick'$"),
])
def test_bad_law_parameters_are_one_line_naming_them(kwargs, message):
    with pytest.raises(a.SceneError, match=message):
        a.make_scene(**kwargs)


def test_a_law_parameter_name_taken_by_another_law_is_refused():
    @dataclass(frozen=True)
    class Clash(LinearWeakening):
        parameters = (LawParameter("v_s", 1.0, "m/s", "clashes with velocity weakening"),)

    with pytest.raises(a.SceneError, match=r"'v_s' is already a parameter of the contact law 'velocity-weakening'"):
        register_law(LawEntry("clash", "asperity", Clash))
    assert "clash" not in LAWS


def test_velocity_weakening_sticks_and_slips_only_where_its_slope_beats_the_damping():
    """The belt's criterion on the flat block: from steady sliding at 3 m/s with a 0.5 % kick, a
    damper of half -N mu'(V) lets the oscillation grow until the block sticks (its speed falls to
    the stick level, under 1 % of V) and slips again; one of 1.5 times it brings the block back
    to steady sliding (within 0.1 % of V after 10 ns: it decays at 0.25 c_crit / m = 2e9 1/s, to the solver's noise
    floor of ~3e-5)."""
    from asperity2d.friction import Stribeck
    from asperity2d.run import Run

    N, V = 2e-3, 3.0
    c_crit = -N * float(Stribeck(mu_s=0.4, mu_k=0.3, v_s=3.0, delta=1.0).slope(V))
    run = Run(a.make_scene(contact_law="velocity-weakening", drive_velocity=V, v_s=3.0, **closed_forms.LAW_BLOCK),
              record_every=4)
    run.settle()
    run.advance(2e-8)
    out = {}
    for f in (0.5, 1.5):
        fork = run.fork()
        fork.engine.drive.c = f * c_crit / fork.engine.units.damping
        fork.set_drive_velocity(1.005 * V)
        fork.advance(1.5e-8)
        out[f] = fork.result()
    late = out[1.5].t > out[1.5].t[0] + 1e-8  # the last 5 ns
    assert np.abs(out[1.5].v[late] / (1.005 * V) - 1).max() < 1e-3
    stuck = out[0.5].v < 0.01 * V
    assert stuck.any() and (out[0.5].v[stuck.argmax():] > V).any()  # stuck, then slipping again


@pytest.mark.slow  # ~40 s of CPU: 16 named measures on the smallest track
def test_the_contact_law_lesson_gives_a_verdict_per_law_and_measure(tmp_path, capsys):
    """scenes/contact_laws_spacing.py --quick: a claim record per (law, measure), every comparison
    saved and drawn, each law's coefficients in the summary."""
    from scene_scripts import run_script

    summary = run_script("contact_laws_spacing", tmp_path, capsys, "--no-gif", "--workers", "1")
    claims = summary["claims"]
    assert len(claims) == 8 and all(c["verdict"] for c in claims)
    assert {c["claim"].split(",")[0] for c in claims} == {f"under {law}" for law in
                                                           ("static-kinetic", "velocity-weakening",
                                                            "viscous", "rate-state")}
    for m in ("critical-run-up", "peak-stick"):
        assert (tmp_path / f"{m}.png").stat().st_size > 0 and (tmp_path / f"{m}.json").stat().st_size > 0
    mu = summary["coefficients"]
    # the laws' own closed forms at rest and sliding: the viscous law has no static excess
    assert mu["viscous"]["rest"] < mu["viscous"]["drive"] and mu["static-kinetic"]["rest"] == 0.3


def test_the_laws_examples_run(tmp_path, monkeypatch):
    """The Examples sections of asperity2d.contact_laws (each law's) run as doctests."""
    import doctest

    import asperity2d.contact_laws as module

    monkeypatch.chdir(tmp_path)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert result.attempted >= 20 and result.failed == 0
