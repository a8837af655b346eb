"""Random asperity heights: seeded draws with a chosen mean and standard deviation.

Greenwood and Williamson describe a rough surface by the distribution of its
summit heights, most often Gaussian. :func:`random_heights` draws one height
per asperity:

* ``"gaussian"``: mean + std * N(0, 1);
* ``"uniform"``: uniform on [mean - sqrt(3) std, mean + sqrt(3) std], the
  uniform distribution with that mean and standard deviation.

Heights are not clipped: clipping would change the mean and spread that were
asked for. A Gaussian height is <= 0 with probability Phi(-mean / std)
(0.6 % at std = mean / 2.5); a uniform one never when std < mean / sqrt(3).
Whoever builds triangles from the heights must reject non-positive ones.
"""

from __future__ import annotations

import math

import numpy as np

from .._validate import check_choice, check_finite, check_int, check_nonnegative

DISTRIBUTIONS = ("gaussian", "uniform")


def random_heights(count: int, *, mean: float, std: float, distribution: str = "gaussian",
                   seed: int | np.random.SeedSequence = 0) -> np.ndarray:
    """``count`` heights (m) with the given ``mean`` and standard deviation ``std`` (m).

    ``seed`` is an integer or a ``numpy.random.SeedSequence`` (so that each
    surface of a scene can get its own stream spawned from one seed);
    the same seed gives the same heights.
    """
    count = check_int("count", count, minimum=1)
    mean = check_finite("mean", mean)
    std = check_nonnegative("std", std)
    check_choice("distribution", distribution, DISTRIBUTIONS)
    if not isinstance(seed, np.random.SeedSequence):
        seed = check_int("seed", seed, minimum=0)
    rng = np.random.default_rng(seed)
    if distribution == "gaussian":
        return mean + std * rng.standard_normal(count)
    half_width = math.sqrt(3.0) * std
    return rng.uniform(mean - half_width, mean + half_width, count)


def fraction_above(level: float, *, mean: float, std: float, distribution: str = "gaussian") -> float:
    """Probability that a height drawn as in :func:`random_heights` exceeds ``level`` (m).

    The closed form the "which asperities carry load" study checks against:
    Q((level - mean) / std) for Gaussian heights (Q the normal tail), a
    linear ramp for uniform ones.
    """
    from scipy.stats import norm

    check_choice("distribution", distribution, DISTRIBUTIONS)
    level, mean = check_finite("level", level), check_finite("mean", mean)
    std = check_nonnegative("std", std)
    if std == 0:
        return float(mean > level)
    if distribution == "gaussian":
        return float(norm.sf(level, loc=mean, scale=std))
    half_width = math.sqrt(3.0) * std
    return float(np.clip((mean + half_width - level) / (2.0 * half_width), 0.0, 1.0))
