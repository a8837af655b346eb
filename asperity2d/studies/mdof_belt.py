"""The multi-DOF belt thesis' studies: masses on a moving belt (the ``scenes/belt_*.py`` scripts).

Every quantitative statement of the thesis becomes a claim record
(:func:`asperity2d.experiments.verdicts.claim`) whose numbers hold the thesis' value and the
computed one, judged by a criterion fixed before looking at the numbers
(default: within ``REL_TOL`` = 5 % for a number read off a figure).
:func:`belt_chain_run` is the sweep run function of ``scenes/belt_study.toml``.

The scripts read their options with :mod:`asperity2d.scripting` like every scene script;
:func:`claim_lines` says their claims in words.
"""

from __future__ import annotations

import math

import numpy as np

from .._format import si
from ..belt import classify, presets, simulate_chain
from ..dynamics import chain_lyapunov, flow_map
from ..dynamics.basins import LABELS, RUN_CPU_LIMIT, chain_basins, classify_chain, cpu_limit, with_initial
from ..errors import SimulationError
from ..experiments.verdicts import claim

#: A number read off one of the thesis' figures holds if the computed one is within this fraction.
REL_TOL = 0.05


#: What solved the runs and how their claims are judged (each study's summary carries both).
SOLVER = "asperity2d.belt exact event-driven (closed-form phases, brentq switches)"
VERDICT_RULE = f"numbers read off the thesis' figures hold within {REL_TOL:.0%}; trends as stated"


def run(name: str, *, quick: bool = False, **overrides):
    """Simulate one of the thesis' chains, a preset of ``asperity2d.belt.presets``.

    Parameters
    ----------
    name : str
        The preset's name (``"table1-2dof"``, ``"table2-3dof"``, ``"table3-k20"``, ...).
    quick : bool, default False
        Fewer output samples (501 instead of 4001); the events and the physics are unchanged.
    **overrides
        Arguments of :func:`asperity2d.belt.simulate_chain` that replace the preset's.

    Returns
    -------
    asperity2d.belt.BeltResult
        The exact run.
    """
    return simulate_chain(**presets.preset(name, n_samples=501 if quick else 4001, **overrides))


def number_claim(text, thesis_value, computed, unit="s", rel_tol=REL_TOL):
    """A number read off the thesis against the computed one.

    Parameters
    ----------
    text : str
        The thesis' statement.
    thesis_value, computed : float
        The thesis' value and the computed one, in ``unit``.
    unit : str, default "s"
        Their SI unit.
    rel_tol : float, default ``REL_TOL``
        The claim holds if ``|computed - thesis_value| <= rel_tol * |thesis_value|``.

    Returns
    -------
    dict
        A claim record; its ``numbers`` hold both values as text in engineering units and the
        relative difference at full precision.
    """
    ok = abs(computed - thesis_value) <= rel_tol * abs(thesis_value)
    rel = (computed - thesis_value) / thesis_value if thesis_value and math.isfinite(computed) else math.nan
    return claim(text, ok, numbers={"thesis": si(thesis_value, unit, 3, trim=True),
                                    "computed": si(computed, unit, 3), "relative_difference": rel},
                 test=f"|computed - thesis| <= {rel_tol:.0%} of thesis")


def trend_claim(text, labels, values, expect, criterion, unit=""):
    """A trend the thesis states, judged on one value per case.

    Parameters
    ----------
    text : str
        The thesis' statement.
    labels : sequence of str
        The cases (``"k=10"``, ``"k=20"``, ...).
    values : sequence of float
        The measured value of each case, in ``unit``.
    expect : callable
        ``expect(values) -> bool``: whether the trend holds.
    criterion : str
        The test in words.
    unit : str, default ""
        The values' SI unit ("" for a count).

    Returns
    -------
    dict
        A claim record whose ``numbers["computed"]`` maps each label to its value.
    """
    ok = bool(expect(np.asarray(values, dtype=float)))
    return claim(text, ok, numbers={"thesis": "trend", "unit": unit,
                                    "computed": {str(lab): _r(v) for lab, v in zip(labels, values)}},
                 test=criterion)


def claim_lines(claims) -> list[str]:
    """The claim records of a belt study in words, one line each.

    Parameters
    ----------
    claims : list of dict
        Records of :func:`number_claim` and :func:`trend_claim` (or any claim record).

    Returns
    -------
    list of str
        ``"[verdict] statement: the thesis says X, computed Y"``; a trend lists its values.
    """
    lines = []
    for c in claims:
        n = c["numbers"]
        computed = n.get("computed")
        if isinstance(computed, dict):  # a trend: one value per case, in the claim's unit
            computed = ", ".join(f"{label}: {si(v, n['unit'], 3) if n.get('unit') else f'{v:.3g}'}"
                                 for label, v in computed.items())
        said = "" if n.get("thesis") == "trend" else f"the thesis says {n.get('thesis')}, "
        lines.append(f"[{c['verdict']:>13}] {c['claim']}: {said}computed {computed}")
    return lines


