"""The belt chains' limits: derived scales and the work budget of a run (:class:`SceneError`).

Each parameter alone is checked by the package's one validator (:mod:`asperity2d._validate`:
real, finite, within the magnitude window ``TINY`` .. ``HUGE``). Here:

* the chain's derived scales (``ChainSpec.rate_bound``, ``velocity_scale``,
  ``length_scale``, force and energy scales) are finite and below 1e150 -- the jointly
  absurd combinations that pass the per-parameter window;
* budgets (overridable): ``max_steps`` bounds the work of a run, counted as scan steps of
  the exact solver (``t_end`` over 1/16 of the fastest period) or right-hand-side
  evaluations of an integrator; at most ``MAX_MASSES`` masses; at most ``MAX_VALUES``
  sampled values (masses x samples).
"""

from __future__ import annotations

import math

from .._validate import show
from ..errors import SceneError

#: largest derived scale (rate, speed, length, force, energy) of a chain
SCALE_LIMIT = 1e150
#: the dense eigendecomposition of an all-slipping chain costs O(n³): minutes beyond this
MAX_MASSES = 2000
#: masses x output samples (each result holds ~8 such arrays of doubles)
MAX_VALUES = 20_000_000


def scales(spec) -> None:
    """Refuse chains whose derived scales overflow (each parameter alone being acceptable)."""
    reach = spec.length_scale + abs(spec.belt_velocity(0.0)) * spec.t_end
    force = spec.force_scale
    derived = (
        ("fastest rate (1/s)", spec.rate_bound, "`masses`, `springs` and `dampers`"),
        ("velocity scale (m/s)", spec.velocity_scale, "`v_belt`, `v0`, `mu_s`, `g` or `normal_load`, `masses`"),
        ("length scale (m)", spec.length_scale, "`x0` and the velocity scale over the fastest rate"),
        ("distance travelled (m)", reach, "`v_belt` times `t_end`"),
        ("force scale (N)", force, "`mu_s` times the normal load, or `springs` times the length scale"),
        ("energy scale (J)", spec.energy_scale,
         "the force scale times the length scale, or `masses` times the velocity scale squared"),
    )
    for what, value, source in derived:
        if not (math.isfinite(value) and value <= SCALE_LIMIT):
            raise SceneError(f"the chain's {what} is {show(value)}, beyond {SCALE_LIMIT:g}: rescale {source}")


def budget(spec, n_values: int, max_steps: int) -> int:
    """Estimated scan steps of the run; refuse it when over ``max_steps`` or the sample budget."""
    if spec.n > MAX_MASSES:
        raise SceneError(f"`masses` may hold at most {MAX_MASSES} masses, got {spec.n}")
    if n_values * spec.n > MAX_VALUES:
        raise SceneError(f"`n_samples` (or `t_eval`) asks for {n_values:,} samples of {spec.n} masses, over the "
                         f"budget of {MAX_VALUES:,} values")
    steps = spec.t_end / spec.scan_step
    if steps > max_steps:
        raise SceneError(
            f"`t_end` = {show(spec.t_end)} s is {steps:.3g} steps of 1/16 of the chain's fastest period "
            f"({2 * math.pi / spec.rate_bound:.3g} s, from `masses`, `springs`, `dampers`), over the budget "
            f"`max_steps` = {max_steps:,}; shorten `t_end` or raise `max_steps`")
    return int(math.ceil(steps))
