"""The extension points, used from outside the package: a toy measure, a toy output format, a toy
contact law and a toy belt back end, each added through its registry alone and run end to end,
then removed.

Nothing here edits a package file: if one of these needs a second file touched, the
extension point is not one.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import asperity2d as a
from asperity2d.cli import main
from asperity2d.experiments.measures import MEASURES, Measure, register_measure, unregister_measure
from asperity2d.experiments.verdicts import VerdictRule
from asperity2d.renderers import FORMATS, OutputFormat, register_format, render, unregister_format
from asperity2d.saved import RESULT_KINDS

TINY = {"lower_count": 6, "upper_count": 2}


# -- a measure ------------------------------------------------------------------------------------
def smallest_gap(scene) -> float:
    """The smallest tip-to-tip gap between neighbouring lower asperities (m): geometry only, so
    the comparison below costs no simulation."""
    spacing = scene.lower.spacing
    return float(np.diff(spacing.tips(*scene.lower.profile.runs(upper=False))).min())


@pytest.fixture
def toy_measure():
    entry = register_measure(Measure("smallest-gap", smallest_gap, "smallest gap between lower asperities",
                                     unit="m", drive="force", rule=VerdictRule(alpha=0.01, direction="less")))
    yield entry
    unregister_measure("smallest-gap")
    assert "smallest-gap" not in MEASURES


def test_a_measure_added_through_the_registry_is_listed_compared_and_judged(toy_measure, capsys):
    assert main(["measures", "--json"]) == 0
    listed = {m["name"]: m for m in json.loads(capsys.readouterr().out)["measures"]}
    assert listed["smallest-gap"]["unit"] == "m"
    assert listed["smallest-gap"]["label"] == "smallest gap between lower asperities"
    assert main(["measures"]) == 0
    assert any(line.startswith("smallest-gap") and "[m]" in line for line in capsys.readouterr().out.splitlines())

    comparison = a.compare("smallest-gap", {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}},
                           range(8), base=TINY, progress=False, workers=1)
    assert comparison.unit == "m" and comparison.label == toy_measure.label
    record = comparison.verdict("random", "regular", subject="random spacing")
    # random tips are drawn about the same mean pitch, so on every seed some gap is below the
    # regular pitch: 8/8 seeds below, one-sided exact Wilcoxon p = 2**-8 = 0.0039 < 0.01, and the
    # change (about -15 % here) is far above the 1 % no-effect band: the rule must say it holds
    assert record["numbers"]["below"] == 8
    assert record["numbers"]["p_wilcoxon"] == pytest.approx(2.0 ** -8)
    assert record["verdict"] == "holds"
    assert record["claim"] == "random spacing lowers the smallest gap between lower asperities"

    # and the command line runs it by name, printing the unit and the verdict it got from the library
    assert main(["compare", "--measure", "smallest-gap", "--seeds", "8", "--workers", "1",
                 "--set", "lower_count=6", "--set", "upper_count=2"]) == 0
    out = capsys.readouterr().out
    assert "regular: mean 1.250 µm" in out
    assert "random spacing lowers the smallest gap between lower asperities: holds" in out


# -- an output format -----------------------------------------------------------------------------
def write_csv(result, path, **options):
    """The slider's track: one ``t,x`` line per sample."""
    t, x = np.asarray(result.t), np.asarray(result.slider_x if hasattr(result, "slider_x") else result.x[0])
    path.write_text("t,x\n" + "".join(f"{float(ti)!r},{float(xi)!r}\n" for ti, xi in zip(t, x)))
    return path


@pytest.fixture
def toy_format():
    fmt = register_format(OutputFormat(".csv", "the time series as CSV", {"belt": write_csv}, "table"))
    yield fmt
    unregister_format(".csv")
    assert ".csv" not in FORMATS
    # nor its drawer on the kinds it drew (a later test reading the belt's drawers would see it)
    assert "table" not in RESULT_KINDS["belt"].drawers


