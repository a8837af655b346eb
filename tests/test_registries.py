"""Every registry is one :class:`asperity2d._registry.Registry`, and every entry of each is tested
by walking the registry, so an entry added (in the package, by a test, or by an installed
package's entry point) is an entry checked:

* the helper itself: register, a collision refused in one line, unregister, "did you mean",
  ``module:name``, an entry point that is broken or collides kept as one line;
* each belt back end against ``exact`` on shared chains (events and tolerance);
* each output format written twice gives identical bytes;
* each measure states a step policy (an outside measure that states none says so);
* a back end returning arrays of the wrong length, and a contact law missing a method, are one
  line naming them.
"""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import asperity2d as a
from asperity2d._registry import Registry, UnknownName, resolve
from asperity2d.errors import SceneError


# -- the helper --------------------------------------------------------------------------------------
def _colours() -> Registry:
    reg = Registry("colour", None, key=lambda e: e["name"], param="colour")
    for name in ("red", "green", "blue"):
        reg.register({"name": name})
    return reg


def test_register_refuses_a_taken_name_in_one_line_unless_replacing():
    reg = _colours()
    with pytest.raises(SceneError, match=r"^`colour` 'red' is already registered \(pass replace=True\)$"):
        reg.register({"name": "red"})
    entry = reg.register({"name": "red", "shade": 2}, replace=True)
    assert reg["red"] is entry and list(reg) == ["red", "green", "blue"]  # order of first registration
    assert reg.unregister("red") is entry and "red" not in reg
    with pytest.raises(SceneError, match="must be one of green, blue, got 'red'"):
        reg.unregister("red")


def test_an_unknown_name_is_one_line_with_the_nearest_names_and_a_key_error_for_get():
    reg = _colours()
    with pytest.raises(SceneError, match=r"^`colour` must be one of red, green, blue, got 'gren' "
                                         r"\(did you mean 'green'\?\)$"):
        reg.lookup("gren")
    with pytest.raises(SceneError, match="`--colour` must be one of"):
        reg.lookup("purple", "--colour")
    assert reg.get("gren") is None and isinstance(UnknownName("x"), KeyError)
    with pytest.raises(SceneError, match="at most 1,000 characters"):
        reg.lookup("x" * 100_000)
    with pytest.raises(SceneError, match="must be a name, got int"):
        reg.lookup(3)


def test_module_colon_name_works_wherever_a_name_does_and_fails_in_one_line():
    reg = _colours()
    assert reg.lookup("string:ascii_lowercase") == "abcdefghijklmnopqrstuvwxyz"
    assert "string:digits" in reg and reg["string:digits"] == "0123456789"
    assert "string:digits" not in list(reg)  # resolved, not registered
    with pytest.raises(SceneError, match=r"^`colour` 'no_such_module_x:y': module 'no_such_module_x' cannot be "
                                         r"imported \(ModuleNotFoundError"):
        reg.lookup("no_such_module_x:y")
    with pytest.raises(SceneError, match="'string' has no attribute 'nope'"):
        resolve("string:nope")


class _EntryPoint:
    """What importlib.metadata hands the registry: a name, a value, its distribution, load()."""

    def __init__(self, name, value, load, package="outside-pkg"):
        self.name, self.value, self._load = name, value, load
        self.dist = type("Dist", (), {"name": package})()

    def load(self):
        return self._load()


def test_entry_points_load_on_first_use_and_a_broken_one_is_one_line(monkeypatch):
    import asperity2d._registry as registry

    def boom():
        raise ImportError("No module named 'outside_pkg.gone'")

    points = [_EntryPoint("purple", "outside_pkg:PURPLE", lambda: {"name": "purple"}),
              _EntryPoint("gone", "outside_pkg.gone:X", boom),
              _EntryPoint("red", "outside_pkg:RED", lambda: {"name": "red"}),
              _EntryPoint("wrong", "outside_pkg:WRONG", lambda: 42)]
    calls = []
    monkeypatch.setattr(registry, "_entry_points", lambda group: calls.append(group) or points)

    def check(entry):
        if not isinstance(entry, dict):
            raise SceneError(f"a colour is a dict, got {type(entry).__name__}")
        return entry

    reg = Registry("colour", "asperity2d.colours", key=lambda e: e["name"], check=check)
    reg.register({"name": "red"})
    assert calls == []  # nothing loaded until the registry is read
    assert list(reg) == ["red", "purple"] and calls == ["asperity2d.colours"]
    assert reg.failures == {
        "gone": "entry point 'gone' of package 'outside-pkg' (group asperity2d.colours) cannot be loaded "
                "(ImportError: No module named 'outside_pkg.gone')",
        "red": "entry point 'red' of package 'outside-pkg' (group asperity2d.colours): colour 'red' is already "
               "registered",
        "wrong": "entry point 'wrong' of package 'outside-pkg' (group asperity2d.colours) is not a colour: `colour` "
                 "'wrong' is not a colour: a colour is a dict, got int"}
    with pytest.raises(SceneError, match=r"^`colour` 'gone': entry point 'gone' of package 'outside-pkg'"):
        reg.lookup("gone")
    len(reg)
    assert calls == ["asperity2d.colours"]  # once per process


