"""Named chains from the multi-DOF belt thesis' tables, as keyword arguments for :func:`~asperity2d.belt.simulate_chain`.

The thesis uses one friction coefficient mu0 in sign() friction, so the
presets set mu_s = mu_k = mu0. Figures 3-4 (2-DOF) run on a still surface
(their captions say v_belt = 0) although Table 1 lists 0.01 m/s: both are
offered. The 3-DOF presets use the initial conditions of eq 3.12 (the
appendix code starts from rest instead: ``"table2-3dof-rest"``).
"""

from __future__ import annotations

import copy

from ..errors import SceneError

IC_2DOF = {"x0": [0.05, 0.06], "v0": [0.04, 0.03]}  # eq 3.3 (m, m/s)
IC_3DOF = {"x0": [0.05, 0.06, 0.07], "v0": [0.04, 0.03, 0.05]}  # eq 3.12 (m, m/s)


def _two(mu0, v_belt):
    return dict(masses=[1.0, 1.0], springs=[10.0] * 3, dampers=[0.0] * 3, mu_s=mu0, mu_k=mu0,
                v_belt=v_belt, t_end=10.0, **IC_2DOF)


def _three(m=1.0, k=10.0, c=0.0, mu0=0.2, v_belt=0.1, ic=IC_3DOF):
    return dict(masses=[m] * 3, springs=[k] * 4, dampers=[c] * 4, mu_s=mu0, mu_k=mu0,
                v_belt=v_belt, t_end=10.0, **ic)


PRESETS = {
    "table1-2dof-free": (lambda: _two(0.0, 0.0), "Fig 3a/4a: 2-DOF, no friction, still surface"),
    "table1-2dof": (lambda: _two(0.05, 0.0), "Fig 3b/4b: 2-DOF, mu0 = 0.05, still surface (captions)"),
    "table1-2dof-belt": (lambda: _two(0.05, 0.01), "Table 1 as listed: 2-DOF, mu0 = 0.05, belt 0.01 m/s"),
    "table2-3dof": (lambda: _three(), "Table 2 / Fig 5: 3-DOF base case"),
    "table2-3dof-rest": (lambda: _three(ic={"x0": [0.0] * 3, "v0": [0.0] * 3}),
                         "Table 2 from rest (appendix B code)"),
    "table3-k20": (lambda: _three(k=20.0), "Table 3 case I / Fig 6: k = 20 N/m"),
    "table3-k30": (lambda: _three(k=30.0), "Table 3 case II / Fig 7: k = 30 N/m"),
    "table4-c0.5": (lambda: _three(c=0.5), "Table 4 case I / Fig 8: c = 0.5 N·s/m"),
    "table4-c2": (lambda: _three(c=2.0), "Table 4 case II / Fig 9: c = 2 N·s/m"),
    "table5-m1.5": (lambda: _three(m=1.5), "Table 5 case I / Fig 10: m = 1.5 kg"),
    "table5-m2.5": (lambda: _three(m=2.5), "Table 5 case II / Fig 11: m = 2.5 kg"),
    "table6-v0.4": (lambda: _three(v_belt=0.4), "Table 6 case I / Fig 12: v_belt = 0.4 m/s"),
    "table6-v0.7": (lambda: _three(v_belt=0.7), "Table 6 case II / Fig 13: v_belt = 0.7 m/s"),
    "table7-mu0.4": (lambda: _three(mu0=0.4), "Table 7 / Fig 14: mu0 = 0.4"),
}


#: ``simulate_chain`` arguments a preset does not set but accepts as overrides
RUN_SETTINGS = frozenset({"method", "n_samples", "t_eval", "rtol", "atol", "integrator", "friction", "normal_load",
                          "g", "include_events", "max_events", "max_steps", "max_wall_time", "normal", "y0",
                          "vy0"})


def names() -> list[str]:
    return sorted(PRESETS)


def describe(name: str) -> str:
    return _lookup(name)[1]


def preset(name: str, **overrides) -> dict:
    """Keyword arguments for ``simulate_chain`` for preset ``name``, updated by ``overrides``.

    A ``friction`` law replaces the preset's ``mu_s`` / ``mu_k``. The result is the caller's own:
    its lists can be changed without changing the preset (they were shared with the table's
    initial conditions, so one caller's edit reached every later run of the preset).
    """
    kwargs = copy.deepcopy(_lookup(name)[0]())
    unknown = set(overrides) - set(kwargs) - RUN_SETTINGS
    if unknown:
        raise SceneError(f"`{sorted(unknown)[0]}` is not a parameter of preset {name!r}")
    if overrides.get("friction") is not None:
        kwargs.pop("mu_s")
        kwargs.pop("mu_k")
    kwargs.update(overrides)
    return kwargs


def _lookup(name):
    if name not in PRESETS:
        raise SceneError(f"`preset` must be one of {', '.join(names())}, got {name!r}")
    return PRESETS[name]