def test_a_format_added_through_the_registry_is_rendered_and_in_the_help(toy_format, tmp_path, capsys):
    result = a.belt.simulate_chain([1.0], [10.0, 0.0], [0.1, 0.0], mu_s=0.5, mu_k=0.3, v_belt=0.1, x0=[0.0],
                                   v0=[0.1], t_end=0.5, n_samples=11)
    out = render(result, tmp_path / "chain.CSV")  # the extension picks it, in any case
    rows = out.read_text().splitlines()
    assert rows[0] == "t,x" and len(rows) == 1 + len(result.t)
    assert float(rows[-1].split(",")[1]) == result.x[0, -1]
    # a kind it does not accept is refused in the format's own words
    with pytest.raises(a.SceneError, match="for a asperity result|must end in one of"):
        render(_FakeAsperity(), tmp_path / "run.csv")
    assert main(["render", "--help"]) == 0
    assert ".csv: the time series as CSV" in " ".join(capsys.readouterr().out.split())  # argparse wraps lines


class _FakeAsperity:
    kind = "asperity"


# -- a belt back end ------------------------------------------------------------------------------
def run_frozen(spec, options):
    """One mass stuck to the belt, held by a spring to the wall: x = x0 + v_belt t, the friction
    force balances the spring (k x), the belt does the work k v (x0 t + v t^2 / 2) = the spring's
    energy gain, and nothing slips (no dissipation). A toy: it never checks that the friction
    limit holds. Returns the contract's RawRun."""
    from asperity2d.belt.backend import RawRun
    from asperity2d.errors import SceneError

    if len(spec.masses) != 1:
        raise SceneError("`masses`: the frozen back end takes one mass")
    t = np.asarray(options.samples, dtype=float)
    k, v, x0 = float(spec.springs[0]), float(spec.v_belt), float(spec.x0[0])
    x = (x0 + v * t)[None, :]
    work = np.zeros((3, t.size))
    work[0] = k * v * (x0 * t + 0.5 * v * t * t)
    return RawRun(t=t, x=x, v=np.full((1, t.size), v), state=np.zeros((1, t.size)), friction_force=k * x,
                  work=work, events=[], stick_intervals=[[(float(t[0]), float(t[-1]))]], meta={})


@pytest.fixture
def toy_backend():
    from asperity2d.belt.solver import METHODS, Backend

    METHODS["frozen"] = (Backend("every mass stuck to the belt", lambda spec: True, run_frozen),)
    yield METHODS["frozen"][0]
    del METHODS["frozen"]
    assert "frozen" not in METHODS


def test_a_back_end_added_to_methods_runs_through_simulate_chain(toy_backend):
    result = a.belt.simulate_chain([1.0], [2.0, 0.0], [0.0, 0.0], mu_s=0.5, mu_k=0.3, v_belt=0.2, x0=[0.1],
                                   v0=[0.2], t_end=1.0, n_samples=21, method="frozen")
    assert result.meta["backend"] == "every mass stuck to the belt" and result.meta["method"] == "frozen"
    np.testing.assert_array_equal(result.x[0], 0.1 + 0.2 * result.t)  # what the back end returned, unchanged
    with pytest.raises(a.SceneError, match="`method`"):
        a.belt.simulate_chain([1.0], [1.0, 0.0], [0.0, 0.0], mu_s=0.5, mu_k=0.3, v_belt=0.1, x0=[0.0], v0=[0.1],
                              t_end=1.0, method="nope")


def test_a_method_whose_back_ends_all_refuse_a_chain_is_one_line():
    from asperity2d.belt.solver import METHODS, Backend

    METHODS["picky"] = (Backend("two masses only", lambda spec: len(spec.masses) == 2, run_frozen),)
    try:
        with pytest.raises(a.SceneError, match="`method` 'picky' has no back end that accepts this chain"):
            a.belt.simulate_chain([1.0], [1.0, 0.0], [0.0, 0.0], mu_s=0.5, mu_k=0.3, v_belt=0.1, x0=[0.0],
                                  v0=[0.1], t_end=1.0, method="picky")
    finally:
        del METHODS["picky"]