def test_every_registry_of_the_package_is_one_registry_with_its_entry_point_group():
    from asperity2d._registry import GROUPS
    from asperity2d.belt.solver import METHODS
    from asperity2d.contact_laws import LAWS
    from asperity2d.experiments.measures import MEASURES
    from asperity2d.renderers import FORMATS
    from asperity2d.saved import RESULT_KINDS

    registries = {"asperity2d.measures": MEASURES, "asperity2d.contact_laws": LAWS,
                  "asperity2d.formats": FORMATS, "asperity2d.belt_methods": METHODS,
                  "asperity2d.result_kinds": RESULT_KINDS}
    for group, registry in registries.items():
        assert isinstance(registry, Registry) and registry.group == group and group in GROUPS
        assert len(registry) > 0 and not registry.failures


# -- every belt back end against exact -----------------------------------------------------------------
#: Chains every back end of the tangential chain accepts, each with what it shows: stick-slip of one
#: mass (the closed-form reference), three coupled masses (the multi-DOF belt thesis' Table 2), two
#: damped masses, and a chain that never sticks (the belt outruns every mass: sign() friction is
#: then Coulomb friction, and the thesis' sign() model must agree with the exact one).
SHARED_CHAINS = {
    "one mass, stick-slip": dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3,
                                 v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0),
    "table2-3dof": "table2-3dof",
    "two damped masses": dict(masses=[1.0, 2.0], springs=[50.0, 20.0, 30.0], dampers=[0.2, 0.1, 0.0], mu_s=0.3,
                              mu_k=0.2, v_belt=0.2, x0=[0.0, 0.01], v0=[0.2, 0.0], t_end=3.0),
    "never sticks": dict(masses=[1.0, 1.0], springs=[10.0, 5.0, 10.0], dampers=[0.1, 0.0, 0.1], mu_s=0.2,
                         v_belt=1.5, x0=[0.0, 0.01], v0=[0.0, 0.0], t_end=3.0),
}
#: sign() friction chatters wherever a mass sticks (the thesis' own model, not a solver of the exact
#: one): it is compared where nothing sticks, and only there.
ONLY_SLIDING = {"sign() friction through solve_ivp"}


def _chain(name: str) -> dict:
    kw = SHARED_CHAINS[name]
    if isinstance(kw, str):
        kw = a.belt.presets.preset(kw)
    kw = dict(kw)
    kw.pop("method", None)
    return kw


def _pairs():
    from asperity2d.belt.solver import METHODS

    for method, backends in METHODS.items():
        for backend in backends:
            for chain in SHARED_CHAINS:
                yield pytest.param(method, backend.name, chain, id=f"{method}/{backend.name}/{chain}")


@pytest.mark.parametrize("method, backend_name, chain", list(_pairs()))
def test_each_belt_back_end_agrees_with_exact_on_the_shared_chains(method, backend_name, chain):
    from asperity2d.belt.solver import METHODS
    from asperity2d.belt.spec import ChainSpec

    backend = next(b for b in METHODS[method] if b.name == backend_name)
    kw = _chain(chain)
    spec = ChainSpec(kw["masses"], kw["springs"], kw["dampers"], kw.get("mu_s"), kw.get("mu_k"), kw["v_belt"],
                     kw["x0"], kw["v0"], kw["t_end"], kw.get("g", 9.81), kw.get("normal_load"), kw.get("friction"))
    if not backend.accepts(spec):
        pytest.skip(f"{backend_name} does not take this chain")
    reference = a.belt.simulate_chain(**kw)
    if backend_name in ONLY_SLIDING and reference.stick_intervals != [[]] * reference.n:
        pytest.skip("the chain sticks: sign() friction chatters there (a different model)")
    result = a.belt.simulate_chain(**kw, method=backend)  # the back end itself, as solve_ivp takes a class
    assert result.meta["backend"] == backend_name
    scale = float(np.ptp(reference.x))
    if result.meta["backend"] == reference.meta["backend"]:  # exact's own choice: the same run
        np.testing.assert_array_equal(result.x, reference.x)
        return
    # the same switches, in the same order, each within 1e-6 of the run's length in time: the
    # integrated phases locate a switch by solve_ivp's event finder at rtol 1e-8 (measured: 1.1e-8 s
    # on the one-mass chain), so 100x that bounds it with room for the chains' longer runs
    assert [(e.mass, e.kind) for e in result.events] == [(e.mass, e.kind) for e in reference.events]
    assert all(abs(x.t - y.t) <= 1e-6 * kw["t_end"] for x, y in zip(result.events, reference.events))
    # positions at the reference's samples: 1e-6 of the motion's range for the event-driven back
    # ends (measured 4e-8); 1e-4 for sign() (LSODA over a whole run, its error control scaled by
    # atol: measured 4e-6 of the range on the chain that never sticks)
    x = np.array([np.interp(reference.t, result.t, row) for row in result.x])
    tol = 1e-4 if backend_name in ONLY_SLIDING else 1e-6
    assert np.abs(x - reference.x).max() <= tol * scale


