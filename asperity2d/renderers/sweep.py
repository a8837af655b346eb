"""The picture of a sweep's summary (:class:`asperity2d.sweep.Summary`): mean and confidence
band per variant, one panel per quantity (matplotlib through :func:`.plots.figure`, no pyplot)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..errors import SceneError
from ..sweep.study import variant_label
from .plots import FORMATS, figure, save


def _axis(quantity: str, values) -> tuple[str, str, float]:
    """``(plain name, unit label, factor)`` of a quantity's axis: ``critical_force_N`` with values
    of some mN -> ("critical force", "mN", 1e-3); divide the values by ``factor``."""
    from .._format import prefixed, split_unit

    name, unit = split_unit(quantity)
    if unit is None:
        return name, "", 1.0
    if unit == "%":
        return name, "%", 0.01
    finite = np.abs(np.asarray(values, dtype=float))
    finite = finite[np.isfinite(finite)]
    factor, label = prefixed(float(finite.max()) if len(finite) else 1.0, unit)
    return name, label, factor


def plot_summary(summary, path: str | Path) -> Path:
    """Write a figure of mean and confidence band per variant, one panel per quantity.

    When a single numeric grid parameter varies, variants are placed at its
    values and joined by a line; otherwise they are categories on the x axis.
    The format follows the extension of ``path`` (``.png``, ``.pdf``, ``.svg``).
    """
    if Path(path).suffix.lower() not in FORMATS:
        raise SceneError(f"`path` must end in .png, .pdf or .svg, got {str(path)!r}")
    if not summary.quantities:
        raise SceneError("`summary` has no quantities to plot (no run has finished)")
    varying = [k for k, _ in summary.variants[0]
               if len({dict(v)[k] for v in summary.variants}) > 1] if summary.variants[0] else []
    numeric = len(varying) == 1 and all(
        isinstance(dict(v)[varying[0]], (int, float)) and not isinstance(dict(v)[varying[0]], bool)
        for v in summary.variants)
    if numeric:
        xs = np.array([float(dict(v)[varying[0]]) for v in summary.variants])
    else:
        xs = np.arange(len(summary.variants), dtype=float)
    labels = [variant_label((k, val) for k, val in v if k in varying) for v in summary.variants]

    nq = len(summary.quantities)
    fig, axes = figure(nq, width=max(5.0, 1.2 * len(xs) + 2.5), height=2.6 + 0.6 / nq, sharex=True)
    for ax, q in zip(axes, summary.quantities):
        st = [summary.stat(v, q) for v in summary.variants]
        name, unit, factor = _axis(q, [s.mean for s in st])
        mean = np.array([s.mean for s in st]) / factor
        lo = np.array([s.ci_low for s in st]) / factor
        hi = np.array([s.ci_high for s in st]) / factor
        if numeric:
            order = np.argsort(xs)
            ax.fill_between(xs[order], lo[order], hi[order], alpha=0.3,
                            label=f"{summary.confidence:.0%} CI")
            ax.plot(xs[order], mean[order], "o-", label="mean")
        else:
            for i, (x, a, b) in enumerate(zip(xs, lo, hi)):
                ax.fill_between([x - 0.3, x + 0.3], [a, a], [b, b], alpha=0.3, color="C0",
                                label=f"{summary.confidence:.0%} CI" if i == 0 else None)
            ax.plot(xs, mean, "o", color="C0", label="mean")
        ax.set_ylabel(f"{name} ({unit})" if unit else name)
        ax.grid(alpha=0.3)
    axes[0].set_title(f"{summary.study}: mean and {summary.confidence:.0%} CI per variant")
    axes[0].legend(loc="best", fontsize="small")
    if numeric:
        axes[-1].set_xlabel(_axis(varying[0], [])[0])
    else:
        axes[-1].set_xticks(xs, [f"{lab}\n(n={d})" for lab, (d, _) in zip(labels, summary.counts)],
                            rotation=20 if len(xs) > 4 else 0, fontsize="small")
    return save(fig, path, 110)