def run_pressed(spec, options):
    """A toy back end for chains with a normal contact: one mass pressed on a compliant contact
    at its rest gap and stuck to the belt, held by a spring to the wall. The gap never moves, so
    the normal force stays at the spec's rest value; the belt does the spring's energy gain
    k v (x0 t + v t^2 / 2) and nothing slips or hits. Returns the contract's ContactRun."""
    from asperity2d.belt.backend import ContactRun

    t = np.asarray(options.samples, dtype=float)
    chain, k_c = spec.chain, spec.normal.contact_stiffness
    k, v, x0, y0 = float(chain.springs[0]), float(chain.v_belt), float(chain.x0[0]), float(spec.y0[0])
    x = x0 + v * t
    Z = np.stack([x, np.full_like(t, y0), np.full_like(t, v), np.zeros_like(t)])
    work = np.zeros((4, t.size))
    work[0] = k * v * (x0 * t + 0.5 * v * t * t)
    return ContactRun(t=t, Z=Z, modes=np.zeros((1, t.size), dtype=int), friction_force=(k * x)[None, :],
                      normal_force=np.full((1, t.size), -k_c * y0), work=work,
                      stick_intervals=[[(float(t[0]), float(t[-1]))]], separation_intervals=[[]])


def test_a_back_end_for_chains_with_a_normal_contact_runs_through_simulate_chain():
    from asperity2d.belt import METHODS, Backend, ContactSpec

    METHODS["pressed"] = (Backend("one mass pressed and stuck", lambda spec: isinstance(spec, ContactSpec),
                                  run_pressed, settings=()),)
    chain = dict(masses=[1.0], springs=[2.0, 0.0], dampers=[0.0, 0.0], mu_s=0.5, mu_k=0.3, v_belt=0.2, x0=[0.1],
                 v0=[0.2], t_end=1.0, n_samples=21, method="pressed")
    try:
        result = a.belt.simulate_chain(**chain, normal=a.belt.NormalContact(stiffness=1e4, contact_stiffness=1e5))
        assert isinstance(result, a.belt.ContactResult)
        assert result.meta["backend"] == "one mass pressed and stuck" and "rtol" not in result.meta
        np.testing.assert_array_equal(result.x[0], 0.1 + 0.2 * result.t)  # what the back end returned
        # the rest gap the spec chose shares the weight between the normal spring and the contact:
        # N = m g k_c / (k_c + k_n) = 9.81 * 1e5 / 1.1e5 N (to rounding: the gap is y = -N / k_c)
        np.testing.assert_allclose(result.normal_force[0], 9.81 * 1e5 / 1.1e5, rtol=1e-12)
        assert result.separation_intervals == [[]] and result.summary()["kind"] == "belt"
        # the spring's energy gain is the belt's work: the books close (the driver checks them too)
        assert abs(result.energy_balance_error()) < 1e-12
        # the built-in back ends refuse it, and this one refuses a chain without a normal contact
        with pytest.raises(a.SceneError, match="`method` 'pressed' has no back end .* methods that do: 'exact', "
                                               "'sign'"):
            a.belt.simulate_chain(**chain)
    finally:
        del METHODS["pressed"]


# -- a friction law of the asperity model ---------------------------------------------------------
from dataclasses import dataclass  # noqa: E402

from asperity2d.contact_laws import LAWS, ContactLaw, LawEntry, register_law, unregister_law  # noqa: E402