def test_every_back_end_is_compared_with_another_on_a_chain_or_is_the_only_one_for_its_chains():
    # a back end that no shared chain compares (it is exact's only choice for what it runs) says so
    from asperity2d.belt.solver import METHODS

    only_choice = {"closed-form contact phases": "the only back end of a chain with a normal contact",
                   "state-variable ODE (Dahl, LuGre)": "the only back end of a law with a state variable",
                   "closed-form phases": "the reference the others are compared with"}
    names = {b.name for backends in METHODS.values() for b in backends}
    assert set(only_choice) <= names
    assert names - set(only_choice) >= {"integrated phases", "sign() friction through solve_ivp"}


def test_a_back_end_returning_arrays_of_the_wrong_length_is_one_line_naming_it_and_the_array():
    from asperity2d.belt.backend import Backend, RawRun

    def short(spec, options):
        t = np.asarray(options.samples, dtype=float)
        n = len(spec.masses)
        full = np.zeros((n, t.size))
        return RawRun(t=t, x=full, v=full[:, :-1], state=full, friction_force=full, work=np.zeros((3, t.size)),
                      stick_intervals=[[]] * n)

    with pytest.raises(SceneError, match=r"^back end 'short' returned `v` of shape \(1, 20\), expected \(1, 21\) "
                                         r"\(1 masses, 21 samples of `t`\)$"):
        a.belt.simulate_chain([1.0], [1.0, 0.0], [0.0, 0.0], mu_s=0.5, v_belt=0.1, x0=[0.0], v0=[0.1], t_end=1.0,
                              n_samples=21, method=Backend("short", lambda spec: True, short))
    with pytest.raises(SceneError, match="back end 'none' must return a RawRun, got NoneType"):
        a.belt.simulate_chain([1.0], [1.0, 0.0], [0.0, 0.0], mu_s=0.5, v_belt=0.1, x0=[0.0], v0=[0.1], t_end=1.0,
                              method=Backend("none", lambda spec: True, lambda spec, options: None))


def test_a_method_can_be_registered_once_and_a_class_is_a_back_end():
    from asperity2d.belt.solver import METHODS, backends_of, register_method, unregister_method

    class Nothing:
        def run(self, spec, options):
            raise SceneError("`masses`: nothing runs")

    (backend,) = register_method("nothing", Nothing)
    try:
        assert backend.name == "Nothing" and backend.settings == () and "nothing" in METHODS
        with pytest.raises(SceneError, match="`method` 'nothing' is already registered"):
            register_method("nothing", Nothing)
        with pytest.raises(SceneError, match="nothing runs"):
            a.belt.simulate_chain([1.0], [1.0, 0.0], [0.0, 0.0], mu_s=0.5, v_belt=0.1, x0=[0.0], v0=[0.1],
                                  t_end=1.0, method="nothing")
    finally:
        unregister_method("nothing")
    with pytest.raises(SceneError, match="`method` must be a method name, a Backend or a back-end class"):
        backends_of(object())
    with pytest.raises(SceneError, match=r"`method` must be one of exact, sign.*\(did you mean 'exact'\?\)"):
        a.belt.simulate_chain([1.0], [1.0, 0.0], [0.0, 0.0], mu_s=0.5, v_belt=0.1, x0=[0.0], v0=[0.1], t_end=1.0,
                              method="exakt")


# -- every output format: the same result twice, the same bytes ----------------------------------------
@pytest.fixture(scope="module")
def examples():
    belt = a.belt.simulate_chain(**_chain("one mass, stick-slip"), n_samples=401)  # sticks and slips: a sound
    asperity = a.simulate(a.make_scene(lower_count=4, upper_count=2), progress=False)
    comparison = a.Comparison(values={"regular": (1.0, 1.0), "random": (0.8, 0.9)}, seeds=(0, 1), measure="critical")
    return {"belt": belt, "asperity": asperity, "comparison": comparison}


