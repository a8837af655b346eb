"""Every invalid parameter raises SceneError naming it; the CLI turns it into one line, exit 2."""

import math
import subprocess
import sys

import pytest

import asperity2d as a
from asperity2d.cli import main

BAD = [
    (dict(mass=-1.0), "`mass`"),
    (dict(lower_count=3, mass=[2.88e-16, 0.0, 2.88e-16]), "`mass[1]`"),
    (dict(stiffness=0.0), "`stiffness`"),
    (dict(damping=-1e-7), "`damping`"),
    (dict(mass=math.nan), "`mass`"),
    (dict(stiffness=math.inf), "`stiffness`"),
    (dict(mass=[1e-16, 1e-16]), "`mass`"),  # wrong length
    (dict(mu_static=0.1, mu_kinetic=0.2), "`mu_static`"),
    (dict(mu=-0.1), "`mu`"),
    (dict(pitch=0.0), "`pitch`"),
    (dict(pitch=0.5e-6), "`pitch`"),  # asperities on the lower track would overlap
    (dict(lower_count=0), "`lower_count`"),
    (dict(upper_count=1.5), "`upper_count`"),
    (dict(slider_mass=0.0), "`slider_mass`"),
    (dict(normal_load=-0.01), "`normal_load`"),
    (dict(normal_load=0.0, track="free"), "`normal_load`"),
    (dict(flank_angle=95.0), "`flank_angle`"),
    (dict(base=0.0), "`base`"),
    (dict(height=-1e-6), "`height`"),
    (dict(drive_velocity=0.0), "`drive_velocity`"),
    (dict(drive_stiffness=-1.0), "`drive_stiffness`"),
    (dict(track="sideways"), "`track`"),
    (dict(interference=0.0, track="fixed"), "`interference`"),
    (dict(lower_profile="trapezoid"), "`lower_profile`"),
    (dict(min_gap=-1e-7, spacing="random"), "`min_gap`"),
    (dict(pitch=1.1e-6, min_gap=0.5e-6, spacing="random"), "`pitch`"),
    (dict(stifness=1.0), "`stifness` (did you mean `stiffness`?)"),
    (dict(profile="triangle"), "`profile`"),
    (dict(spacing="chaotic"), "`spacing`"),
    (dict(drive="magnetic"), "`drive`"),
    (dict(seed=-3), "`seed`"),
]


@pytest.mark.parametrize("kwargs, name", BAD, ids=[b[1] for b in BAD])
def test_invalid_parameter_raises_scene_error_naming_it(kwargs, name):
    with pytest.raises(a.SceneError) as info:
        a.make_scene(**kwargs)
    assert name in str(info.value)
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize("kwargs, name", [
    (dict(dt=-1.0), "`dt`"), (dict(record_every=0), "`record_every`"),
    (dict(duration=math.nan), "`duration`"), (dict(iterations=0), "`iterations`"),
    (dict(stop=[42]), "`stop`"),
])
def test_invalid_run_argument_raises_scene_error(kwargs, name):
    with pytest.raises(a.SceneError, match=name):
        a.simulate(a.make_scene(lower_count=2, upper_count=1), **kwargs)


def test_random_spacing_is_seeded_and_never_overlaps():
    one = a.make_scene(spacing="random", seed=7).lower.tips()
    two = a.make_scene(spacing="random", seed=7).lower.tips()
    other = a.make_scene(spacing="random", seed=8).lower.tips()
    assert (one == two).all() and not (one == other).all()
    assert (one[1:] - one[:-1]).min() >= 1e-6  # base + min_gap
    scene = a.make_scene(spacing="random-upper", seed=7)
    assert isinstance(scene.lower.spacing, a.RegularSpacing)
    assert isinstance(scene.slider.spacing, a.RandomSpacing)


def test_scene_round_trips_through_a_plain_dict():
    scene = a.make_scene(spacing="random", seed=4, profile="half", drive="force")
    assert a.Scene.from_dict(scene.to_dict()) == scene


def test_cli_bad_input_is_one_line_and_exit_2(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[scene]\nmass = -1.0\n")
    assert main(["run", str(bad), "--json"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "`mass`" in err[0]
    assert main(["run", str(tmp_path / "missing.toml")]) == 2


def test_cli_bad_input_as_a_subprocess_has_no_traceback(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text("[scene]\nmu_static = 0.1\nmu_kinetic = 0.3\n")
    proc = subprocess.run([sys.executable, "-m", "asperity2d", "run", str(bad)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "`mu_static`" in proc.stderr


def test_the_dataclass_defaults_are_the_builders_defaults():
    # one source of truth (scene.OOTEN_DEFAULTS): Scene() and make_scene() build the same scene;
    # only the builder names it after its arguments
    import dataclasses

    built = a.make_scene()
    assert dataclasses.replace(built, name="") == a.Scene()
    assert built.slider.track == "fixed" and built.contact.mu_kinetic == 0.2


def test_a_slider_start_far_from_the_surface_is_refused_naming_it():
    """The default duration covers the way from ``slider_start`` to the surface: a start a metre
    away is refused up front by the step budget, and the message names the field that made it long."""
    import asperity2d as a

    scene = a.make_scene(lower_count=4, upper_count=2, slider_start=-1.0)
    with pytest.raises(a.SceneError, match=r"move `slider_start` closer to the surface") as info:
        a.simulate(scene)
    assert "\n" not in str(info.value)