@dataclass(frozen=True)
class AlwaysKinetic(ContactLaw):
    """Coulomb friction at ``mu_kinetic`` whatever the contact does (no sticking)."""

    mu: float

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed, slip_distance, dt):
        return cls(contact.mu_kinetic)

    @property
    def active(self) -> bool:
        return False  # the coefficient never changes

    @property
    def idle(self) -> float:
        return self.mu

    def step(self, state, slip, impulse, new):
        return self.mu, ()

    def steady(self, v):
        return self.mu


@pytest.fixture
def toy_law():
    entry = register_law(LawEntry("always-kinetic", "asperity", AlwaysKinetic, "Coulomb at mu_kinetic"))
    yield entry
    unregister_law("always-kinetic")
    assert "always-kinetic" not in LAWS


def test_a_contact_law_added_through_the_registry_runs_in_the_python_loop(toy_law):
    from asperity2d.engine import Engine
    from asperity2d.run import default_dt

    scene = a.make_scene(**TINY, mu_static=0.3, mu_kinetic=0.2)  # a spring drive: it sticks and slips
    mine = scene.replace(contact=dataclasses.replace(scene.contact, law="always-kinetic"))
    engine = Engine(mine, default_dt(mine))
    engine.step(50)
    assert engine._kernel is None and "AlwaysKinetic has no C implementation" in engine.loop_reason
    assert set(engine.switch.mu.tolist()) == {0.2}
    # the same friction everywhere as the built-in switch with mu_static = mu_kinetic (which never
    # switches): the two runs are the same run, to the bit
    coulomb = scene.replace(contact=dataclasses.replace(scene.contact, mu_static=0.2))
    from asperity2d.run import default_duration

    duration = 0.2 * default_duration(scene)
    ours, theirs = a.simulate(mine, duration, progress=False), a.simulate(coulomb, duration, progress=False)
    assert np.count_nonzero(ours.friction_force) > 100  # it rubbed over the asperities
    np.testing.assert_array_equal(ours.x, theirs.x)
    np.testing.assert_array_equal(ours.friction_force, theirs.friction_force)
    with pytest.raises(a.SceneError, match="`law`"):
        dataclasses.replace(scene.contact, law="nope")


# -- an outside package, installed: its entry points reach the command line ----------------------
#: A package as a contributor writes it: a pyproject.toml naming one entry of each group, and the
#: modules. Each module imports only what its entry needs (a format's module stays light: the
#: command line's help lists the formats).
TOY_PYPROJECT = '''
[project]
name = "toyext"
version = "0.1"

[project.entry-points."asperity2d.measures"]
toy-lower-count = "toyext.measures:LOWER_COUNT"
broken = "toyext.missing:NOTHING"

[project.entry-points."asperity2d.contact_laws"]
toy-kinetic = "toyext.laws:AlwaysKinetic"

[project.entry-points."asperity2d.formats"]
times = "toyext.formats:TIMES"

[project.entry-points."asperity2d.belt_methods"]
toy-frozen = "toyext.backends:Frozen"
'''