def _r(v):
    return float(f"{float(v):.6g}")


def first_stick(result, i):
    """Mass ``i``'s first stick interval of positive length.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult
        A run.
    i : int
        The mass (0-based).

    Returns
    -------
    tuple of float or None
        (start, end) in s, or None if the mass never sticks.
    """
    for a, b in result.stick_intervals[i]:
        if b > a:
            return (a, b)
    return None


def final_rest(result, i):
    """When mass ``i`` comes to rest for good: the start of a stick interval that lasts to the end.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult
        A run.
    i : int
        The mass (0-based).

    Returns
    -------
    float or None
        The time (s), or None if the mass is moving at the end of the run.
    """
    per = result.stick_intervals[i]
    if per and per[-1][1] >= result.t[-1]:
        return per[-1][0]
    return None


def total_stick(result):
    """Total stick time of each mass.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult
        A run.

    Returns
    -------
    list of float
        One total per mass (s).
    """
    return [float(sum(b - a for a, b in per)) for per in result.stick_intervals]


def amplitude(result, *, window=0.5):
    """Half the peak-to-peak displacement of each mass over the last part of the run.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult
        A run.
    window : float, default 0.5
        The fraction of the run, at its end, that is measured.

    Returns
    -------
    list of float
        One amplitude per mass (m).
    """
    sel = result.t >= (1 - window) * result.t[-1]
    return [float(a) for a in 0.5 * np.ptp(result.x[:, sel], axis=1)]


def oscillations(result):
    """The number of oscillations of each mass: upward crossings of its mean position.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult
        A run.

    Returns
    -------
    list of int
        One count per mass.
    """
    out = []
    for x in result.x:
        y = x - x.mean()
        out.append(int(np.count_nonzero((y[:-1] < 0) & (y[1:] >= 0))))
    return out


def case_summary(result):
    """What a study reports of one run.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult
        A run.

    Returns
    -------
    dict
        Per mass: ``first_stick``, ``total_stick_time_s``, ``stick_count``, ``amplitude_m``,
        ``oscillations``; the run's ``regime`` (:func:`asperity2d.belt.classify`), its ``events``
        and its ``energy_balance_error``.
    """
    return {
        "first_stick": [first_stick(result, i) for i in range(result.n)],
        "total_stick_time_s": [_r(s) for s in total_stick(result)],
        "stick_count": [len(per) for per in result.stick_intervals],
        "amplitude_m": [_r(a) for a in amplitude(result)],
        "oscillations": oscillations(result),
        "regime": classify(result),
        "events": result.meta["n_events"],
        "energy_balance_error": result.energy_balance_error(),
    }


def motion_class(result) -> dict:
    """The kind of motion a belt run settles into, from its last quarter.

    Rest, pure slip, stick-slip (a limit cycle of period n: its multiplicity) or irregular, as the
    basin maps of ``asperity2d.dynamics`` classify their runs.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult
        A run, long enough to have settled.

    Returns
    -------
    dict
        ``class`` (``"rest"``, ``"pure slip"``, ``"stick-slip"`` or ``"irregular"``),
        ``multiplicity`` (int), ``period_s`` (the cycle's period, NaN if none) and
        ``last_stick_s`` (the last stick onset, NaN if none).
    """
    found = classify_chain(result)
    return {"class": LABELS[int(found["label"])], "multiplicity": int(found["multiplicity"]),
            "period_s": found["period"], "last_stick_s": found["last_stick"]}


def initial_state_basins(chain: dict, x1, v1, *, store=None, workers=None, progress: bool = False):
    """The basin map of a chain over mass 1's initial displacement and velocity.

    Every grid point is one exact run from ``chain``'s initial state with (x1, v1) replaced,
    classified as :func:`motion_class` does, through the sweep machinery (resumable).

    Parameters
    ----------
    chain : dict
        Keyword arguments of :func:`asperity2d.belt.simulate_chain` (a preset's), with ``t_end``.
    x1, v1 : array_like
        The grid: mass 1's initial displacements (m) and velocities (m/s).
    store : str or os.PathLike, optional
        The sweep's results folder: run again with it and only unfinished points are computed.
    workers : int, optional
        Worker processes (None: decided by cost).
    progress : bool, default False
        Show a progress bar.

    Returns
    -------
    object
        A ``BasinMap``: ``x_values``, ``y_values``, ``t_end``, ``failed``; ``values["label"]``
        indexes the classes (``"rest"``, ``"pure slip"``, ``"stick-slip"``, ``"irregular"``; -1 a
        failed run), ``values["multiplicity"]``, ``values["last_stick"]``,
        ``values["stick_fraction"]``, ... per (x1, v1); ``to_dict()`` for the summary.
    """
    return chain_basins(chain, x=("x1", np.asarray(x1, dtype=float)), y=("v1", np.asarray(v1, dtype=float)),
                        store=store, workers=workers, progress=progress)


