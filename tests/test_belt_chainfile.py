"""Chain files in the model layer: ``ChainSpec.to_toml`` / ``from_toml`` (a normal contact
included), the command line running such a file, and the basin map's chain record through
``ChainSpec.from_dict``.

A round trip must give back an equal spec *and* the same run to the bit: the file writes every
number as its shortest round-trip text, so nothing may move.
"""

import json

import numpy as np
import pytest

from asperity2d import SceneError, belt
from asperity2d.belt import NormalContact, presets
from asperity2d.belt.chainfile import read_chain
from asperity2d.cli import main
from asperity2d.friction import Stribeck

ARRAYS = ("t", "x", "v", "state", "friction_force", "belt_work", "friction_dissipation", "damper_dissipation")
CONTACT_ARRAYS = ARRAYS + ("y", "vy", "normal_force", "impact_dissipation")


def _same_run(first, second, names):
    for name in names:
        a, b = getattr(first, name), getattr(second, name)
        assert a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes(), name
    assert first.events == second.events and first.stick_intervals == second.stick_intervals


def _chains():
    table2 = presets.preset("table2-3dof", t_end=3.0)
    stribeck = {k: v for k, v in presets.preset("table4-c0.5", t_end=3.0).items() if k not in ("mu_s", "mu_k")}
    return [
        table2,                                                             # mu_s = mu_k (Coulomb)
        {**table2, "mu_k": 0.15, "normal_load": [5.0, 10.0, 20.0]},        # static/kinetic, a load
        {**stribeck, "friction": Stribeck(0.3, 0.2, 0.05)},                 # a [friction] table
    ]


@pytest.mark.parametrize("kwargs", _chains(), ids=["coulomb", "static-kinetic-load", "stribeck"])
def test_a_chain_round_trips_through_toml_to_the_bit(kwargs, tmp_path):
    first = belt.simulate_chain(**kwargs)
    path = first.chain.to_toml(tmp_path / "chain.toml")
    spec = belt.ChainSpec.from_toml(path)
    assert type(spec) is belt.ChainSpec and spec == first.chain and spec.law == first.chain.law
    _same_run(first, belt.simulate_chain(**spec.arguments()), ARRAYS)
    # and what the command line reads is the same chain
    _same_run(first, belt.simulate_chain(**read_chain(path)), ARRAYS)


CONTACTS = [
    (NormalContact(), [0.001, 0.0, 0.002], [0.1, 0.0, -0.05]),                               # rigid, impacts
    (NormalContact(stiffness=100.0, preload=-5.0, contact_stiffness=1e4, inclined=((50.0, 30.0),)), None, None),
    (NormalContact(stiffness=400.0, damping=3.0, preload=20.0, restitution=0.5), None, [0.0, 0.2, 0.0]),
]


@pytest.mark.parametrize("normal, y0, vy0", CONTACTS, ids=["rigid", "compliant-inclined", "rigid-bouncy"])
def test_a_chain_with_a_normal_contact_round_trips_through_toml_to_the_bit(normal, y0, vy0, tmp_path):
    first = belt.simulate_chain(**presets.preset("table2-3dof", t_end=2.0), normal=normal, y0=y0, vy0=vy0)
    path = first.contact.to_toml(tmp_path / "contact.toml", method="exact", n_samples=2001)
    text = path.read_text()
    assert "[normal]" in text and "y0 = " in text and "normal_load" not in text
    spec = belt.ChainSpec.from_toml(path)
    assert type(spec) is belt.ContactSpec and spec == first.contact
    second = belt.simulate_chain(**spec.arguments())
    assert isinstance(second, belt.ContactResult)
    _same_run(first, second, CONTACT_ARRAYS)
    assert second.separation_intervals == first.separation_intervals


def test_the_command_line_runs_a_chain_file_with_a_normal_contact(tmp_path, capsys):
    kwargs = dict(masses=[1.0], springs=[100.0, 0.0], dampers=[0.0, 0.0], mu_s=0.4, mu_k=0.3, v_belt=0.1, x0=[0.0],
                  v0=[0.1], t_end=2.0)
    normal = NormalContact(stiffness=1e4, contact_stiffness=1e5)
    path = tmp_path / "chain.toml"
    path.write_text('masses = [1.0]\nsprings = [100.0, 0.0]\ndampers = [0.0, 0.0]\nmu_s = 0.4\nmu_k = 0.3\n'
                    'v_belt = 0.1\nx0 = [0.0]\nv0 = [0.1]\nt_end = 2.0\n'
                    '[normal]\nstiffness = 1e4\ncontact_stiffness = 1e5\n')
    assert main(["belt", str(path), "-o", str(tmp_path / "run.npz"), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    expected = belt.simulate_chain(**kwargs, normal=normal)
    assert summary["events"] == len(expected.events) and summary["final_x"] == expected.x[:, -1].tolist()
    saved = belt.load(tmp_path / "run.npz")
    assert isinstance(saved, belt.ContactResult) and saved.contact.normal == normal
    assert saved.contact.y0 == expected.contact.y0 and saved.chain.law == expected.chain.law


@pytest.mark.parametrize("text, needle", [
    ("[normal]\nstiff = 1.0\n", "`normal.stiff` is not a NormalContact parameter"),
    ("[normal]\nrestitution = 2.0\n", "`normal.restitution` must be within [0, 1]"),
    ("normal = 3\n", "`normal` must be a table of NormalContact parameters"),
    ("yy0 = [0.0]\n", "`yy0` in "),
])
def test_a_bad_normal_table_is_one_line_naming_the_key_and_the_file(text, needle, tmp_path, capsys):
    path = tmp_path / "bad.toml"
    path.write_text('masses = [1.0]\nsprings = [100.0, 0.0]\ndampers = [0.0, 0.0]\nmu_s = 0.4\nv_belt = 0.1\n'
                    'x0 = [0.0]\nv0 = [0.1]\nt_end = 2.0\n' + text)
    with pytest.raises(SceneError) as info:
        belt.ChainSpec.from_toml(path)
    assert needle in str(info.value) and "bad.toml" in str(info.value)
    assert main(["belt", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert needle in err and "bad.toml" in err and len(err.splitlines()) == 1


def test_a_function_belt_speed_cannot_be_written(tmp_path):
    spec = belt.ChainSpec((1.0,), (1.0, 0.0), (0.0, 0.0), 0.4, 0.3, lambda t: 0.1, (0.0,), (0.0,), 1.0)
    with pytest.raises(SceneError, match="`v_belt` is a function"):
        spec.to_toml(tmp_path / "c.toml")


@pytest.mark.parametrize("extra", [{}, {"normal": NormalContact(contact_stiffness=1e5), "vy0": [0.0, 0.1, 0.0]}],
                         ids=["chain", "contact"])
def test_the_basin_maps_chain_record_is_the_models(extra):
    from asperity2d.dynamics.basins import _decode_chain, _encode_chain

    kwargs = {**presets.preset("table2-3dof", t_end=1.0), **extra, "n_samples": 101}
    decoded = _decode_chain(_encode_chain(kwargs))
    assert decoded["n_samples"] == 101 and "spec" not in decoded
    _same_run(belt.simulate_chain(**kwargs), belt.simulate_chain(**decoded), ARRAYS)