TOY_MODULES = {
    "measures.py": '''
from asperity2d.experiments.measures import Measure


def lower_count(scene) -> float:
    """The number of lower asperities (geometry only: no run)."""
    return float(scene.lower.spacing.count)


LOWER_COUNT = Measure("toy-lower-count", lower_count, "number of lower asperities", unit="")
''',
    "laws.py": '''
from dataclasses import dataclass

from asperity2d.contact_laws import ContactLaw


@dataclass(frozen=True)
class AlwaysKinetic(ContactLaw):
    """Coulomb friction at mu_kinetic whatever the contact does."""

    mu: float

    @classmethod
    def from_contact(cls, contact, *, units, stick_speed, slip_distance, dt):
        return cls(contact.mu_kinetic)

    @property
    def active(self):
        return False

    @property
    def idle(self):
        return self.mu

    def step(self, state, slip, impulse, new):
        return self.mu, ()

    def steady(self, v):
        return self.mu
''',
    "formats.py": '''
from asperity2d.renderers import OutputFormat


def write_times(result, path, **options):
    path.write_text("".join(f"{float(t)!r}\\n" for t in result.t))
    return path


TIMES = OutputFormat(".times", "the sample times, one a line", {"belt": write_times}, "table")
''',
    "backends.py": '''
import numpy as np

from asperity2d.belt.backend import RawRun
from asperity2d.belt.spec import ChainSpec


class Frozen:
    """One mass stuck to the belt, held by a spring to the wall (solve_ivp-style: a class)."""

    name = "one mass stuck to the belt"
    settings = ()

    def accepts(self, spec):
        return isinstance(spec, ChainSpec) and len(spec.masses) == 1

    def run(self, spec, options):
        t = np.asarray(options.samples, dtype=float)
        k, v, x0 = float(spec.springs[0]), float(spec.v_belt), float(spec.x0[0])
        x = (x0 + v * t)[None, :]
        work = np.zeros((3, t.size))
        work[0] = k * v * (x0 * t + 0.5 * v * t * t)
        return RawRun(t=t, x=x, v=np.full((1, t.size), v), state=np.zeros((1, t.size)), friction_force=k * x,
                      work=work, events=[], stick_intervals=[[(float(t[0]), float(t[-1]))]], meta={})
''',
}


