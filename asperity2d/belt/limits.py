"""The belt chains' limits: derived scales and the work budget of a run (:class:`SceneError`).

Each parameter alone is checked by the package's one validator (:mod:`asperity2d._inputs`:
real, finite, within the magnitude window ``TINY`` .. ``HUGE``). Here:

* the chain's derived scales (``ChainSpec.rate_bound``, ``velocity_scale``,
  ``length_scale``, force and energy scales) are finite and below 1e150 -- the jointly
  absurd combinations that pass the per-parameter window;
* budgets (overridable): ``max_steps`` bounds the work of a run, counted as scan steps of
  the exact solver (``t_end`` over 1/16 of the fastest period) or right-hand-side
  evaluations of an integrator; at most ``MAX_MASSES`` masses; at most ``MAX_VALUES``
  sampled values (masses x samples); at most ``MAX_MEMORY`` (4 GiB) of estimated peak memory
  (:func:`memory_estimate`: ~1,000 bytes per mass² and ~200 per mass and sample; a 1,800-mass
  chain with 2,001 samples is about the largest that fits), with each cache of a run held to
  ``CACHE_BYTES``;
* a rigid normal contact's masses differ by at most ``MAX_MASS_RATIO_RIGID`` (1e5).
"""

from __future__ import annotations

import math

from .._inputs import show
from ..errors import SceneError

#: largest derived scale (rate, speed, length, force, energy) of a chain
SCALE_LIMIT = 1e150
#: relative tolerance that declares an event function zero (and two numbers equal at a switch):
#: the switch finder's (:mod:`.phases.finder`), and the spec's static-limit band
SWITCH_TOL = 1e-9
#: the dense eigendecomposition of an all-slipping chain costs O(n³): minutes beyond this
MAX_MASSES = 2000
#: masses x output samples (each result holds ~8 such arrays of doubles)
MAX_VALUES = 20_000_000
#: the largest estimated peak memory of one run (bytes, :func:`memory_estimate`), refused up front beyond
MAX_MEMORY = 4 * 2**30
#: the largest ratio of masses a *rigid* normal contact is solved for (:func:`contact_masses`). A rigid
#: contact's phases hold a landed mass at y = 0 and propagate the others in one closed form whose rounding
#: follows the heaviest mass's scales: measured over 24 rigid chains (restitution 0 and 0.5, with and
#: without inclined springs, either mass the heavy one), every run at ratios up to 1e5 passed its checks;
#: at 1e6 a light mass's or heavy mass's landing was missed by 3e-11 to 2e-7 m (refused by the validity
#: check) or the switching stalled. A compliant contact checks each mass on its own scale and has no limit.
MAX_MASS_RATIO_RIGID = 1e5
#: per cache of a run (mode patterns, segments' eigendecompositions): the oldest entries are dropped
#: beyond this many bytes (recomputed when needed again, to the same bits)
CACHE_BYTES = 256 * 2**20
#: and beyond this many entries (the solvers' own ``CACHE_SIZE`` are this one)
CACHE_SIZE = 512


def memory_estimate(n: int, n_values: int, dof: int = 1) -> float:
    """Estimated peak memory (bytes) of a run of ``n`` masses and ``n_values`` output samples.

    ~1,000 bytes per mass² -- the mode pattern in use: the eigenvectors of its 2n x 2n phase matrix
    and their inverse, its mode shapes for positions, velocities and accelerations, its event and
    power rows (complex), the phase's amplitudes and LAPACK's workspace -- plus ~200 bytes per mass
    and sample: the result's eight series, the recorded copies they are joined from and a phase's
    sampling temporaries (25 doubles); plus what the caches hold besides the pattern in use
    (:func:`cache_estimate`: up to ``CACHE_BYTES`` each). ``dof``: 2 for a chain with a normal degree
    of freedom (its phase matrices are 4n x 4n: four times the first term). A 2,000-mass chain with
    2,001 samples was reported to take 3-5 GB (estimate 4.8 GB); a 200-mass chain with mu_s = 0.05
    peaks at 284 MiB (estimate 621 MiB), 250 MiB of it cached mode patterns."""
    return 1000.0 * (dof * n) ** 2 + 200.0 * n * n_values + cache_estimate(n, dof)