def recheck_irregular(bm, chain: dict, factor: int, count: int, chaos: int, steps: int, seed: int = 0) -> dict:
    """Run grid points classed irregular again, longer: a long transient, or chaos?

    A long transient (sparse sticks on the way to pure slip) changes class when run longer; a
    sustained irregular motion does not. For the first ``chaos`` of those still irregular, the
    largest Lyapunov exponent (Benettin, ``steps`` x 2 s after a transient of ``t_end``): positive
    for chaos, about 0 (to about 1e-3 1/s over 300 s) for a cycle or a torus.

    Parameters
    ----------
    bm : object
        A ``BasinMap`` of :func:`initial_state_basins`.
    chain : dict
        The chain it was made of.
    factor : int
        How many times longer the re-runs are.
    count : int
        At most this many irregular points are re-run (picked at random with ``seed``).
    chaos : int
        At most this many Lyapunov exponents are computed.
    steps : int
        Benettin steps of 2 s each.
    seed : int, default 0
        The pick's random seed.

    Returns
    -------
    dict
        ``checked`` (how many), ``t_end_s``, ``classes`` (class -> count after the long run) and
        ``lyapunov_of_still_irregular`` (x1, v1 and the exponent in 1/s).
    """
    i, j = np.nonzero(bm.values["label"] == 3)
    if i.size == 0:
        return {"checked": 0}
    pick = np.random.default_rng(seed).choice(i.size, min(count, i.size), replace=False)
    classes, exponents = [], []
    for k in pick:
        kw = with_initial(with_initial(chain, bm.x_name, bm.x_values[i[k]]), bm.y_name, bm.y_values[j[k]])
        longer = dict(kw, t_end=factor * chain["t_end"], n_samples=factor * (chain["n_samples"] - 1) + 1)
        try:
            with cpu_limit(RUN_CPU_LIMIT):
                classes.append(LABELS[int(classify_chain(simulate_chain(**longer))["label"])])
        except SimulationError:
            classes.append("failed")
        if classes[-1] == "irregular" and len(exponents) < chaos:
            s = flow_map(kw, np.concatenate([kw["x0"], kw["v0"]]), chain["t_end"])
            settled = dict(kw, x0=s[:len(s) // 2].tolist(), v0=s[len(s) // 2:].tolist())
            exponents.append({"x1": float(bm.x_values[i[k]]), "v1": float(bm.y_values[j[k]]),
                              "lyapunov_per_s": chain_lyapunov(settled, steps=steps, interval=2.0).value})
    return {"checked": len(classes), "t_end_s": factor * chain["t_end"],
            "classes": {name: classes.count(name) for name in sorted(set(classes))},
            "lyapunov_of_still_irregular": exponents}


def belt_chain_run(*, seed: int = 0, preset_name: str = "table2-3dof", ic_spread: float = 0.0,
                   **overrides) -> dict:
    """Sweep run for a belt chain of the multi-DOF belt thesis: regime and stick-slip measures.

    Parameters
    ----------
    seed : int, default 0
        Seeds the noise of ``ic_spread``.
    preset_name : str, default "table2-3dof"
        A preset of :mod:`asperity2d.belt.presets`.
    ic_spread : float, default 0.0
        If > 0, the initial displacements get seeded uniform noise of this half-width (m): a
        Monte-Carlo over initial conditions.
    **overrides
        Arguments of :func:`asperity2d.belt.simulate_chain` that replace the preset's
        (``v_belt``, ``mu_s``, ...).

    Returns
    -------
    dict
        ``stick_slip`` and ``quasi_harmonic`` (1.0 or 0.0: the run's regime), ``total_stick_s``,
        ``amplitude_m`` (the largest mass's) and ``energy_balance_error``.
    """
    kwargs = presets.preset(preset_name, **overrides)
    if ic_spread > 0:
        rng = np.random.default_rng(seed)
        x0 = np.asarray(kwargs["x0"], dtype=float)
        kwargs["x0"] = list(x0 + rng.uniform(-ic_spread, ic_spread, len(x0)))
    result = simulate_chain(**kwargs)
    label = classify(result)
    return {"stick_slip": float(label == "stick-slip"), "quasi_harmonic": float(label == "quasi-harmonic"),
            "total_stick_s": float(sum(total_stick(result))), "amplitude_m": float(max(amplitude(result))),
            "energy_balance_error": float(result.energy_balance_error())}
