"""The names ``asperity2d.run``, ``asperity2d.scene`` and ``asperity2d.analysis`` held before they
were split by role still resolve there, as the very objects of their new modules: users' imports,
the docs' ``asperity2d.run.stops_from_settings``, code the workbench writes and pickles that name
the old module all keep working.
"""

from __future__ import annotations

import ast
import importlib
import inspect
import pickle

import pytest

#: Old module -> the public names it defined before the split (its module-level classes, functions
#: and upper-case data) and the module that defines each now.
MOVED = {
    "asperity2d.run": {
        "asperity2d.stops": ["Probe", "Passed", "Stuck", "Travelled", "ForceCrossed", "FirstSlip", "STOP_SETTINGS",
                             "stops_from_settings", "default_stops"],
        "asperity2d.steps": ["DT_FRACTION", "COARSEST_DT_FRACTION", "DAMPER_DT_FRACTION",
                             "COARSEST_DAMPER_DT_FRACTION", "MAX_STEPS", "COST_ASPERITIES", "default_duration",
                             "default_dt", "settle_cap", "step_cost", "check_budget", "resolve_dt"],
        "asperity2d.run_loop": ["Run", "ENERGY_TOLERANCE", "NUMERICAL_ENERGY_TOLERANCE"],
        "asperity2d.run": ["simulate", "Simulation", "simulate_many"],
    },
    "asperity2d.scene": {
        "asperity2d.scene_parameters": ["Parameter", "OOTEN_PARAMETERS", "OOTEN_DEFAULTS", "kinetic_default"],
        "asperity2d.scene_parts": ["TRACKS", "Drive", "LowerSurface", "gershgorin_rows", "Slider", "ConstantForce",
                                   "SpringDrive", "Contact"],
        "asperity2d.scene": ["FLOOR_OVERLAP", "Scene", "TOML_FORMAT", "spec_from_toml", "describe"],
    },
    "asperity2d.analysis": {
        "asperity2d.slip_thresholds": ["STICK_SPEED_FRACTION", "NO_SLIP_PEAK_FRACTION", "SLIP_MARGIN_FRACTION",
                                       "SLIP_SPEED_FRACTION", "MIN_STICK_PERIODS", "MIN_SLIP_PERIODS",
                                       "MIN_SLIP_FRACTION", "slip_scale", "SpringBlockSlip", "spring_block_slip",
                                       "scene_slip", "slip_speed_threshold"],
        "asperity2d.events": ["Event", "EVENT_COLUMNS", "events_table", "stick_slip_events", "event_statistics",
                              "synthetic_stick_slip"],
        "asperity2d.forces": ["breakaway_force", "peak_stick_force", "mean_stick_force", "friction_traces"],
        "asperity2d.contact_states": ["ContactStates", "contact_states"],
    },
}
#: Public names a new module has defined since the split (not moved: nothing older names them).
ADDED = {"asperity2d.run": ["check_scenes"]}
CASES = [(old, new, name) for old, homes in MOVED.items() for new, names in homes.items() for name in names]


@pytest.mark.parametrize("old, new, name", CASES, ids=[f"{o}.{n}" for o, _, n in CASES])
def test_an_old_path_is_the_new_object(old, new, name):
    assert getattr(importlib.import_module(old), name) is getattr(importlib.import_module(new), name)


def _defined(module_name: str) -> set[str]:
    """The public names ``module_name``'s source defines at module level (not those it imports)."""
    module = importlib.import_module(module_name)
    names = set()
    for node in ast.parse(inspect.getsource(module)).body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Assign):
            names |= {t.id for t in node.targets if isinstance(t, ast.Name)}
    return {n for n in names if not n.startswith("_")}


def test_every_name_the_new_modules_define_is_listed():
    # the lists above are whole: each new module defines exactly the names listed for it, so
    # no name was dropped in the move or left off the checks above
    for homes in MOVED.values():
        for new, names in homes.items():
            assert _defined(new) == set(names) | set(ADDED.get(new, [])), new


def test_a_pickle_that_names_the_old_module_loads():
    import asperity2d as a
    from asperity2d.events import Event

    # a pickle written before the split names the class by its old module (protocol 0 spells it out)
    for obj, new, old in [(Event(0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 1.0), b"asperity2d.events", b"asperity2d.analysis"),
                          (a.Passed(), b"asperity2d.stops", b"asperity2d.run")]:
        data = pickle.dumps(obj, protocol=0)
        assert new in data
        back = pickle.loads(data.replace(new, old))
        assert type(back) is type(obj)
        if not isinstance(obj, a.Passed):  # Passed has no fields to compare (no __eq__)
            assert back == obj
    # the scene's parts keep the address they had before the split (asperity2d.scene, where users
    # import them and the reference documents them): a pickle of a scene is what it was
    scene = a.make_scene(lower_count=4, upper_count=2)
    data = pickle.dumps(scene, protocol=0)
    assert b"asperity2d.scene_parts" not in data and b"asperity2d.scene\n" in data
    assert pickle.loads(data) == scene
