"""Compare scene variants over seeds: one measured number per (variant, seed), and statistics.

Seed 000's comparisons (regular against random spacing, full against half
triangles, damped against undamped) as a study::

    comparison = compare(critical_force, {"regular": {"spacing": "regular"},
                                          "random": {"spacing": "random"}}, seeds=range(10))
    comparison.mann_whitney("regular", "random")
    comparison.save("renders/spacing.json")   # re-plot later without re-running

Each scene is ``make_scene(**base, **variant, seed=seed)``; ``measure(scene)``
returns a float (NaN is allowed and ignored by the statistics). Results are
stored in (variant, seed) order, so they do not depend on ``workers``.
"""

from __future__ import annotations

import json
import math
import os
import pickle
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable

import numpy as np

from ._io import FileError, atomic_write_text, read_text
from .errors import SceneError

FORMAT = "asperity2d.comparison/1"


def _evaluate(measure: Callable, kwargs: dict) -> float:
    """Build one scene and measure it (module level, so worker processes can run it)."""
    from .builders import make_scene

    return float(measure(make_scene(**kwargs)))


@dataclass(frozen=True)
class Comparison:
    """Measured values per variant (same seeds for every variant) and their statistics.

    ``values`` maps variant name to one value per seed (in ``seeds`` order);
    ``variants`` holds each variant's ``make_scene`` arguments, ``base`` the
    shared ones, ``measure`` the measure's name. Statistics ignore NaN values.
    """

    values: dict[str, tuple[float, ...]]
    seeds: tuple[int, ...]
    variants: dict[str, dict] = field(default_factory=dict)
    base: dict = field(default_factory=dict)
    measure: str = "value"

    def __post_init__(self):
        for name, vals in self.values.items():
            if len(vals) != len(self.seeds):
                raise SceneError(f"`values` of variant {name!r} has {len(vals)} entries for "
                                 f"{len(self.seeds)} seeds")

    # -- statistics --------------------------------------------------------
    def finite(self, name: str) -> np.ndarray:
        """The variant's finite values."""
        if name not in self.values:
            raise SceneError(f"`name` must be one of {sorted(self.values)}, got {name!r}")
        a = np.asarray(self.values[name], dtype=float)
        return a[np.isfinite(a)]

    def mean(self, name: str) -> float:
        a = self.finite(name)
        return float(a.mean()) if len(a) else math.nan

    def std(self, name: str) -> float:
        """Sample standard deviation (ddof=1); NaN with fewer than two values."""
        a = self.finite(name)
        return float(a.std(ddof=1)) if len(a) > 1 else math.nan

    def ci(self, name: str, *, level: float = 0.95) -> tuple[float, float]:
        """Confidence interval of the mean: mean ± t(1-α/2, n-1) · s / sqrt(n)."""
        from scipy import stats

        if not 0 < level < 1:
            raise SceneError(f"`level` must be in (0, 1), got {level!r}")
        a = self.finite(name)
        if len(a) < 2:
            return (math.nan, math.nan)
        half = stats.t.ppf(0.5 + level / 2.0, len(a) - 1) * a.std(ddof=1) / math.sqrt(len(a))
        return (float(a.mean() - half), float(a.mean() + half))

    def mann_whitney(self, a: str, b: str, *, alternative: str = "two-sided") -> float:
        """p-value of the Mann–Whitney U test between variants ``a`` and ``b``
        (:func:`scipy.stats.mannwhitneyu`, default method: exact for small
        samples without ties)."""
        from scipy import stats

        x, y = self.finite(a), self.finite(b)
        if len(x) == 0 or len(y) == 0:
            return math.nan
        return float(stats.mannwhitneyu(x, y, alternative=alternative).pvalue)

    def one_sample(self, name: str, reference: float, *, test: str = "wilcoxon",
                   alternative: str = "two-sided") -> float:
        """p-value of a test that variant ``name`` is centred on ``reference``.

        ``test="wilcoxon"`` (default): Wilcoxon signed-rank test of the
        differences from ``reference`` (:func:`scipy.stats.wilcoxon`; no
        normality assumption, tests the median). ``test="t"``: one-sample
        t-test of the mean (:func:`scipy.stats.ttest_1samp`).
        """
        from scipy import stats

        a = self.finite(name)
        if test not in ("wilcoxon", "t"):
            raise SceneError(f"`test` must be 'wilcoxon' or 't', got {test!r}")
        if len(a) < 2:
            return math.nan
        if test == "t":
            return float(stats.ttest_1samp(a, reference, alternative=alternative).pvalue)
        d = a - float(reference)
        if not np.any(d):
            return 1.0
        return float(stats.wilcoxon(d, alternative=alternative).pvalue)

    def summary(self, *, level: float = 0.95) -> dict[str, dict[str, float]]:
        """Per variant: n (finite values), mean, std, median, ci_low, ci_high."""
        out = {}
        for name in self.values:
            a = self.finite(name)
            lo, hi = self.ci(name, level=level)
            out[name] = {"n": int(len(a)), "mean": self.mean(name), "std": self.std(name),
                         "median": float(np.median(a)) if len(a) else math.nan,
                         "ci_low": lo, "ci_high": hi}
        return out

    # -- persistence -------------------------------------------------------
    def to_dict(self) -> dict:
        def plain(v):
            return None if not math.isfinite(v) else v

        return {"format": FORMAT, "measure": self.measure, "seeds": list(self.seeds),
                "base": self.base, "variants": self.variants,
                "values": {k: [plain(float(v)) for v in vals] for k, vals in self.values.items()}}

    def save(self, path: str | os.PathLike) -> Path:
        """Write the comparison as JSON (NaN as null), atomically; return the path."""
        try:
            text = json.dumps(self.to_dict(), indent=1, allow_nan=False)
        except (TypeError, ValueError) as exc:
            raise SceneError(f"`variants` / `base` must hold JSON values to be saved ({exc})") from None
        return atomic_write_text(path, text + "\n")

    @classmethod
    def load(cls, path: str | os.PathLike) -> "Comparison":
        """Read a comparison written by :meth:`save`; a file that is not one raises ``SceneError``."""
        path = Path(path)
        text = read_text("path", path)
        try:
            data = json.loads(text)
            if data.get("format") != FORMAT:
                raise ValueError(f"format is {data.get('format')!r}, expected {FORMAT!r}")
            values = {k: tuple(math.nan if v is None else float(v) for v in vals)
                      for k, vals in data["values"].items()}
            return cls(values=values, seeds=tuple(int(s) for s in data["seeds"]),
                       variants=data.get("variants", {}), base=data.get("base", {}),
                       measure=data.get("measure", "value"))
        except (ValueError, KeyError, TypeError, AttributeError) as exc:
            raise FileError("path", path, "is not a comparison file", str(exc)) from None


