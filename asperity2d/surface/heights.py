"""Random asperity heights: seeded draws with a chosen mean and standard deviation.

Greenwood and Williamson describe a rough surface by the distribution of its
summit heights, most often Gaussian. :func:`random_heights` draws one height
per asperity:

* ``"gaussian"``: mean + std * N(0, 1);
* ``"uniform"``: uniform on [mean - sqrt(3) std, mean + sqrt(3) std], the
  uniform distribution with that mean and standard deviation.

Heights are never clipped: clipping would pile draws up at the clip and change
the mean and spread that were asked for. A Gaussian height is <= 0 with
probability Phi(-mean / std) (0.6 % at std = mean / 2.5); a uniform one never
when std < mean / sqrt(3). With a ``floor`` (a scene's triangles need heights
the engine resolves, :data:`asperity2d.units.MIN_LENGTH_RATIO` bases), every
draw at or below it is redrawn from the same stream: the heights then follow
the distribution truncated at the floor, whose mean and spread
:func:`truncated_moments` gives in closed form. ``max_std`` is the largest
spread for which at most :data:`MAX_REDRAWN` (1 %) of the draws fall below the
floor; ``make_scene`` refuses a larger one, so the truncation moves the mean
by at most 0.027 std (Gaussian) and the heights stay what was asked for.
"""

from __future__ import annotations

import math

import numpy as np

from .._inputs import check_choice, check_finite, check_int, check_nonnegative
from ..errors import SceneError

DISTRIBUTIONS = ("gaussian", "uniform")
#: Largest probability of a draw below the floor that is redrawn rather than refused.
MAX_REDRAWN = 0.01
_MAX_ROUNDS = 200  # redraw rounds: at <= 1 % per draw, 200 rounds leave < 1e-400 per height


def random_heights(count: int, *, mean: float, std: float, distribution: str = "gaussian",
                   seed: int | np.random.SeedSequence = 0, floor: float | None = None) -> np.ndarray:
    """``count`` heights (m) with the given ``mean`` and standard deviation ``std`` (m).

    ``seed`` is an integer or a ``numpy.random.SeedSequence`` (so that each
    surface of a scene can get its own stream spawned from one seed);
    the same seed gives the same heights. ``floor`` (m): draws at or below it
    are redrawn (see the module notes); draws above it are the very numbers
    drawn without a floor.

    Parameters
    ----------
    count : int
        Number of heights.
    mean, std : float
        Mean and standard deviation (m).
    distribution : {"gaussian", "uniform"}, default "gaussian"
        The distribution.
    seed : int or numpy.random.SeedSequence, default 0
        The stream.
    floor : float, optional
        Draws at or below it are redrawn (m).

    Returns
    -------
    numpy.ndarray
        Heights (m).

    See Also
    --------
    asperity2d.surface.fraction_above : the share above a level, in closed form.
    asperity2d.make_scene : ``height_std=`` draws them for a scene.

    Examples
    --------
    >>> import numpy as np
    >>> from asperity2d.surface import random_heights
    >>> np.round(random_heights(4, mean=0.5e-6, std=0.05e-6, seed=1) * 1e9, 1)  # nm
    array([517.3, 541.1, 516.5, 434.8])
    """
    count = check_int("count", count, minimum=1)
    mean = check_finite("mean", mean)
    std = check_nonnegative("std", std)
    check_choice("distribution", distribution, DISTRIBUTIONS)
    if not isinstance(seed, np.random.SeedSequence):
        seed = check_int("seed", seed, minimum=0)
    rng = np.random.default_rng(seed)
    half_width = math.sqrt(3.0) * std

    def draw(k):
        if distribution == "gaussian":
            return mean + std * rng.standard_normal(k)
        return rng.uniform(mean - half_width, mean + half_width, k)

    heights = draw(count)
    if floor is None:
        return heights
    floor = check_finite("floor", floor)
    if fraction_above(floor, mean=mean, std=std, distribution=distribution) == 0.0:
        raise SceneError(f"`std`: no {distribution} height with mean {mean:g} m and std {std:g} m "
                         f"lies above the floor {floor:g} m")
    for _ in range(_MAX_ROUNDS):
        low = heights <= floor
        if not low.any():
            return heights
        heights[low] = draw(int(low.sum()))
    raise SceneError(f"`std`: {distribution} heights (mean {mean:g} m, std {std:g} m) kept falling "
                     f"below the floor {floor:g} m after {_MAX_ROUNDS} redraws")