def _install_toy_package(root) -> dict:
    """The toy package installed on a path of its own, as pip lays it out (the modules beside a
    ``.dist-info`` whose ``entry_points.txt`` is the pyproject's entry points); returns the
    environment of a process that sees it. Nothing enters the test's own environment."""
    import configparser
    import os
    import tomllib

    source, site = root / "toyext-src", root / "site"
    source.mkdir()
    (source / "pyproject.toml").write_text(TOY_PYPROJECT)
    package = site / "toyext"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    for name, text in TOY_MODULES.items():
        (package / name).write_text(text)
    project = tomllib.loads(TOY_PYPROJECT)["project"]
    info = site / f"{project['name']}-{project['version']}.dist-info"
    info.mkdir()
    (info / "METADATA").write_text(f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n")
    points = configparser.ConfigParser(delimiters=("=",))
    points.optionxform = str  # entry-point names keep their case
    for group, entries in project["entry-points"].items():
        points[group] = entries
    with (info / "entry_points.txt").open("w") as fh:
        points.write(fh)
    return {**os.environ, "PYTHONPATH": str(site)}


def test_an_installed_package_reaches_the_command_line_through_its_entry_points(tmp_path):
    import ast
    import subprocess
    import sys

    env = _install_toy_package(tmp_path)

    def cli(*args, check=True):
        proc = subprocess.run([sys.executable, "-m", "asperity2d", *args], capture_output=True, text=True,
                              env=env, cwd=tmp_path, timeout=300)
        assert not check or proc.returncode == 0, proc.stderr[-3000:]
        return proc

    # its measure: listed (with the step it runs at, none stated), compared by name and as module:name
    proc = cli("measures", "--json")
    listed = {m["name"]: m for m in json.loads(proc.stdout)["measures"]}
    assert listed["toy-lower-count"]["step"] == "default dt (no step policy stated)"
    assert {"critical", "peak-stick"} <= set(listed)
    # the broken entry point is one line naming the package and the entry, and the rest still work
    assert proc.stderr.strip().splitlines() == [
        "asperity2d: warning: entry point 'broken' of package 'toyext' (group asperity2d.measures) cannot be "
        "loaded (ModuleNotFoundError: No module named 'toyext.missing')"]
    proc = cli("compare", "--measure", "broken", "--seeds", "1", check=False)
    assert proc.returncode == 2 and len(proc.stderr.strip().splitlines()) == 1
    assert "entry point 'broken' of package 'toyext'" in proc.stderr
    for name in ("toy-lower-count", "toyext.measures:LOWER_COUNT"):
        out = json.loads(cli("compare", "--measure", name, "--seeds", "2", "--workers", "1", "--json",
                             "--set", "lower_count=5", "--set", "upper_count=2").stdout)
        assert out["variants"]["regular"]["mean"] == 5.0 and out["variants"]["random"]["mean"] == 5.0

    # its contact law, named in a TOML scene run by `asperity2d run`: the run is the Coulomb run at
    # mu_kinetic to the bit (what the law says), not the built-in static/kinetic switch's
    script = ("import dataclasses, asperity2d as a\n"
              "from asperity2d.run import default_duration\n"
              "s = a.make_scene(lower_count=6, upper_count=2, mu_static=0.3, mu_kinetic=0.2)\n"
              "s.replace(contact=dataclasses.replace(s.contact, law='toy-kinetic')).to_toml('toy.toml')\n"
              "s.replace(contact=dataclasses.replace(s.contact, mu_static=0.2)).to_toml('coulomb.toml')\n"
              "s.to_toml('switch.toml')\n"
              "print(0.2 * default_duration(s))\n")
    made = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, cwd=tmp_path,
                          timeout=300)
    assert made.returncode == 0, made.stderr[-3000:]
    assert 'law = "toy-kinetic"' in (tmp_path / "toy.toml").read_text()
    duration = made.stdout.strip()
    for name in ("toy", "coulomb", "switch"):
        cli("run", f"{name}.toml", "--duration", duration, "--save", f"{name}.npz", "--json")
    toy, coulomb, switch = (np.load(tmp_path / f"{name}.npz") for name in ("toy", "coulomb", "switch"))
    assert np.count_nonzero(toy["friction_force"]) > 100  # it rubbed
    np.testing.assert_array_equal(toy["x"], coulomb["x"])
    np.testing.assert_array_equal(toy["friction_force"], coulomb["friction_force"])
    assert not np.array_equal(toy["friction_force"], switch["friction_force"])

    # its back end (a class) by name through `belt --method`, and its format through render() and -o
    (tmp_path / "chain.toml").write_text("masses = [1.0]\nsprings = [2.0, 0.0]\ndampers = [0.0, 0.0]\n"
                                         "mu_s = 0.5\nmu_k = 0.3\nv_belt = 0.2\nx0 = [0.1]\nv0 = [0.2]\n"
                                         "t_end = 1.0\nn_samples = 21\n")
    for method in ("toy-frozen", "toyext.backends:Frozen"):
        out = json.loads(cli("belt", "chain.toml", "--method", method, "--json", "-o", "run.times").stdout)
        assert out["method"] == method and out["final_x"] == [0.1 + 0.2 * 1.0]
        assert [float(t) for t in (tmp_path / "run.times").read_text().split()] == list(np.linspace(0, 1, 21))
    proc = cli("belt", "chain.toml", "--method", "toy-frozn", check=False)
    assert proc.returncode == 2 and "(did you mean 'toy-frozen'?)" in proc.stderr
    render = ("import asperity2d as a\n"
              "r = a.belt.simulate_chain([1.0], [2.0, 0.0], [0.0, 0.0], mu_s=0.5, v_belt=0.2, x0=[0.0], v0=[0.2],"
              " t_end=0.5, n_samples=6)\n"
              "print(a.render(r, 'chain.TIMES').read_text().split())\n")
    proc = subprocess.run([sys.executable, "-c", render], capture_output=True, text=True, env=env, cwd=tmp_path,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    # the file holds the run's sample times: six uniform samples over 0.5 s (to rounding of linspace)
    written = [float(t) for t in ast.literal_eval(proc.stdout)]
    np.testing.assert_allclose(written, np.linspace(0.0, 0.5, 6), rtol=0, atol=1e-15)
    assert ".times: the sample times, one a line" in " ".join(cli("render", "--help").stdout.split())

    # and none of it is in this process: the test's environment is untouched
    assert "toy-lower-count" not in MEASURES and ".times" not in FORMATS