#: bytes per (dof·n)² of one cached entry, measured (``limits.nbytes``) on all-slipping chains of 100 and
#: 200 masses: a tangential mode pattern 114 (its sparse shapes and event maps), a segment 41, a contact
#: mode pattern 65; rounded up
ENTRY_BYTES = {1: (120.0, 45.0), 2: (70.0,)}


def cache_estimate(n: int, dof: int = 1) -> float:
    """Bytes the caches of a run hold besides the entry in use: each holds at most ``CACHE_SIZE``
    entries and ``CACHE_BYTES`` (the newest always kept), an entry of ``n`` masses taking
    :data:`ENTRY_BYTES` per (dof·n)². A chain's distinct mode patterns grow with its events: a
    500-mass chain with mu_s = 0.05 cycles through hundreds of them."""
    total = 0.0
    for per in ENTRY_BYTES[dof]:
        entry = per * (dof * n) ** 2
        total += max(0.0, min(float(CACHE_BYTES), CACHE_SIZE * entry) - entry)
    return total


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
    dof = 2 if hasattr(spec, "chain") else 1  # a ContactSpec (it wraps a chain): x and y per mass
    need = memory_estimate(spec.n, n_values, dof)
    if need > MAX_MEMORY:
        which = "`masses`" if 1000.0 * dof * dof * spec.n > 200.0 * n_values else "`n_samples` (or `t_eval`)"
        raise SceneError(f"{which}: a run of {spec.n} masses with {n_values:,} samples needs ~{need / 2**30:.1f} GiB "
                         f"(estimated), over the limit of {MAX_MEMORY / 2**30:g} GiB; use fewer masses or samples")
    steps = spec.t_end / spec.scan_step
    if steps > max_steps:
        raise SceneError(
            f"`t_end` = {show(spec.t_end)} s is {steps:.3g} steps of 1/16 of the chain's fastest period "
            f"({2 * math.pi / spec.rate_bound:.3g} s, from `masses`, `springs`, `dampers`), over the budget "
            f"`max_steps` = {max_steps:,}; shorten `t_end` or raise `max_steps`")
    return int(math.ceil(steps))


def contact_masses(spec) -> None:
    """Refuse a rigid normal contact whose masses differ by more than :data:`MAX_MASS_RATIO_RIGID`."""
    if not spec.normal.rigid:
        return
    m = spec.chain.m
    ratio = float(m.max() / m.min())
    if ratio > MAX_MASS_RATIO_RIGID:
        raise SceneError(f"`masses` differ by a factor of {ratio:.3g} (from {float(m.min()):g} to "
                         f"{float(m.max()):g} kg): a rigid normal contact is solved for ratios up to "
                         f"{MAX_MASS_RATIO_RIGID:g}; bring the masses closer or give the contact a "
                         "`contact_stiffness` (a compliant contact has no such limit)")


def nbytes(entry) -> int:
    """Bytes of the arrays an object holds as attributes (a cache entry's size): NumPy arrays and
    SciPy sparse arrays (their data, indices and index pointers; a sparse array has no ``nbytes``, and
    a mode pattern's shapes and event maps are sparse: uncounted, 512 patterns of a 500-mass chain
    held ~3.5 GiB under a cache bound of 256 MiB)."""
    return sum(_array_bytes(v) for v in vars(entry).values())


def _array_bytes(value) -> int:
    if hasattr(value, "nbytes"):
        return int(value.nbytes)
    parts = [getattr(value, name, None) for name in ("data", "indices", "indptr", "coords", "offsets")]
    if hasattr(value, "nnz") and hasattr(value, "shape"):  # a SciPy sparse array (any format)
        return sum(_array_bytes(part) for part in parts if part is not None and not isinstance(part, memoryview))
    if isinstance(value, tuple) and all(hasattr(v, "nbytes") for v in value):  # COO's coords
        return sum(int(v.nbytes) for v in value)
    return 0


def bound_cache(cache: dict, sizes: dict, count: int) -> None:
    """Drop the oldest entries of ``cache`` (``sizes``: their bytes) beyond ``count`` entries or
    ``CACHE_BYTES`` in all, the newest always kept. A dropped entry is recomputed when needed again,
    to the same bits: only memory changes."""
    while len(cache) > 1 and (len(cache) > count or sum(sizes.values()) > CACHE_BYTES):
        key = next(iter(cache))
        cache.pop(key)
        sizes.pop(key, None)