def max_std(mean: float, floor: float, *, distribution: str = "gaussian") -> float:
    """Largest std (m) that puts at most :data:`MAX_REDRAWN` of the draws at or below ``floor``.

    Gaussian: (mean - floor) / z with z = Q^-1(0.01) = 2.326; uniform:
    (mean - floor) / (sqrt(3) (1 - 2 x 0.01)).
    """
    from scipy.stats import norm

    check_choice("distribution", distribution, DISTRIBUTIONS)
    room = check_finite("mean", mean) - check_finite("floor", floor)
    if room <= 0:
        return 0.0
    if distribution == "gaussian":
        return room / float(norm.isf(MAX_REDRAWN))
    return room / (math.sqrt(3.0) * (1.0 - 2.0 * MAX_REDRAWN))


def truncated_moments(mean: float, std: float, floor: float, *,
                      distribution: str = "gaussian") -> tuple[float, float]:
    """Mean and standard deviation (m) of the heights :func:`random_heights` draws with ``floor``.

    Gaussian: those of ``scipy.stats.truncnorm`` cut at ``floor``; uniform:
    the uniform distribution on [max(floor, mean - sqrt(3) std), mean + sqrt(3) std].
    """
    from scipy.stats import truncnorm

    check_choice("distribution", distribution, DISTRIBUTIONS)
    if std == 0:
        return float(mean), 0.0
    if distribution == "gaussian":
        d = truncnorm((floor - mean) / std, math.inf, loc=mean, scale=std)
        return float(d.mean()), float(d.std())
    half_width = math.sqrt(3.0) * std
    lo, hi = max(floor, mean - half_width), mean + half_width
    return 0.5 * (lo + hi), (hi - lo) / math.sqrt(12.0)


def fraction_above(level: float, *, mean: float, std: float, distribution: str = "gaussian",
                   floor: float | None = None) -> float:
    """Probability that a height drawn as in :func:`random_heights` exceeds ``level`` (m).

    The closed form the "which asperities carry load" study checks against:
    Q((level - mean) / std) for Gaussian heights (Q the normal tail), a
    linear ramp for uniform ones; with a ``floor`` (redrawn heights), the
    tail above max(level, floor) divided by the tail above the floor.

    Parameters
    ----------
    level : float
        The level (m).
    mean, std : float
        As for :func:`random_heights` (m).
    distribution : {"gaussian", "uniform"}, default "gaussian"
        The distribution.
    floor : float, optional
        The redraw floor (m).

    Returns
    -------
    float
        A probability.

    See Also
    --------
    asperity2d.surface.random_heights

    Examples
    --------
    >>> from asperity2d.surface import fraction_above
    >>> round(fraction_above(0.55e-6, mean=0.5e-6, std=0.05e-6), 4)  # one std above: 15.87 %
    0.1587
    """
    from scipy.stats import norm

    check_choice("distribution", distribution, DISTRIBUTIONS)
    level, mean = check_finite("level", level), check_finite("mean", mean)
    std = check_nonnegative("std", std)
    if floor is not None:
        floor = check_finite("floor", floor)
        kept = fraction_above(floor, mean=mean, std=std, distribution=distribution)
        if kept == 0.0:
            return math.nan
        return fraction_above(max(level, floor), mean=mean, std=std, distribution=distribution) / kept
    if std == 0:
        return float(mean > level)
    with np.errstate(over="ignore", divide="ignore"):  # a vanishing std: z = +-inf, the tail is 0 or 1
        z = (np.float64(level) - mean) / np.float64(std)
        if distribution == "gaussian":
            return float(norm.sf(z))
        half_width = math.sqrt(3.0) * std
        return float(np.clip((mean + half_width - level) / (2.0 * half_width), 0.0, 1.0))


def random_shapes(shape, count: int, *, std: float, name: str, distribution: str,
                  seed: np.random.SeedSequence | int, floor: float, upper: bool):
    """``count`` asperities of ``shape`` (a :class:`~asperity2d.geometry.Profile`), each with
    its own height drawn about ``shape.height`` (same base, so each its own flank angles),
    as a ``Shapes`` record. A ``std`` over ``max_std`` is
    refused, naming the parameter ``name``."""
    from ..shapes import Shapes
    from ..units import MIN_LENGTH_RATIO

    std = check_nonnegative(name, std)  # a plain float (a Fraction or NumPy scalar may come in)
    limit = max_std(shape.height, floor, distribution=distribution)
    if std > limit:
        raise SceneError(
            f"`{name}` = {std:g} m is too wide for {distribution} heights about {shape.height:g} m: "
            f"over 1 % of them would fall below {floor:.3g} m ({MIN_LENGTH_RATIO:g} base, the smallest "
            f"height the engine resolves) and be redrawn; use `{name}` <= {limit:.4g} m")
    heights = random_heights(count, mean=shape.height, std=std, distribution=distribution,
                             seed=seed, floor=floor)
    left, right = shape.runs(upper=upper)
    return Shapes(heights=heights, left_runs=(left,) * count, right_runs=(right,) * count)
