"""Compare scene variants over seeds: one measured number per (variant, seed), and statistics.

Ooten's comparisons (regular against random spacing, full against half
triangles, damped against undamped) as a study::

    comparison = compare("critical", {"regular": {"spacing": "regular"},
                                      "random": {"spacing": "random"}}, seeds=range(10))
    comparison.versus("random", "regular")      # effect and one-sample Wilcoxon test
    comparison.save("renders/spacing.json")     # re-plot later without re-running

Each scene is ``make_scene(**base, **variant, seed=seed)``; ``measure(scene)``
returns a float (NaN is allowed and ignored by the statistics). ``measure`` is
a callable or the name of one of the named measures
(:data:`asperity2d.experiments.measures.MEASURES`). The runs go through the
ensemble engine (:func:`asperity2d.sweep.engine.run_calls`: in-process, a
local process pool, or a Dask cluster, one failure contract), like
:func:`asperity2d.sweep.run_study`; a run that raises raises here, with a note
naming its variant and seed. A variant whose
scene does not depend on the seed (regular spacing) is measured once and
reported for every seed. Results are stored in (variant, seed) order; they
do not depend on the executor.

``seeds="auto"`` adds seeds in stages until every variant's verdict against the reference is
decided or ``max_seeds`` are spent, under a group-sequential design that keeps each claim's
false-positive rate at the rule's alpha (:mod:`asperity2d.experiments.sequential`).
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import pickle
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from .. import stats
from .._format import si
from .._io import FileError, read_text, write_json
from .._inputs import check_int, count_seeds, show
from ..builders import make_scene
from ..errors import SceneError
from ..scene import Scene
from ..sweep.engine import is_auto, run_calls
from ..sweep.executors import check_executor_args, make_executor
from ..sweep.progress import Progress
from .measures import BATCHED, MEASURES, Measure, find_measure, measure_label, measure_unit  # noqa: F401
from .sequential import MAX_SEEDS, SPENDING, STAGE_SEEDS, Design, plan, run_in_stages
from .verdicts import DECIDED, UNDECIDED, VerdictRule, verdict_line
from .verdicts import claim as claims_record

FORMAT = "asperity2d.comparison/1"


def _evaluate(measure: Callable, scene: Scene, where: str) -> float:
    """Measure one scene (module level, so worker processes can run it); ``where`` names it
    in the note of a failure."""
    return float(measure(scene))


# -- the result -----------------------------------------------------------------------------------
@dataclass(frozen=True)
class Comparison:
    """Measured values per variant (same seeds for every variant) and their statistics.

    ``values`` maps variant name to one value per seed (in ``seeds`` order);
    ``variants`` holds each variant's ``make_scene`` arguments, ``base`` the
    shared ones, ``measure`` the measure's name. Statistics (:mod:`asperity2d.stats`)
    ignore NaN values.

    Parameters
    ----------
    values : dict of str to tuple of float
        Variant name -> one measured value per seed (the measure's unit, N for forces).
    seeds : tuple of int
        The seeds, in the order of ``values``.
    variants : dict of str to dict, optional
        Each variant's ``make_scene`` arguments.
    base : dict, optional
        The arguments shared by every variant.
    measure : str, default "value"
        The measure's name.
    design : dict, optional
        A comparison run in stages (``compare(..., seeds="auto")``): the sequential design
        (``stages`` planned, ``alpha``, ``spending``, ``reference``) and ``looks``, one entry per
        stage run: its number, the seeds it took and each variant's verdict after it. Empty for a
        comparison of fixed seeds.
    engine : str, default "pymunk"
        The engine that ran the scenes (``asperity2d.engine.ENGINES``).

    Raises
    ------
    SceneError
        A variant with a number of values other than the number of seeds.

    See Also
    --------
    asperity2d.compare : makes one by running the scenes.
    asperity2d.stats.relative_effect : the Hodges-Lehmann ratio and its interval.

    Examples
    --------
    >>> from asperity2d import Comparison
    >>> c = Comparison(values={"regular": (7.6e-3,) * 4, "random": (3.8e-3, 6.9e-3, 3.8e-3, 5.1e-3)},
    ...                seeds=(0, 1, 2, 3), measure="critical")
    >>> test = c.versus("random", "regular", alternative="less")
    >>> test["below"], test["p_wilcoxon"]  # four seeds: p cannot go below 1/2**4
    (4, 0.0625)
    >>> path = c.save("critical.json")
    >>> Comparison.load(path) == c
    True
    >>> import asperity2d as a
    >>> a.render(c, "critical.png").name  # values per variant, in the measure's unit (mN)
    'critical.png'
    """

    #: The result family :func:`asperity2d.render` draws it as (a plot of values per variant).
    kind = "comparison"

    values: dict[str, tuple[float, ...]]
    seeds: tuple[int, ...]
    variants: dict[str, dict] = field(default_factory=dict)
    base: dict = field(default_factory=dict)
    measure: str = "value"
    design: dict = field(default_factory=dict)
    #: The measure's label and unit when it was measured (kept in the saved file, so a comparison
    #: of a measure this session has not registered still reads in its words and unit).
    saved_label: str | None = field(default=None, compare=False, repr=False)
    saved_unit: str | None = field(default=None, compare=False, repr=False)
    engine: str = "pymunk"

    def __post_init__(self):
        for name, vals in self.values.items():
            if len(vals) != len(self.seeds):
                raise SceneError(f"`values` of variant {name!r} has {len(vals)} entries for "
                                 f"{len(self.seeds)} seeds")

    def _get(self, name: str) -> np.ndarray:
        if name not in self.values:
            raise SceneError(f"`name` must be one of {sorted(self.values)}, got {show(name)}")
        return np.asarray(self.values[name], dtype=float)

    def _repr_html_(self) -> str:
        """A table of each variant's statistics and the plot (Jupyter shows it)."""
        from .._display import represent

        return represent(self, "html")

    def finite(self, name: str) -> np.ndarray:
        """The variant's finite values."""
        return stats.finite(self._get(name))

    def summary(self, *, level: float = 0.95) -> dict[str, dict]:
        """Per variant: :func:`asperity2d.stats.describe` (n, missing, mean, std, median, CI)."""
        return {name: stats.describe(self._get(name), level=level) for name in self.values}

    def mann_whitney(self, a: str, b: str, *, alternative: str = "two-sided") -> float:
        """p-value of the Mann–Whitney U test between variants ``a`` and ``b``."""
        return stats.mann_whitney(self._get(a), self._get(b), alternative=alternative)

    def versus(self, name: str, reference: str, *, alternative: str = "less", alpha: float = 0.01) -> dict:
        """Variant ``name`` against variant ``reference``.

        A reference measured once (seed-independent, e.g. regular spacing) is a
        value: one-sample Wilcoxon of ``name`` against it
        (:func:`asperity2d.stats.versus_reference`). Otherwise the seeds pair
        up: paired Wilcoxon of ``name - reference`` (same seed, same draws),
        reported in the same fields. Either way with :func:`asperity2d.stats.equivalence`
        at ``alpha`` (the ratio's ``1 - 2 alpha`` interval, the per-seed spread).
        """
        ref = self._get(reference)
        if np.all(ref == ref[0]):
            return {**stats.versus_reference(self._get(name), float(ref[0]), alternative=alternative, alpha=alpha),
                    "test": "one-sample Wilcoxon signed-rank against the reference value"}
        out = stats.versus_reference(stats.difference(self._get(name), ref), 0.0, alternative=alternative)
        mine, theirs = stats.describe(self._get(name)), stats.describe(ref)
        out.update(mean=mine["mean"], std=mine["std"], reference=theirs["mean"],
                   relative_difference=(mine["mean"] - theirs["mean"]) / theirs["mean"],
                   test="paired Wilcoxon signed-rank (same seeds)")
        out.update(stats.equivalence(self._get(name), ref, alpha=alpha))
        return out

    # -- what it means, in words -------------------------------------------
    @property
    def entry(self) -> Measure | None:
        """The registered :class:`~asperity2d.experiments.measures.Measure` measured (None for
        a plain callable)."""
        return find_measure(self.measure)

    @property
    def label(self) -> str:
        """The measure's plain-language label (the registered measure's, else the one saved with it)."""
        entry = self.entry
        if entry is not None:
            return entry.label
        return measure_label(self.measure) if self.saved_label is None else self.saved_label

    @property
    def unit(self) -> str:
        """The measure's SI unit (the registered measure's, else the one saved with it; ``""`` for a
        plain callable, whose unit is unknown)."""
        entry = self.entry
        if entry is not None:
            return entry.unit
        return "" if self.saved_unit is None else self.saved_unit

    @property
    def rule(self) -> VerdictRule:
        """The measure's verdict rule (the default one for a plain callable)."""
        entry = self.entry
        return entry.rule if entry is not None else VerdictRule()

    def level(self, rule: VerdictRule | None = None) -> float:
        """The one-sided level this comparison's verdicts test at: the rule's alpha, or for a
        comparison run in stages the nominal level of its last look under its design
        (:class:`~asperity2d.experiments.sequential.Design`)."""
        rule = self.rule if rule is None else rule
        if not self.design:
            return rule.alpha
        design = self._design(rule)
        look = design.look(len(self.seeds))
        return design.nominal[-1 if look is None else look]

    def _design(self, rule: VerdictRule) -> Design:
        return Design(stages=tuple(self.design["stages"]), alpha=rule.alpha,
                      spending=self.design.get("spending", "pocock"))

    def verdict(self, name: str, reference: str, *, subject: str | None = None, setup: str | None = None,
                rule: VerdictRule | None = None) -> dict:
        """The claim "``subject`` lowers (raises) the <measure>" judged by the measure's rule.

        Returns a claim record (:func:`asperity2d.experiments.verdicts.claim`): ``claim`` (the
        sentence), ``verdict`` ("holds", "no effect", "does not hold" -- shown the other way --,
        "undecided" or "not testable with so few seeds"), ``numbers`` (:meth:`versus` in the
        rule's direction; the Hodges-Lehmann ratio ``ratio_hl`` with its 95 % interval
        ``ratio_ci_low``/``ratio_ci_high``; the ``margin``; ``seeds_needed`` when undecided;
        ``stages``, the seeds each stage took, for a comparison run in stages), ``test`` (the
        test and the criterion in words) and ``setup`` when given. ``subject`` defaults to the
        variant's name; :func:`~asperity2d.experiments.verdicts.verdict_line` prints it. A
        comparison run in stages is judged at its last look's nominal level (:meth:`level`).
        """
        rule = self.rule if rule is None else rule
        alpha = self.level(rule)
        numbers = self.versus(name, reference, alternative=rule.direction, alpha=alpha)
        ref = self._get(reference)
        effect = stats.relative_effect(self.values[name], float(ref[0]) if np.all(ref == ref[0]) else ref)
        numbers.update(ratio_hl=effect["ratio"], ratio_ci_low=1 + effect["ci_low"],
                       ratio_ci_high=1 + effect["ci_high"], margin=rule.min_effect)
        outcome = rule.judge(numbers, alpha=alpha)
        if outcome == UNDECIDED:
            numbers["seeds_needed"] = rule.seeds_needed(numbers, alpha=rule.alpha)
        test = rule.describe(numbers["test"])
        if self.design:
            numbers["stages"] = [{"stage": look["stage"], "seeds": look["seeds"]}
                                 for look in self.design.get("looks", [])]
            test += f"; seeds added in stages ({self._design(rule).describe()}), judged at the nominal level {alpha:.2g}"
        return claims_record(f"{subject or name} {rule.verb} the {self.label}", outcome, numbers, test, setup=setup)

    def report(self, reference: str | None = None, *, subject: str = "{name}") -> tuple[dict, list[str]]:
        """The comparison in numbers and in words: ``(summary, lines)``.

        ``summary`` holds the measure, the seed count, each variant's statistics, the
        Mann-Whitney p of the first variant against each other one and, when ``reference``
        is a variant, the claim records (:meth:`verdict`) of every other variant against it
        (``subject`` formats each claim's subject from the variant's ``name``). ``lines`` say
        the same with units: the text ``asperity2d compare`` prints.
        """
        unit = self.unit
        described = self.summary()
        summary = {"measure": self.measure, "seeds": len(self.seeds), "variants": described}
        if self.design:  # seeds added in stages: the design and the seeds each stage took
            summary["design"] = self.design
        names = list(self.values)
        if len(names) >= 2:
            summary["mann_whitney_p"] = {f"{names[0]} vs {other}": self.mann_whitney(names[0], other)
                                         for other in names[1:]}
        staged = ""
        if self.design:
            looks = self.design.get("looks", [])
            staged = f" in {len(looks)} stage{'s' * (len(looks) != 1)} (of up to {self.design['stages'][-1]})"
        lines = [f"{self.label}, {len(self.seeds)} seeds{staged}:"]
        lines += [f"  {name}: mean {si(s['mean'], unit, 4)}, 95 % CI [{si(s['ci_low'], unit, 4)}, "
                  f"{si(s['ci_high'], unit, 4)}] (n = {s['n']})" for name, s in described.items()]
        lines += [f"Mann-Whitney U {pair}: p = {p:.3g}" for pair, p in summary.get("mann_whitney_p", {}).items()]
        if reference is not None and reference in names:
            summary["claims"] = [self.verdict(other, reference, subject=subject.format(name=other))
                                 for other in names if other != reference]
            lines += [verdict_line(record) for record in summary["claims"]]
        return summary, lines

    # -- persistence -------------------------------------------------------
    def to_dict(self) -> dict:
        return {"format": FORMAT, "measure": self.measure, "label": self.label, "unit": self.unit,
                "seeds": list(self.seeds),
                "base": self.base, "variants": self.variants,
                "values": {k: [float(v) for v in vals] for k, vals in self.values.items()},
                "engine": self.engine, **({"design": self.design} if self.design else {})}

    def save(self, path: str | os.PathLike) -> Path:
        """Write the comparison as strict JSON (NaN as null, ``write_json``),
        atomically; return the path."""
        try:  # the scene arguments must come back as they went in (no object turned into text)
            json.dumps({"base": self.base, "variants": self.variants})
        except (TypeError, ValueError) as exc:
            raise SceneError(f"`variants` / `base` must hold JSON values to be saved ({exc})") from None
        return write_json(path, self.to_dict(), indent=1)

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Comparison":
        """Read a comparison written by :meth:`save`; a file that is not one raises ``SceneError``."""
        path = Path(path)
        text = read_text("path", path)
        try:
            data = json.loads(text)
            if not isinstance(data, dict) or data.get("format") != FORMAT:
                raise ValueError(f"format is {data.get('format') if isinstance(data, dict) else None!r}, "
                                 f"expected {FORMAT!r}")
            values = {k: tuple(math.nan if v is None else float(v) for v in vals)
                      for k, vals in data["values"].items()}
            return cls(values=values, seeds=tuple(int(s) for s in data["seeds"]),
                       variants=data.get("variants", {}), base=data.get("base", {}),
                       measure=data.get("measure", "value"), design=data.get("design") or {},
                       saved_label=_text_or_none(data.get("label")), saved_unit=_text_or_none(data.get("unit")),
                       engine=data.get("engine", "pymunk"))
        except (ValueError, KeyError, TypeError, AttributeError) as exc:
            raise FileError("path", path, "is not a comparison file", str(exc)) from None


def _text_or_none(value) -> str | None:
    """A saved label or unit (a short string), or None when the file has none."""
    if value is None:
        return None
    if not isinstance(value, str) or len(value) > 1000:
        raise ValueError(f"a measure's label and unit must be short strings, got {type(value).__name__}")
    return value


# -- running it -------------------------------------------------------------------------------------
def _measure(measure: Callable, variants: dict, base: dict, seeds: tuple, where: dict, *, progress: bool,
             label: str, unseeded: dict, batched: Callable | None = None,
             engine: str = "pymunk") -> dict[str, list]:
    """Measure every variant on ``seeds``: name -> values. A variant whose scene does not
    depend on the seed is measured once (``unseeded`` holds its value from an earlier stage).
    ``batched``: the measure's batched form (:data:`~asperity2d.experiments.measures.BATCHED`),
    run on every scene at once in this process on ``engine``."""
    # Build every scene first: bad arguments fail here, before any run starts.
    jobs, slots = [], {}
    for name, kw in variants.items():
        scenes = [make_scene(**{**base, **(kw or {})}, seed=s) for s in seeds]  # a variant overrides base
        same = all(sc.replace(name="") == scenes[0].replace(name="") for sc in scenes)
        for j, (seed, scene) in enumerate(zip(seeds, scenes)):
            if name in unseeded or (same and j):
                slots[name, j] = None if name in unseeded else slots[name, 0]  # the scene does not depend on the seed
                continue
            slots[name, j] = len(jobs)
            jobs.append((measure, scene, f"variant {name!r} with seed {seed}"))
    if batched is not None:  # every scene in one batch, in this process
        results = list(batched([scene for _, scene, _ in jobs], engine)) if jobs else []
        return {name: [unseeded[name] if slots[name, j] is None else results[slots[name, j]]
                       for j in range(len(seeds))] for name in variants}
    results: list = [None] * len(jobs)
    failed = None  # the first failing run in (variant, seed) order, whichever finished first
    with Progress(total=len(jobs), enabled=progress, label=label) as bar:
        for outcome in run_calls(_evaluate, jobs, **where):
            if not outcome.ok:
                if failed is None or outcome.index < failed.index:
                    failed = outcome
                bar.update("failed")
                continue
            results[outcome.index] = outcome.value
            bar.update("done" if math.isfinite(outcome.value) else "failed")
    if failed is not None:  # the run's own exception, on every executor (the engine's contract)
        failed.raise_failure(jobs[failed.index][2])
    return {name: [unseeded[name] if slots[name, j] is None else results[slots[name, j]] for j in range(len(seeds))]
            for name in variants}


def compare(measure: Callable | str, variants: dict[str, dict], seeds: Iterable[int] | str, *,
            base: dict | None = None, progress: bool = True, workers: int | str | None = None,
            scheduler: str | None = None, max_seeds: int | None = None, reference: str | None = None,
            spending: str = "pocock", stage_seeds: int = STAGE_SEEDS, engine: str | None = None) -> Comparison:
    """Measure every variant on every seed, or on seeds added in stages until decided.

    Parameters
    ----------
    measure : callable or str
        ``measure(scene) -> float``, or a name from :data:`~asperity2d.experiments.measures.MEASURES`
        (``"critical"``, ``"peak-stick"``, ...). A callable must be picklable
        (a module-level function) to run in worker processes.
    variants : dict of str to dict
        Name -> ``make_scene`` keyword arguments (without ``seed``).
    seeds : iterable of int, or "auto"
        Seeds run for every variant (passed as ``seed=``); ``"auto"``: seeds 0, 1, 2, ... in
        stages of ``stage_seeds`` until every variant's verdict against ``reference`` (by the
        measure's rule) is decided -- holds, no effect, or shown the other way -- or
        ``max_seeds`` are spent, under a Lan-DeMets alpha-spending design that keeps each
        claim's false-positive rate at the rule's alpha despite the repeated looks
        (:mod:`asperity2d.experiments.sequential`). The comparison records the design and the
        seeds each stage took (``Comparison.design``).
    base : dict, optional
        ``make_scene`` arguments shared by all variants (a variant overrides them).
    progress : bool
        Show a progress bar (one per stage with ``seeds="auto"``: "stage 2: seeds 11-20").
    workers, scheduler
        As for :func:`asperity2d.sweep.run_study`: ``workers`` local processes
        (1: in this process; default None or ``"auto"``: decided by what the first
        run costs, ``decide_workers`` -- serial for a
        small comparison, every core for a large one; always this process for a
        measure that cannot be pickled), or a Dask ``scheduler`` address (``"local"``
        starts one). The values do not depend on them.
    max_seeds : int, optional
        The seed budget of ``seeds="auto"`` (default 40: four stages of 10).
    reference : str, optional
        The variant the others are judged against with ``seeds="auto"`` (default "regular"
        when there is one, else the first variant).
    spending : {"pocock", "obrien-fleming"}
        The alpha-spending function of ``seeds="auto"``: Pocock-type (decides clear effects at
        the first stage) or O'Brien-Fleming-type (keeps nearly all of alpha for the last look).
    stage_seeds : int
        Seeds per stage of ``seeds="auto"`` (default 10: the fewest with which the exact
        signed-rank test can reach the first look's level at alpha 0.01).
    engine : str, optional
        The engine that runs the scenes (``asperity2d.engine.ENGINES``). ``"batched"``
        (the ``[batch]`` extra) runs every scene of the comparison in one batch, in this
        process, for the measures it implements (``"peak-stick"``, ``"mean-stick"``); the
        comparison records the engine. ``"auto"``: ``"batched"`` where Numba is installed and
        it runs the measure and every variant's scene
        (``asperity2d.engine.registry.choose_engine``), else ``"pymunk"``. Default: ``"auto"``
        with ``seeds="auto"`` (an ensemble of up to ``max_seeds``), ``"pymunk"`` with seeds given.

    Returns
    -------
    Comparison
        One value per (variant, seed), with the statistics and tests on it.

    Raises
    ------
    SceneError
        An unknown measure, empty or malformed ``variants``, no seeds, or a scene
        argument that :func:`~asperity2d.make_scene` refuses (named).

    See Also
    --------
    asperity2d.Comparison.verdict : the verdict of a variant against a reference, in words.
    asperity2d.stats.relative_effect : the Hodges-Lehmann ratio and its interval.
    asperity2d.sweep.run_study : larger grids, resumable, on a cluster.

    Examples
    --------
    Does random spacing lower the critical force? Three seeds on a small scene:

    >>> import asperity2d as a
    >>> c = a.compare("critical", {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}},
    ...               range(3), base={"lower_count": 4, "upper_count": 2}, progress=False, workers=1)
    >>> [f"{f * 1e3:.3g}" for f in c.values["random"]], f"{c.values['regular'][0] * 1e3:.3g} mN"
    (['3.8', '6.95', '3.85'], '7.61 mN')
    >>> c.versus("random", "regular", alternative="less")["p_wilcoxon"]
    0.125

    All three seeds are below, yet p = 1/2**3: with 3 seeds a one-sided signed-rank test
    cannot reach p < 0.01 (7 seeds can), so the verdict is "not testable", not "holds".
    ``seeds="auto"`` adds seeds until the verdict is decided:

    >>> c = a.compare("critical", {"regular": {"spacing": "regular"}, "random": {"spacing": "random"}},
    ...               "auto", max_seeds=20, base={"lower_count": 4, "upper_count": 2}, progress=False,
    ...               workers=1)
    >>> len(c.seeds), c.verdict("random", "regular")["verdict"]
    (10, 'holds')
    """
    from ..engine.registry import AUTO, DEFAULT, check_engine, choose_engine

    if engine is None:
        engine = AUTO if isinstance(seeds, str) and seeds == "auto" else DEFAULT
    runs_batched = isinstance(measure, str) and measure in BATCHED  # the measures with a batched form
    if engine != AUTO:
        engine = check_engine(engine)
        if engine != DEFAULT and not runs_batched:
            raise SceneError(f"`measure` {show(measure if isinstance(measure, str) else getattr(measure, '__name__', measure))} "
                             f"is not available on engine={engine!r} (it runs {', '.join(map(repr, BATCHED))}); "
                             "engine=\"pymunk\" runs it")
    batched_form = BATCHED[measure] if runs_batched else None
    if isinstance(measure, str):
        entry = MEASURES.lookup(measure, "measure")  # a registered name or "module:name"
        measure, described = entry.function, {"saved_label": entry.label, "saved_unit": entry.unit}
    else:
        described = {}
    if not callable(measure):
        raise SceneError(f"`measure` must be callable, got {show(measure)}")
    if not isinstance(variants, dict) or not variants:
        raise SceneError("`variants` must be a non-empty dict of name -> make_scene arguments")
    if not all(isinstance(kw, dict) or kw is None for kw in variants.values()):
        raise SceneError("`variants` must map each name to a dict of make_scene arguments")
    base = dict(base or {})
    auto = isinstance(seeds, str)
    if auto:
        if seeds != "auto":
            raise SceneError(f"`seeds` must be seeds (integers) or 'auto', got {show(seeds)}")
        design = Design(stages=plan(MAX_SEEDS if max_seeds is None else max_seeds, stage_seeds),
                        alpha=(find_measure(getattr(measure, "__name__", "")) or _Plain).rule.alpha,
                        spending=spending)
        reference = _reference(variants, reference)
        seeds = tuple(range(design.stages[-1]))
    else:
        if max_seeds is not None:
            raise SceneError("`max_seeds` is the budget of `seeds='auto'`; give it with seeds='auto'")
        count_seeds("seeds", seeds)  # before a tuple of 10**20 seeds is attempted
        seeds = tuple(seeds)
        if not seeds:
            raise SceneError("`seeds` must not be empty")
        seeds = tuple(check_int("seeds", s, minimum=0, maximum=2**63 - 1) for s in seeds)
    if "seed" in base or any("seed" in (kw or {}) for kw in variants.values()):
        raise SceneError("`variants` and `base` must not set `seed` (it comes from `seeds`)")
    if engine == AUTO:  # what a scene is does not depend on its seed: the first seed's scenes decide
        engine = choose_engine(AUTO, [make_scene(**{**base, **(kw or {})}, seed=seeds[0]) for kw in variants.values()]) \
            if runs_batched else DEFAULT
    batched = batched_form if engine != DEFAULT else None
    workers = None if is_auto(workers) else check_int("workers", workers, minimum=1, maximum=1024)
    check_executor_args(workers=workers, scheduler=scheduler)  # before the progress bar is drawn
    if workers != 1 or scheduler is not None:
        try:
            pickle.dumps(measure)
        except Exception as exc:
            if workers is None and scheduler is None:
                workers = 1  # auto: a measure that cannot travel to a worker runs here
            else:
                raise SceneError(f"`measure` must be picklable (a module-level function) to run in "
                                 f"worker processes ({exc})") from None
    name = getattr(measure, "__name__", type(measure).__name__)
    kwargs = {k: dict(v or {}) for k, v in variants.items()}
    # a cluster at an address is reached before the progress bar is drawn: one that cannot be
    # reached is then one line, not a progress line and an error
    cluster = make_executor(scheduler=scheduler) if scheduler not in (None, "local") else None
    where = {"executor": cluster} if cluster is not None else {"workers": workers, "scheduler": scheduler}
    with contextlib.ExitStack() as stack:
        if cluster is not None:
            stack.callback(cluster.close)
        if not auto:
            values = _measure(measure, variants, base, seeds, where, progress=progress, label="compare",
                              unseeded={}, batched=batched, engine=engine)
            return Comparison(values={k: tuple(v) for k, v in values.items()}, seeds=seeds, variants=kwargs,
                              base=base, measure=name, engine=engine, **described)
        return _in_stages(measure, variants, base, design, reference, where, progress=progress,
                          kwargs=kwargs, name=name, described=described, batched=batched, engine=engine)


class _Plain:
    """The rule of a measure that is not registered (a plain callable)."""

    rule = VerdictRule()


def _reference(variants: dict, reference: str | None) -> str:
    if reference is None:
        return "regular" if "regular" in variants else next(iter(variants))
    if reference not in variants:
        raise SceneError(f"`reference` must be one of {sorted(variants)}, got {show(reference)}")
    if len(variants) < 2:
        raise SceneError("`seeds='auto'` needs a variant to judge against `reference`: give two or more")
    return reference


def _in_stages(measure, variants: dict, base: dict, design: Design, reference: str, where: dict, *,
               progress: bool, kwargs: dict, name: str, described: dict, batched: Callable | None,
               engine: str) -> Comparison:
    """``compare(..., seeds="auto")``: stage after stage until every verdict is decided."""
    if len(variants) < 2:
        raise SceneError("`seeds='auto'` needs a variant to judge against `reference`: give two or more")
    values: dict[str, list] = {k: [] for k in variants}
    unseeded: dict[str, float] = {}
    looks: list[dict] = []
    state = {"comparison": None}

    def measure_stage(k: int, first: int, last: int) -> None:
        stage_seeds = tuple(range(first, last))
        got = _measure(measure, variants, base, stage_seeds, where, progress=progress,
                       label=f"compare, stage {k + 1}: seeds {first + 1}-{last}", unseeded=unseeded,
                       batched=batched, engine=engine)
        for variant, vals in got.items():
            if k == 0 and len(set(vals)) == 1 and _unseeded(variants[variant], base, stage_seeds):
                unseeded[variant] = vals[0]
            values[variant].extend(vals)

    def decide(k: int, nominal: float) -> bool:
        seeds = tuple(range(design.stages[k]))
        record = {"stages": list(design.stages), "alpha": design.alpha, "spending": design.spending,
                  "reference": reference, "method": design.to_dict()["method"], "looks": looks}
        looks.append({"stage": k + 1, "seeds": list(range(design.stages[k - 1] if k else 0, design.stages[k])),
                      "nominal_alpha": nominal})
        comparison = Comparison(values={v: tuple(x) for v, x in values.items()}, seeds=seeds, variants=kwargs,
                                base=base, measure=name, design=record, engine=engine, **described)
        outcomes = {other: comparison.verdict(other, reference)["verdict"] for other in variants if other != reference}
        looks[-1]["verdicts"] = outcomes
        state["comparison"] = comparison
        return all(v in DECIDED for v in outcomes.values())

    run_in_stages(design, measure_stage, decide)
    return state["comparison"]


def _unseeded(kw: dict | None, base: dict, seeds: tuple) -> bool:
    """Whether a variant's scene is the same for every seed (then later stages reuse its value)."""
    scenes = [make_scene(**{**base, **(kw or {})}, seed=s) for s in seeds[:2]]
    return len(scenes) < 2 or scenes[0].replace(name="") == scenes[1].replace(name="")