def compare(measure: Callable, variants: dict[str, dict], seeds: Iterable[int], *,
            base: dict | None = None, progress: bool = True, workers: int = 1) -> Comparison:
    """Measure every variant on every seed.

    Parameters
    ----------
    measure : callable
        ``measure(scene) -> float``, e.g. a critical-force or breakaway
        function. Must be picklable (a module-level function) when
        ``workers > 1``.
    variants : dict of str to dict
        Name -> ``make_scene`` keyword arguments (without ``seed``).
    seeds : iterable of int
        Seeds run for every variant (passed as ``seed=``).
    base : dict, optional
        ``make_scene`` arguments shared by all variants (a variant overrides them).
    progress : bool
        Show a tqdm progress bar.
    workers : int
        Processes (``concurrent.futures.ProcessPoolExecutor``); 1 runs in this
        process. The values do not depend on it.
    """
    from tqdm.auto import tqdm

    if not callable(measure):
        raise SceneError(f"`measure` must be callable, got {measure!r}")
    if not isinstance(variants, dict) or not variants:
        raise SceneError("`variants` must be a non-empty dict of name -> make_scene arguments")
    base = dict(base or {})
    seeds = tuple(seeds)
    if not seeds or not all(isinstance(s, (int, np.integer)) and s >= 0 for s in seeds):
        raise SceneError(f"`seeds` must be non-negative integers, got {seeds!r}")
    seeds = tuple(int(s) for s in seeds)
    if "seed" in base or any("seed" in (kw or {}) for kw in variants.values()):
        raise SceneError("`variants` and `base` must not set `seed` (it comes from `seeds`)")
    if isinstance(workers, bool) or not isinstance(workers, int) or workers < 1:
        raise SceneError(f"`workers` must be an integer >= 1, got {workers!r}")
    tasks = [(name, {**base, **(kw or {}), "seed": s}) for name, kw in variants.items() for s in seeds]
    from .builders import make_scene

    for _, kwargs in tasks[:: len(seeds)]:
        make_scene(**kwargs)  # bad arguments fail here, before any run starts
    if workers > 1:
        try:
            pickle.dumps(measure)
        except Exception as exc:
            raise SceneError(f"`measure` must be picklable (a module-level function) when "
                             f"workers > 1 ({exc})") from None
    bar = tqdm(total=len(tasks), disable=not progress, unit="run", leave=False)
    results = []
    try:
        if workers == 1:
            for _, kwargs in tasks:
                results.append(_evaluate(measure, kwargs))
                bar.update(1)
        else:
            with ProcessPoolExecutor(max_workers=workers) as pool:
                futures = [pool.submit(_evaluate, measure, kwargs) for _, kwargs in tasks]
                for fut in futures:  # in task order: identical to the serial result
                    results.append(fut.result())
                    bar.update(1)
    except Exception as exc:
        name, kwargs = tasks[len(results)]
        exc.add_note(f"while measuring variant {name!r} with seed {kwargs['seed']}")
        raise
    finally:
        bar.close()
    values = {name: tuple(results[i * len(seeds):(i + 1) * len(seeds)])
              for i, name in enumerate(variants)}
    return Comparison(values=values, seeds=seeds,
                      variants={k: dict(v or {}) for k, v in variants.items()}, base=base,
                      measure=getattr(measure, "__name__", type(measure).__name__))
