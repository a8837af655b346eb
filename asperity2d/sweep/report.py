"""Summaries of a finished (or partly finished) study: statistics, tests, a figure.

For every grid point (*variant*) and quantity: the number of finite values,
mean, sample standard deviation and the two-sided t confidence interval of the
mean (:func:`asperity2d.stats.describe`).

Comparisons: for every grid parameter with exactly two values (regular vs
random spacing, full vs half profile, ...), each pair of variants that differ
only in that parameter is compared with the two-sided Mann–Whitney U test
(:func:`asperity2d.stats.mann_whitney`). No multiple-comparison correction is applied.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import stats
from ..errors import SceneError
from .store import ResultStore, quantity_names
from .study import variant_label

Variant = tuple[tuple[str, Any], ...]


@dataclass(frozen=True)
class VariantStats:
    """Statistics of one quantity over the done runs of one grid point.

    See Also
    --------
    asperity2d.sweep.summarize

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> stats = sweep.summarize('spacing').stats[0]
    >>> stats.variant, stats.n, f'{stats.mean * 1e3:.3g} mN'
    ((('spacing', 'regular'),), 1, '7.61 mN')
    """

    variant: Variant
    quantity: str
    n: int
    mean: float
    std: float
    ci_low: float
    ci_high: float


@dataclass(frozen=True)
class VariantTest:
    """Mann–Whitney U test of one quantity between two variants differing in ``parameter``.

    See Also
    --------
    asperity2d.sweep.summarize

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> test = sweep.summarize('spacing').comparisons[0]
    >>> test.parameter, test.n_a, test.n_b
    ('spacing', 1, 1)
    """

    parameter: str
    variant_a: Variant
    variant_b: Variant
    quantity: str
    n_a: int
    n_b: int
    p_value: float


@dataclass(frozen=True)
class Summary:
    """Statistics of a study; ``counts`` maps each variant to (done, failed).

    See Also
    --------
    asperity2d.sweep.summarize : makes one.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> summary = sweep.summarize('spacing')
    >>> summary.quantities, summary.counts
    (('critical_force_N',), ((1, 0), (1, 0)))
    """

    study: str
    confidence: float
    quantities: tuple[str, ...]
    variants: tuple[Variant, ...]
    counts: tuple[tuple[int, int], ...]
    stats: tuple[VariantStats, ...]
    comparisons: tuple[VariantTest, ...]

    def stat(self, variant: Variant | dict, quantity: str) -> VariantStats:
        """The :class:`VariantStats` of ``quantity`` at ``variant``."""
        variant = tuple(variant.items()) if isinstance(variant, dict) else tuple(variant)
        for s in self.stats:
            if s.variant == variant and s.quantity == quantity:
                return s
        raise SceneError(f"`variant` {variant!r} / `quantity` {quantity!r} not in the summary")

    def to_dict(self) -> dict[str, Any]:
        """JSON-able dict; NaN becomes None."""
        def num(x):
            return None if isinstance(x, float) and not math.isfinite(x) else x

        variants = []
        for variant, (done, failed) in zip(self.variants, self.counts):
            entry = {"params": dict(variant), "label": variant_label(variant),
                     "done": done, "failed": failed, "quantities": {}}
            for s in self.stats:
                if s.variant == variant:
                    entry["quantities"][s.quantity] = {
                        "n": s.n, "mean": num(s.mean), "std": num(s.std),
                        "ci": [num(s.ci_low), num(s.ci_high)],
                    }
            variants.append(entry)
        comparisons = [
            {"parameter": c.parameter, "a": dict(c.variant_a), "b": dict(c.variant_b),
             "quantity": c.quantity, "n_a": c.n_a, "n_b": c.n_b,
             "p_value": num(c.p_value), "test": "mann-whitney-u two-sided"}
            for c in self.comparisons
        ]
        return {"study": self.study, "confidence": self.confidence,
                "quantities": list(self.quantities), "variants": variants,
                "comparisons": comparisons}


def summarize(store: str | Path | ResultStore, *, confidence: float = 0.95) -> Summary:
    """Per-variant statistics and Mann–Whitney comparisons of a store's study.

    Parameters
    ----------
    store : str, pathlib.Path or ResultStore
        The study's results directory.
    confidence : float, default 0.95
        Level of the intervals.

    Returns
    -------
    Summary

    See Also
    --------
    asperity2d.sweep.run_study : fills the store.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> session = sweep.run_study(study, store='spacing', workers=1, progress=False)
    >>> summary = sweep.summarize('spacing')
    >>> [f'{s.mean * 1e3:.3g} mN' for s in summary.stats]
    ['7.61 mN', '3.8 mN']
    """
    if not (isinstance(confidence, float) and 0.0 < confidence < 1.0):
        raise SceneError(f"`confidence` must be a float in (0, 1), got {confidence!r}")
    store = store if isinstance(store, ResultStore) else ResultStore(store)
    study = store.study()
    records = store.records(study)
    names = tuple(quantity_names(study, records.values()))
    by_variant: dict[Variant, list] = {v: [] for v in study.variants()}
    for spec in study.runs():
        if spec.key in records:
            by_variant[spec.variant].append(records[spec.key])
    values: dict[tuple[Variant, str], np.ndarray] = {}
    all_stats, counts = [], []
    for variant, recs in by_variant.items():
        done = [r for r in recs if r.status == "done"]
        counts.append((len(done), len(recs) - len(done)))
        for q in names:
            x = np.array([r.quantities.get(q, np.nan) for r in done], dtype=float)
            values[variant, q] = x[np.isfinite(x)]
            d = stats.describe(x, level=confidence)
            all_stats.append(VariantStats(variant, q, d["n"], d["mean"], d["std"], d["ci_low"], d["ci_high"]))
    comparisons = []
    for param, options in study.grid.items():
        if len(options) != 2:
            continue
        for variant in by_variant:
            if dict(variant)[param] != options[0]:
                continue
            other = tuple((k, options[1] if k == param else v) for k, v in variant)
            for q in names:
                a, b = values[variant, q], values[other, q]
                comparisons.append(VariantTest(param, variant, other, q, len(a), len(b),
                                               stats.mann_whitney(a, b)))
    return Summary(study.name, confidence, names, tuple(by_variant), tuple(counts),
                   tuple(all_stats), tuple(comparisons))
