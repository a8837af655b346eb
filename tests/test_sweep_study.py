"""Study descriptions: validation, stable keys, expansion, TOML / Python loading."""

import hashlib

import pytest

from asperity2d.errors import SceneError
from asperity2d.sweep import Study, load_study, run_key

RUN = "sweep_fixtures:noisy_run"


def test_key_is_sha256_of_canonical_json_pinned():
    # pinned regression value: changing the canonical form would orphan every existing store
    text = b'{"params":{"a":"x","b":2,"c":0.5},"run":"pkg.mod:fn","seed":7}'
    assert run_key("pkg.mod:fn", {"b": 2, "a": "x", "c": 0.5}, 7) == hashlib.sha256(text).hexdigest()[:16]
    assert run_key("pkg.mod:fn", {"b": 2, "a": "x", "c": 0.5}, 7) == "482da768c249f3e8"


def test_key_depends_on_path_params_and_seed_only():
    base = run_key(RUN, {"amplitude": 1.0}, 0)
    assert run_key(RUN, {"amplitude": 1.0}, 0) == base
    assert run_key(RUN, {"amplitude": 2.0}, 0) != base
    assert run_key(RUN, {"amplitude": 1.0}, 1) != base
    assert run_key("sweep_fixtures:slow_run", {"amplitude": 1.0}, 0) != base
    a = Study(name="a", run=RUN, grid={"amplitude": [1.0]}, seeds=[0])
    b = Study(name="b", run=RUN, grid={"amplitude": [1.0, 5.0]}, seeds=[3, 0])
    assert a.runs()[0].key in {s.key for s in b.runs()}  # the name does not enter the key


def test_expansion_order_fixed_and_variants():
    study = Study(name="s", run=RUN, grid={"amplitude": [1.0, 2.0], "offset": [0.0, 1.0, 2.0]},
                  seeds=range(3), fixed={"extra": "x"})
    runs = study.runs()
    assert len(runs) == len(study) == 2 * 3 * 3
    assert len({r.key for r in runs}) == len(runs)
    assert runs[0].params == {"extra": "x", "amplitude": 1.0, "offset": 0.0}
    assert [r.seed for r in runs[:4]] == [0, 1, 2, 0]
    assert runs[3].variant == (("amplitude", 1.0), ("offset", 1.0))
    assert runs[3].variant_label == "amplitude=1.0, offset=1.0"
    assert study.seeds == (0, 1, 2)


@pytest.mark.parametrize(
    "kwargs, field",
    [
        ({"name": ""}, "name"),
        ({"name": "a b"}, "name"),
        ({"run": "no_colon"}, "run"),
        ({"run": "mod:1fn"}, "run"),
        ({"grid": {"amplitude": []}}, "grid.amplitude"),
        ({"grid": {"amplitude": "abc"}}, "grid.amplitude"),
        ({"grid": {"amplitude": [1.0, 1.0]}}, "grid.amplitude"),
        ({"grid": {"amplitude": [float("nan")]}}, "grid.amplitude"),
        ({"grid": {"amplitude": [[1, 2]]}}, "grid.amplitude"),
        ({"grid": {"seed": [1]}}, "grid"),
        ({"seeds": 5}, "seeds"),
        ({"seeds": []}, "seeds"),
        ({"seeds": [0, 0]}, "seeds"),
        ({"seeds": [-1]}, "seeds"),
        ({"seeds": [1.5]}, "seeds"),
        ({"fixed": {"amplitude": 1.0}}, "fixed"),
        ({"fixed": {"seed": 1}}, "fixed"),
        ({"quantities": []}, "quantities"),
        ({"quantities": "mean"}, "quantities"),
        ({"quantities": ["mean", "mean"]}, "quantities"),
    ],
)
def test_invalid_study_names_the_field(kwargs, field):
    args = {"name": "s", "run": RUN, "grid": {"amplitude": [1.0]}, "seeds": [0]}
    args.update(kwargs)
    with pytest.raises(SceneError, match=f"`{field}"):
        Study(**args)


def test_study_is_frozen_and_keyword_only():
    study = Study(name="s", run=RUN, grid={"amplitude": [1.0]}, seeds=[0])
    with pytest.raises(AttributeError):
        study.name = "t"
    with pytest.raises(TypeError):
        Study("s", RUN)  # positional arguments are rejected
    assert hash(study) == hash(Study(name="s", run=RUN, grid={"amplitude": (1.0,)}, seeds=(0,)))


def test_load_toml_and_round_trip(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(
        'name = "spacing"\nrun = "sweep_fixtures:noisy_run"\nseeds = 4\n'
        'quantities = ["mean"]\n[grid]\namplitude = [1.0, 2.0]\n[fixed]\noffset = 0.5\n'
    )
    study = load_study(path)
    assert study == Study(name="spacing", run=RUN, grid={"amplitude": [1.0, 2.0]},
                          seeds=range(4), fixed={"offset": 0.5}, quantities=("mean",))
    assert Study.from_dict(study.to_dict()) == study
    path.write_text('name = "x"\nrun = "m:f"\nseeds = {start = 3, stop = 6}\n')
    assert load_study(path).seeds == (3, 4, 5)


def test_load_python_script(tmp_path):
    path = tmp_path / "s.py"
    path.write_text(
        "from asperity2d.sweep import Study\n"
        "STUDY = Study(name='py', run='sweep_fixtures:noisy_run', grid={'amplitude': [1.0]},"
        " seeds=range(2))\n"
    )
    assert load_study(path).name == "py"
    path.write_text("x = 1\n")
    with pytest.raises(SceneError, match="`study`"):
        load_study(path)


@pytest.mark.parametrize(
    "text, field",
    [
        ('name = "x"\nrun = "m:f"\nseeds = 3\nbogus = 1\n', "study"),
        ('name = "x"\nrun = "m:f"\n', "seeds"),
        ('name = "x"\nrun = "m:f"\nseeds = {start = 1}\n', "seeds"),
        ('name = "x"\nrun = "m:f"\nseeds = 0\n', "seeds"),
        ("name = \n", "study"),
    ],
)
def test_bad_toml_names_the_field(tmp_path, text, field):
    path = tmp_path / "s.toml"
    path.write_text(text)
    with pytest.raises(SceneError, match=f"`{field}`"):
        load_study(path)


def test_missing_or_unknown_study_file(tmp_path):
    with pytest.raises(SceneError, match="`study`"):
        load_study(tmp_path / "nope.toml")
    (tmp_path / "s.yaml").write_text("x")
    with pytest.raises(SceneError, match="`study`"):
        load_study(tmp_path / "s.yaml")