def _format_kinds():
    from asperity2d.renderers import FORMATS

    for ext, fmt in FORMATS.items():
        for kind in fmt.kinds:
            yield pytest.param(ext, kind, id=f"{ext}/{kind}")


@pytest.mark.parametrize("ext, kind", list(_format_kinds()))
def test_each_output_format_written_twice_gives_identical_bytes(ext, kind, examples, tmp_path):
    import importlib.util

    if kind not in examples:
        pytest.skip(f"no example {kind} result here (the surface tests draw those)")
    if ext == ".mp4" and importlib.util.find_spec("imageio_ffmpeg") is None:
        pytest.skip("the video extra is not installed")
    options = {"frames": 6} if ext in (".gif", ".mp4") else {}
    digests = []
    for attempt in ("first", "second"):
        path = a.render(examples[kind], tmp_path / f"{attempt}{ext}", **options)
        digests.append(hashlib.sha256(path.read_bytes()).hexdigest())
    assert digests[0] == digests[1]


# -- every measure: its step policy -----------------------------------------------------------------------
def test_each_measure_states_its_step_policy_and_an_outside_one_gets_the_default_step():
    from asperity2d.experiments.measures import (DEFAULT_DT_FRACTION, MEASURES, STEP_TOLERANCE, Measure,
                                                 measure_step, register_measure, unregister_measure)
    from asperity2d.run import default_dt

    scene = a.make_scene(lower_count=4, upper_count=2)
    for name, entry in MEASURES.items():
        assert entry.dt_fraction is not None and 0 < entry.dt_fraction <= 1, name
        assert entry.step_tolerance is not None and STEP_TOLERANCE[name] == entry.step_tolerance
        assert measure_step(name, scene) == entry.dt_fraction * default_dt(scene)
        assert entry.step_policy.startswith("dt") and "no step policy" not in entry.to_dict()["step"]
    outside = register_measure(Measure("outside", len, "an outside measure"))
    try:
        assert outside.step_policy == "default dt (no step policy stated)"
        assert measure_step("outside", scene) == DEFAULT_DT_FRACTION * default_dt(scene) == default_dt(scene)
    finally:
        unregister_measure("outside")
    with pytest.raises(SceneError, match="`dt_fraction` must be in"):
        Measure("bad", len, "bad", dt_fraction=2.0)


def test_a_saved_comparison_of_a_measure_this_session_does_not_know_keeps_its_unit_and_label(tmp_path):
    from asperity2d.experiments.measures import Measure, register_measure, unregister_measure

    def gap_of(scene) -> float:
        return 1e-6

    register_measure(Measure("gap-of", gap_of, "gap of the outside package", unit="m"))
    try:
        made = a.Comparison(values={"regular": (1e-6, 2e-6)}, seeds=(0, 1), measure="gap_of",
                            saved_label="gap of the outside package", saved_unit="m")
        assert made.label == "gap of the outside package" and made.unit == "m"
        path = made.save(tmp_path / "gap.json")
    finally:
        unregister_measure("gap-of")
    back = a.Comparison.load(path)  # the measure is gone: its words and unit come from the file
    assert back.entry is None and back.label == "gap of the outside package" and back.unit == "m"
    assert back == made
    assert "regular: mean 1.500 µm" in "\n".join(back.report()[1])


# -- every contact law: the whole contract, or one line --------------------------------------------------
def test_a_contact_law_missing_a_method_is_refused_in_one_line_naming_it():
    from dataclasses import dataclass

    from asperity2d.contact_laws import LAWS, REQUIRED_METHODS, ContactLaw, LawEntry, register_law

    @dataclass(frozen=True)
    class Half(ContactLaw):
        mu: float

        @classmethod
        def from_contact(cls, contact, stick_speed, slip_distance, dt):
            return cls(contact.mu_kinetic)

        def coefficient(self, stuck):  # the old contract's method: not the new one's step / idle / steady
            return self.mu

    with pytest.raises(SceneError, match=r"^`law` 'half' \(Half\) does not define step, idle, steady \(the ContactLaw "
                                         r"contract\)$"):
        register_law(LawEntry("half", "asperity", Half))
    assert "half" not in LAWS
    for name, entry in LAWS.items():  # every registered asperity law keeps the whole contract
        if entry.model == "asperity":
            assert all(getattr(entry.law, m) is not getattr(ContactLaw, m) for m in REQUIRED_METHODS)
