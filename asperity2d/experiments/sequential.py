"""Seeds added in stages until a verdict is decided, with the false-positive rate held at alpha.

``compare(..., seeds="auto", max_seeds=N)`` measures a first stage of seeds, judges, and adds
a stage at a time until the verdict is decided (holds, no effect, or shown the other way) or
the budget of N seeds is spent. Looking at the data after every stage and stopping at the
first "holds" would raise the chance of a false "holds" well above alpha (with four looks at a
fixed level 0.01 it is about 0.025); a group-sequential design spends alpha across the looks
so that the chance of a false claim over *all* of them stays at alpha.

The method: Lan-DeMets alpha spending (Lan & DeMets 1983, "Discrete sequential boundaries for clinical
trials", *Biometrika* 70(3), 659-663), with the spending function of either type:

* ``"pocock"`` (the default): alpha(t) = alpha ln(1 + (e - 1) t), Lan & DeMets' Pocock-type
  function (Pocock 1977, *Biometrika* 64(2), 191-199): nearly equal nominal levels at every
  look, so a clear effect is decided at the first stage;
* ``"obrien-fleming"``: alpha(t) = 2 - 2 Phi(z(1 - alpha/2) / sqrt(t)), the O'Brien-Fleming-
  type function (O'Brien & Fleming 1979, *Biometrics* 35(3), 549-556): almost nothing spent
  early, nearly the full alpha at the last look.

t = n_k / N is the information fraction of look k (the seeds planned by then over the budget).
The one-sided boundary c_k of look k solves

    P(Z_1 < c_1, ..., Z_(k-1) < c_(k-1), Z_k >= c_k) = alpha(t_k) - alpha(t_(k-1))

for the standardised statistics Z_k of the looks, which under no effect are multivariate
normal with Corr(Z_i, Z_j) = sqrt(n_i / n_j) (i <= j): the canonical joint distribution of a
statistic that sums independent per-seed contributions (Jennison & Turnbull 2000, *Group
Sequential Methods with Applications to Clinical Trials*, Chapman & Hall/CRC, ch. 3 and 7).
The signed-rank statistic of the per-seed changes is such a sum under no effect, to its
normal approximation. :func:`boundaries` integrates that multivariate normal one look at a
time (deterministic, so the boundaries are the same every run) and :func:`scipy.optimize.brentq`
solves for c_k. Look k then tests at the nominal one-sided level
a_k = 1 - Phi(c_k): "holds" needs the signed-rank p < a_k (and the effect at least the margin),
"no effect" the ratio's 1 - 2 a_k interval inside the margin -- each of its two one-sided tests
at a_k, the same boundaries -- and "does not hold" the opposite test at a_k. Each of those
claims, if false, is made at some look with probability at most alpha: stopping at a look for
another reason only removes later chances to err.

A comparison that runs out of budget is "undecided" with :func:`~asperity2d.experiments.verdicts.seeds_needed`.

Examples
--------
>>> from asperity2d.experiments.sequential import Design
>>> design = Design(stages=(10, 20, 30), alpha=0.01)
>>> [f"{a:.2g}" for a in design.nominal]       # the level each look tests at
['0.0045', '0.0041', '0.0039']
>>> design.describe()
'3 stages of up to 30 seeds (10, 20, 30), Lan-DeMets alpha spending of Pocock type, overall alpha 0.01'
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

from .._inputs import check_int
from ..errors import SceneError

SPENDING = ("pocock", "obrien-fleming")
#: Seeds per stage unless told otherwise: the fewest that leave the exact signed-rank test room
#: to reach the first look's nominal level (10 seeds all on one side give p = 2**-10 ~ 0.001,
#: under the first Pocock-type level 0.0045 of a 30-seed budget at alpha 0.01; 8 seeds give 0.0039,
#: which no look of a design at 0.01 with more than one look tests at).
STAGE_SEEDS = 10
#: The budget ``seeds="auto"`` spends when not told: four stages of :data:`STAGE_SEEDS`.
MAX_SEEDS = 40


def plan(max_seeds: int, stage_seeds: int = STAGE_SEEDS) -> tuple[int, ...]:
    """The seeds measured by each look: ``stage_seeds``, twice that, ..., up to ``max_seeds``
    (the last stage takes what is left).

    >>> plan(40), plan(25, 10)
    ((10, 20, 30, 40), (10, 20, 25))
    """
    max_seeds = check_int("max_seeds", max_seeds, minimum=2, maximum=100_000)
    stage_seeds = check_int("stage_seeds", stage_seeds, minimum=2, maximum=100_000)
    stages = tuple(range(stage_seeds, max_seeds, stage_seeds)) + (max_seeds,)
    return stages


def spent(t: float, alpha: float, spending: str = "pocock") -> float:
    """alpha(t): the type I error spent by information fraction ``t`` in [0, 1]
    (module docstring: Lan & DeMets' Pocock-type or O'Brien-Fleming-type function).

    >>> round(spent(1.0, 0.01), 12), round(spent(0.5, 0.01, "obrien-fleming"), 6)
    (0.01, 0.00027)
    """
    from scipy.stats import norm

    if spending == "pocock":
        return alpha * math.log(1.0 + (math.e - 1.0) * t)
    if spending == "obrien-fleming":
        return 2.0 - 2.0 * float(norm.cdf(norm.ppf(1.0 - alpha / 2.0) / math.sqrt(t))) if t > 0 else 0.0
    raise SceneError(f"`spending` must be one of {', '.join(SPENDING)}, got {spending!r}")


#: Points of the numerical integration over the previous look's statistic (Simpson's rule on
#: [-LOW, c]); 1601 points put the boundaries within 1e-6 of the published tables.
_POINTS, _LOW = 1601, 10.0


def _simpson(a: float, b: float):
    """Nodes and Simpson weights on [a, b]."""
    import numpy as np

    z = np.linspace(a, b, _POINTS)
    w = np.ones(_POINTS)
    w[1:-1:2], w[2:-1:2] = 4.0, 2.0
    return z, w * (b - a) / (3.0 * (_POINTS - 1))


@functools.lru_cache(maxsize=64)
def boundaries(stages: tuple[int, ...], alpha: float, spending: str = "pocock") -> tuple[float, ...]:
    """The one-sided critical values c_k of the standardised statistic at each look (module
    docstring), for looks after ``stages`` seeds (increasing) at overall level ``alpha``.

    The probabilities are the multivariate normal's, integrated one look at a time (Jennison &
    Turnbull 2000, ch. 19; Armitage, McPherson & Rowe 1969): given Z_(k-1) = u, Z_k is normal with
    mean u sqrt(n_(k-1) / n_k) and variance 1 - n_(k-1) / n_k, so the density of Z_k on the paths
    that have not crossed yet is the previous one carried by that kernel (Simpson's rule), and the
    chance of crossing at look k is that density times the kernel's tail. Deterministic, and the
    same as the Genz integral of :func:`scipy.stats.multivariate_normal` to 1e-7.

    >>> [round(c, 3) for c in boundaries((1, 2, 3, 4), 0.025, "obrien-fleming")]   # Jennison & Turnbull
    [4.333, 2.963, 2.359, 2.014]
    """
    import numpy as np
    from scipy.optimize import brentq
    from scipy.stats import norm

    n = np.asarray(stages, dtype=float)
    crit: list[float] = []
    before = 0.0
    z = w = density = None  # the grid, its weights and the density of the paths not yet stopped
    for k in range(len(n)):
        now = spent(n[k] / n[-1], alpha, spending)
        target = now - before
        if k == 0:
            c = float(norm.isf(target)) if target > 0 else math.inf
            c = min(c, 12.0)
            z, w = _simpson(-_LOW, c)
            density = norm.pdf(z)
        else:
            r = math.sqrt(n[k - 1] / n[k])
            sd = math.sqrt(1.0 - r * r)
            mass = density * w

            def crossing(c_k):
                return float(np.sum(mass * norm.sf((c_k - r * z) / sd))) - target

            c = float(brentq(crossing, -_LOW, 12.0, xtol=1e-9)) if crossing(12.0) < 0 else 12.0
            new_z, new_w = _simpson(-_LOW, c)
            kernel = norm.pdf((new_z[:, None] - r * z[None, :]) / sd) / sd
            density, z, w = kernel @ mass, new_z, new_w
        crit.append(c)
        before = now
    return tuple(crit)


@dataclass(frozen=True)
class Design:
    """A group-sequential plan: looks after ``stages`` seeds (increasing), overall one-sided
    level ``alpha`` per claim, Lan-DeMets spending of type ``spending`` (module docstring).

    Examples
    --------
    >>> d = Design(stages=(10, 20, 30, 40), alpha=0.01)
    >>> d.look(20), d.look(40), d.look(23)
    (1, 3, None)
    """

    stages: tuple[int, ...]
    alpha: float = 0.01
    spending: str = "pocock"

    def __post_init__(self):
        stages = tuple(check_int("stages", s, minimum=1, maximum=100_000) for s in self.stages)
        if not stages or any(b <= a for a, b in zip(stages, stages[1:])):
            raise SceneError(f"`stages` must be increasing seed counts, got {list(self.stages)}")
        if len(stages) > 12:
            raise SceneError(f"`stages` must be at most 12 looks, got {len(stages)}")
        object.__setattr__(self, "stages", stages)
        if not (isinstance(self.alpha, (int, float)) and 0.0 < self.alpha < 0.5):
            raise SceneError(f"`alpha` must be in (0, 0.5), got {self.alpha!r}")
        if self.spending not in SPENDING:
            raise SceneError(f"`spending` must be one of {', '.join(SPENDING)}, got {self.spending!r}")

    @property
    def critical(self) -> tuple[float, ...]:
        """The one-sided critical z of each look."""
        return boundaries(self.stages, float(self.alpha), self.spending)

    @property
    def nominal(self) -> tuple[float, ...]:
        """The nominal one-sided level a_k = 1 - Phi(c_k) each look tests at."""
        from scipy.stats import norm

        return tuple(float(norm.sf(c)) for c in self.critical)

    def look(self, seeds: int) -> int | None:
        """The index of the look made after ``seeds`` seeds (None: not a look of this plan)."""
        return self.stages.index(seeds) if seeds in self.stages else None

    def describe(self) -> str:
        """The plan in words."""
        kind = "Pocock" if self.spending == "pocock" else "O'Brien-Fleming"
        k = len(self.stages)
        return (f"{k} stage{'s' * (k > 1)} of up to {self.stages[-1]} seeds "
                f"({', '.join(map(str, self.stages))}), Lan-DeMets alpha spending of {kind} type, "
                f"overall alpha {self.alpha:g}")

    def to_dict(self) -> dict:
        return {"stages": list(self.stages), "alpha": self.alpha, "spending": self.spending,
                "method": "Lan-DeMets alpha spending (Lan & DeMets 1983)"}


def run_in_stages(design: Design, measure_stage, decide, *, on_stage=None) -> tuple[int, str]:
    """Measure stage by stage until decided: the loop of ``compare(..., seeds="auto")``.

    ``measure_stage(k, first, last)`` measures the seeds ``first`` (inclusive) to ``last``
    (exclusive) of look k; ``decide(k, nominal_alpha)`` judges everything measured so far at the
    look's nominal level and returns True once decided; ``on_stage(k, first, last)`` is told before
    each stage runs (progress). Returns ``(looks made, seeds measured)``.

    >>> seen = []
    >>> run_in_stages(Design((10, 20, 30)), lambda k, a, b: seen.append((a, b)), lambda k, a: k == 1)
    (2, 20)
    >>> seen
    [(0, 10), (10, 20)]
    """
    nominal = design.nominal
    first = 0
    for k, last in enumerate(design.stages):
        if on_stage is not None:
            on_stage(k, first, last)
        measure_stage(k, first, last)
        if decide(k, nominal[k]):
            return k + 1, last
        first = last
    return len(design.stages), design.stages[-1]
