"""Static plots of runs and comparisons (matplotlib, Agg back end, imported lazily).

Every function writes one file (format from the extension: ``.png``, ``.svg``,
``.pdf``) through a temporary file and a rename, and returns its path.
Matplotlib is imported inside the functions so ``import asperity2d`` stays
light and works headless.
"""

from __future__ import annotations

import io
import os
import textwrap
from pathlib import Path

import numpy as np

from .._io import atomic_write
from ..errors import SceneError

FORMATS = (".png", ".svg", ".pdf")


def blank(width: float, height: float):
    """An empty figure ``width`` x ``height`` inches on the Agg canvas (constrained layout), for a
    layout :func:`figure` does not make (e.g. a gridspec with an axis spanning rows)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def figure(rows: int = 1, cols: int = 1, *, width: float = 7.0, height: float = 2.2, sharex: bool = True,
           width_ratios=None):
    """A (figure, axes) pair on the Agg canvas, without pyplot's global state: ``rows`` x
    ``cols`` axes, the figure ``width`` inches wide and ``height`` inches per row. ``axes`` is
    the 1-D array of the rows' axes when ``cols`` is 1, else the ``rows`` x ``cols`` array.
    Every figure of the package (and of the scene scripts) starts here; :func:`save` writes it."""
    fig = blank(width, height * rows)
    axes = fig.subplots(rows, cols, sharex=sharex, squeeze=False,
                        gridspec_kw=None if width_ratios is None else {"width_ratios": width_ratios})
    return fig, (axes[:, 0] if cols == 1 else axes)


def save(fig, path: str | os.PathLike, dpi: int, *, bbox_inches: str | None = None) -> Path:
    """Write ``fig`` to ``path`` atomically (format from the extension, one of FORMATS) and
    return the path; every plot in the package is saved here."""
    path = Path(path)
    fmt = path.suffix.lower()
    if fmt not in FORMATS:
        raise SceneError(f"`path` must end in one of {', '.join(FORMATS)}, got {str(path)!r}")

    import matplotlib

    # the same figure, the same bytes (the output-format contract): no creation date in a PDF or
    # SVG, and SVG element ids from a fixed salt instead of a random one
    metadata = {".pdf": {"CreationDate": None}, ".svg": {"Date": None}}.get(fmt)

    def write(fh):
        buf = io.BytesIO()
        with matplotlib.rc_context({"svg.hashsalt": "asperity2d"}):
            fig.savefig(buf, format=fmt[1:], dpi=dpi, bbox_inches=bbox_inches, metadata=metadata)
        fh.write(buf.getvalue())

    return atomic_write(path, write)


def plot_run(result, path: str | os.PathLike, *, events=None, dpi: int = 120) -> Path:
    """Slider position, velocity and drive / friction force against time.

    ``events``: stick–slip events to mark (slip onsets as red lines, stick
    phases shaded); ``None`` detects them for a spring-driven run with
    :func:`~asperity2d.analysis.stick_slip_events`; ``[]`` marks none.
    Units on the axes: µs, µm, mN; velocity in drive velocities (spring
    drive, symlog scale) or m/s. The force axis is scaled to the drive
    force; the contact force's impact spikes are clipped.
    """
    from ..analysis import stick_slip_events
    from ..scene import SpringDrive

    if events is None:
        events = stick_slip_events(result) if isinstance(result.scene.drive, SpringDrive) else []
    events = list(events)
    t = np.asarray(result.t) * 1e6
    fig, (ax_x, ax_v, ax_f) = figure(3)
    ax_x.plot(t, np.asarray(result.x) * 1e6, color="C0", lw=1, label="slider")
    if np.isfinite(result.drive_x).any():
        ax_x.plot(t, np.asarray(result.drive_x) * 1e6, color="0.6", lw=1, ls="--", label="drive end")
        ax_x.legend(loc="upper left", fontsize=8)
    ax_x.set_ylabel("position (µm)")
    spring = isinstance(result.scene.drive, SpringDrive)
    v_unit = result.scene.drive.velocity if spring else 1.0
    ax_v.plot(t, np.asarray(result.v) / v_unit, color="C1", lw=1)
    ax_v.set_yscale("symlog", linthresh=1.0)  # stick (~0) and slip (>> drive speed) both show
    ax_v.set_ylabel("velocity / drive velocity" if spring else "velocity (m/s)")
    drive = np.asarray(result.drive_force) * 1e3
    ax_f.plot(t, np.asarray(result.friction_force) * 1e3, color="C2", lw=0.8, alpha=0.6,
              label="contact (friction)")
    ax_f.plot(t, drive, color="C3", lw=1.2, label="drive")
    lo, hi = float(np.nanmin(drive)), float(np.nanmax(drive))
    pad = 0.3 * max(hi - lo, abs(hi), 1e-12)
    ax_f.set_ylim(min(lo, 0.0) - pad, hi + pad)  # contact impulses spike far above: clipped
    ax_f.set_ylabel("force (mN)")
    ax_f.set_xlabel("time (µs)")
    ax_f.legend(loc="upper left", fontsize=8)
    for e in events:
        for ax in (ax_x, ax_v, ax_f):
            ax.axvspan(e.t_stick * 1e6, e.t_slip * 1e6, color="C0", alpha=0.07, lw=0)
            ax.axvline(e.t_slip * 1e6, color="red", lw=0.7, alpha=0.8)
        ax_f.plot([e.t_slip * 1e6], [e.force_peak * 1e3], "v", color="red", ms=4)
    ax_x.set_title(f"{result.scene.name or 'run'}: {len(events)} stick–slip events", fontsize=10)
    return save(fig, path, dpi)


def plot_force_displacement(result, path: str | os.PathLike, *, dpi: int = 120) -> Path:
    """Contact (friction) and drive force against slider displacement, and
    friction against velocity (raw samples and the binned mean of
    :func:`~asperity2d.analysis.friction_traces`). The force axes stop at 1.3 x
    the larger of the peak drive force and the 99th percentile of the contact
    force, so single-sample impact spikes are clipped."""
    from ..analysis import friction_traces

    tr = friction_traces(result)
    fig, (ax_d, ax_v) = figure(2, height=2.8, sharex=False)
    ax_d.plot(tr["displacement"] * 1e6, tr["friction_force"] * 1e3, lw=0.8, color="C2",
              label="contact (friction)")
    ax_d.plot(tr["displacement"] * 1e6, tr["drive_force"] * 1e3, lw=0.8, color="C3", label="drive")
    top = max(float(np.nanmax(tr["drive_force"])), float(np.nanpercentile(tr["friction_force"], 99)))
    bottom = min(0.0, float(np.nanmin(tr["drive_force"])),
                 float(np.nanpercentile(tr["friction_force"], 1)))
    if top > bottom:
        pad = 0.3 * (top - bottom)
        for ax in (ax_d, ax_v):  # single-sample impact spikes are clipped
            ax.set_ylim((bottom - pad) * 1e3, (top + pad) * 1e3)
    ax_d.set_xlabel("slider displacement (µm)")
    ax_d.set_ylabel("force (mN)")
    ax_d.legend(loc="upper left", fontsize=8)
    centers = tr["velocity_centers"]
    if len(centers):
        v = tr["velocity"]
        moving = v >= centers[0] / 2.0
        ax_v.plot(v[moving], tr["friction_force"][moving] * 1e3, ".", ms=1.5,
                  color="C2", alpha=0.3, label="samples")
        ax_v.plot(centers, tr["friction_mean"] * 1e3, "-o", ms=3, color="k", label="binned mean")
        ax_v.set_xscale("log")
        ax_v.legend(loc="upper left", fontsize=8)
    ax_v.set_xlabel("slider velocity (m/s)")
    ax_v.set_ylabel("friction force (mN)")
    return save(fig, path, dpi)


#: Units plot_comparison can show values (given in SI) in, with their factors.
UNITS = {"mN": 1e3, "N": 1.0, "µm": 1e6, "": 1.0}
#: The unit a measure's SI unit (its registry entry's) is shown in by default.
SHOWN_IN = {"N": "mN", "m": "µm", "": ""}


def plot_comparison(comparison, path: str | os.PathLike, *, reference: float | None = None,
                    label: str | None = None, unit: str | None = None, dpi: int = 120) -> Path:
    """Strip and box plot of each variant's values, with the mean and its 95 % CI.

    ``comparison`` is a :class:`~asperity2d.experiments.compare.Comparison` of SI values
    (forces in N), shown in ``unit`` (a key of :data:`UNITS`; ``""`` for a
    dimensionless quantity); ``reference`` (SI) draws a horizontal line (e.g.
    the flank-law force); ``label`` names the y axis (default: the measure's
    plain-language name and the unit). ``unit`` defaults to the measure's own unit
    (``Comparison.unit``: mN for a
    force, µm for a length; mN for a measure not registered).
    """
    from .. import stats
    from ..experiments.compare import measure_label

    if unit is None:
        own = getattr(comparison, "unit", "")  # "" for a measure not registered
        unit = SHOWN_IN.get(own, "") if own else "mN"

    names = list(comparison.values)
    if not names:
        raise SceneError("`comparison` has no variants to plot")
    if unit not in UNITS:
        raise SceneError(f"`unit` must be one of {', '.join(map(repr, UNITS))}, got {unit!r}")
    scale = UNITS[unit]
    fig, (ax,) = figure(1, width=max(4.0, 1.3 * len(names) + 2.0), height=3.6)
    data = [comparison.finite(name) * scale for name in names]
    ax.boxplot(data, positions=range(len(names)), widths=0.5, showfliers=False,
               medianprops={"color": "0.3"})
    rng = np.random.default_rng(0)  # jitter only: fixed so the figure is reproducible
    for i, (name, values) in enumerate(zip(names, data)):
        ax.plot(i + rng.uniform(-0.15, 0.15, len(values)), values, "o", ms=3.5, alpha=0.6,
                color=f"C{i % 10}")
    intervals = []
    for i, values in enumerate(data):
        d = stats.describe(values)
        if d["n"] >= 2:
            intervals.append((i, d))
    if reference is not None:
        ax.axhline(reference * scale, color="red", lw=0.8, ls="--",
                   label=f"reference {reference * scale:.4g} {unit}".rstrip())
        ax.legend(loc="best", fontsize=8)
    _resolution_axis(ax, data)
    low, high = ax.get_ylim()
    for i, d in intervals:  # an interval that would leave the axes is cut at them and its ends written
        lo, hi = max(d["ci_low"], low), min(d["ci_high"], high)
        ax.errorbar([i + 0.32], [d["mean"]], yerr=[[d["mean"] - lo], [hi - d["mean"]]], fmt="D", color="k",
                    ms=4, capsize=3 if (lo, hi) == (d["ci_low"], d["ci_high"]) else 0)
        if (lo, hi) != (d["ci_low"], d["ci_high"]):
            ax.annotate(f"95 % CI\n[{d['ci_low']:.3g},\n{d['ci_high']:.3g}]\n(n = {d['n']})", (i + 0.36, d["mean"]),
                        fontsize=7, va="center", ha="left")
    ax.set_ylim(low, high)
    ax.set_xlim(-0.6, len(names) - 1 + (1.0 if any(
        (max(d["ci_low"], low), min(d["ci_high"], high)) != (d["ci_low"], d["ci_high"]) for _, d in intervals) else 0.6))
    ax.set_xticks(range(len(names)), names, rotation=20 if len(names) > 4 else 0)
    ax.set_ylabel(textwrap.fill(label or measure_label(comparison.measure) + (f" ({unit})" if unit else ""), 36))
    ax.set_title(f"{len(comparison.seeds)} seeds per variant; diamonds: mean, 95 % CI",
                 fontsize=9)
    return save(fig, path, dpi)


#: The model's own force resolution (relative): the flank laws and the quasi-static ladder agree
#: with the measured forces to 0.3-0.5 %. A comparison plot shades this band about the first
#: variant's mean and never spans less than AXIS_SPAN about its data, so a difference the
#: model cannot resolve is never drawn as a cliff.
RESOLUTION = 0.005
AXIS_SPAN = 0.02


def _resolution_axis(ax, data) -> None:
    values = np.concatenate([np.asarray(d, dtype=float) for d in data]) if data else np.array([])
    values = values[np.isfinite(values)]
    if not len(values):
        return
    lo, hi = float(values.min()), float(values.max())
    centre = 0.5 * (lo + hi)
    half = max(0.55 * (hi - lo), AXIS_SPAN * abs(centre))
    if half > 0:
        ax.set_ylim(centre - half, centre + half)
    first = np.asarray(data[0], dtype=float)
    first = first[np.isfinite(first)]
    if len(first):
        m = float(np.mean(first))
        ax.axhspan(m * (1 - RESOLUTION), m * (1 + RESOLUTION), color="0.85", zorder=0,
                   label=f"model resolution (±{100 * RESOLUTION:g} %)")
        ax.legend(loc="best", fontsize=8)


def plot_positions(results, labels, path: str | os.PathLike, *, dpi: int = 120) -> Path:
    """Slider position against time for several runs on one axis (Ooten's figure 10 style).

    Plateaus are where a slider stopped on a flank. Units: µs and µm.
    """
    if len(results) != len(labels):
        raise SceneError(f"`labels` must have one entry per result ({len(results)}), got {len(labels)}")
    fig, (ax,) = figure(1, height=3.2)
    for result, label in zip(results, labels):
        ax.plot(result.t * 1e6, (result.x - result.x[0]) * 1e6, label=label)
    ax.set_xlabel("time (µs)")
    ax.set_ylabel("slider travel (µm)")
    ax.legend(loc="best", fontsize="small")
    return save(fig, path, dpi)


def plot_position_velocity(result, path, *, title: str = "", dpi: int = 120):
    """Ooten's figure 17 analogue: slider position (µm) and velocity (m/s) against time (µs).

    The velocity panel shows the collision spikes where the slider hits a
    lower flank.
    """
    fig, (ax_x, ax_v) = figure(2, height=2.4)
    t = np.asarray(result.t) * 1e6
    ax_x.plot(t, (np.asarray(result.x) - result.x[0]) * 1e6, lw=1.0, label="slider")
    if np.isfinite(result.drive_x).any():
        ax_x.plot(t, (np.asarray(result.drive_x) - result.x[0]) * 1e6, lw=0.8, ls="--",
                  label="drive spring end")
    ax_x.set_ylabel("position (µm)")
    ax_x.legend(loc="upper left", fontsize=8)
    ax_v.plot(t, result.v, lw=0.8, color="C3")
    ax_v.set_ylabel("velocity (m/s)")
    ax_v.set_xlabel("time (µs)")
    if title:
        ax_x.set_title(title, fontsize=9)
    return save(fig, path, dpi)
