"""The rough-surface studies: measures of rough scenes, shared by the gallery's rough-surface scripts.

Top-level, picklable run functions (``fn(*, seed, **params) -> dict of numbers``,
the signature :mod:`asperity2d.sweep` runs too), each building one scene with
:func:`~asperity2d.make_scene` and measuring it:

* :func:`rough_run`: random heights (or any ``make_scene`` arguments);
* :func:`self_affine_run`: the lower surface made from a seeded self-affine
  profile (:func:`~asperity2d.surface.self_affine_profile`) of given rms
  height and Hurst exponent, the track level given above its mean line.

Both return the critical constant force (:func:`~asperity2d.critical_force`),
and from one spring-driven pass (on the fixed track every step recorded, so
that a touch of a few steps is not missed): the mean drive force at the stick-to-slip transitions
(:func:`~asperity2d.mean_stick_force`), the number of events, the fraction of
lower asperities that touched the slider, the most contacts at once, the
steepest flank among the asperities that touched, and the contact angle the
breakaway forces imply (:func:`breakaway_angle`), to tell which flanks set them.
The scripts map them over parameter sets with
:func:`asperity2d.sweep.map_calls` and summarise with :mod:`asperity2d.stats`.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis import mean_stick_force, stick_slip_events
from ..builders import make_scene
from ..critical import critical_force
from ..errors import SceneError
from ..scene import Scene, SpringDrive
from ..run import simulate
from .. import units as _units

#: Smallest height (and interference) the engine resolves, in asperity bases (the package's
#: ``asperity2d.units.MIN_LENGTH_RATIO``): a summit closer than this to a fixed track is a
#: contact the engine cannot resolve.
MIN_LENGTH_RATIO = _units.MIN_LENGTH_RATIO


def flank_angles(scene: Scene) -> dict[str, np.ndarray]:
    """Angles of the flanks that face each other as the slider moves to +x.

    Parameters
    ----------
    scene : Scene
        Any scene.

    Returns
    -------
    dict of str to numpy.ndarray
        ``"lower"``: the lower asperities' left flanks, ``"upper"``: the upper ones' right
        (front) flanks, in degrees, one per asperity.
    """
    lower, upper = scene.lower.shape_set(), scene.slider.shape_set()
    return {"lower": np.degrees(np.arctan2(lower.heights, np.asarray(lower.left_runs))),
            "upper": np.degrees(np.arctan2(upper.heights, np.asarray(upper.right_runs)))}


def breakaway_angle(result, events) -> float:
    """Mean contact angle at the stick-to-slip transitions, the flank law read backwards.

    atan(F / N) - atan(mu_s) is the angle of the flank a single contact at the friction limit
    would be on, with F the drive force at each breakaway and N the vertical contact force
    averaged over the stick before it (quasi-static there; single samples carry impact spikes).

    Parameters
    ----------
    result : Result
        A spring-driven run.
    events : list of Event
        Its stick-slip events (:func:`asperity2d.stick_slip_events`).

    Returns
    -------
    float
        The mean angle (degrees); NaN without events.
    """
    t = np.asarray(result.t)
    normal, drive = np.asarray(result.normal_force), np.asarray(result.drive_force)
    phi = math.atan(result.scene.contact.mu_static)
    angles = []
    for e in events:
        k = min(int(np.searchsorted(t, e.t_slip)), len(t) - 1)
        stick = (t >= e.t_stick) & (t <= e.t_slip)
        n = float(np.mean(normal[stick])) if stick.any() else float(normal[k])
        if n > 0:
            angles.append(math.degrees(math.atan2(float(drive[k]), n) - phi))
    return float(np.mean(angles)) if angles else math.nan


def track_level(scene: Scene) -> float:
    """Height of the fixed track's deepest upper tip above the lower datum.

    Parameters
    ----------
    scene : Scene
        Any scene.

    Returns
    -------
    float
        The height (m); NaN for a free slider.
    """
    if scene.slider.track != "fixed":
        return math.nan
    return scene.lower.top - scene.slider.interference


def measure(scene: Scene, *, critical: bool = True) -> dict:
    """The critical force and one spring-driven pass's measures (see the module notes).

    Parameters
    ----------
    scene : Scene
        The scene; its drive is replaced by the default spring for the pass if it has none.
    critical : bool, default True
        Also find the critical force from rest (:func:`asperity2d.critical_force`); NaN if not.

    Returns
    -------
    dict of str to float
        ``critical_force_N`` and the keys of :func:`pass_measures`.
    """
    out = {"critical_force_N": critical_force(scene) if critical else math.nan}
    out.update(pass_measures(scene)[0])
    return out


def pass_measures(scene: Scene):
    """One spring-driven pass of ``scene`` and its measures.

    Parameters
    ----------
    scene : Scene
        The scene; driven by its own spring, or the default spring if its drive is a force.

    Returns
    -------
    measures : dict of str to float
        ``mean_stick_force_N`` (N, NaN without stick-slip events), ``events``,
        ``touched_fraction`` and ``touched_count`` (lower asperities that touched the slider),
        on a fixed track ``above_level_fraction`` and ``touched_matches_above_level`` (1 if the
        asperities touched are exactly those whose summit is above the track), the flank
        angles in contact (degrees), ``breakaway_angle_deg`` (:func:`breakaway_angle`) and
        sanity flags (``passed``, ``floor_touched``, ``track_bottomed``).
    result : Result
        The run (every step recorded on a fixed track, every tenth on a free slider).
    """
    if not isinstance(scene.drive, SpringDrive):
        scene = scene.replace(drive=SpringDrive())
    fixed = scene.slider.track == "fixed"
    result = simulate(scene, record_every=1 if fixed else 10)
    events = stick_slip_events(result)
    touched = result.lower_contact.any(axis=1)
    angles = flank_angles(scene)
    level = track_level(scene)
    above = scene.lower.summits() > level  # all False on a free slider (level NaN)
    lower_flank = float(angles["lower"][touched].max()) if touched.any() else math.nan
    out = {
        "mean_stick_force_N": mean_stick_force(result) if events else math.nan,
        "events": float(len(events)),
        "touched_fraction": float(touched.mean()),
        "touched_count": float(touched.sum()),
        "above_level_fraction": float(above.mean()) if fixed else math.nan,
        "touched_matches_above_level": float(np.array_equal(touched, above)) if fixed else math.nan,
        # summits above the track passed without contact because they rise less above it than
        # the slider travelled in the step its tips crossed them (pymunk detects contacts at the
        # steps only: at 3-4 km/s slips a step is 30-45 nm)
        **_missed_within_a_step(scene, result, touched, above, level, fixed),
        "max_contacts": float(np.max(result.contact_count)),
        "breakaway_angle_deg": breakaway_angle(result, events),
        "steepest_touched_flank_deg": lower_flank,
        "steepest_upper_flank_deg": float(angles["upper"].max()),
        # the steepest flank either surface brings into contact (the deepest upper tip, the
        # tallest and steepest on a fixed base, always touches)
        "steepest_contact_flank_deg": max(lower_flank, float(angles["upper"].max())),
        "lower_count": float(scene.lower.count),
        "tallest_height_m": float(scene.lower.heights().max()),
        "passed": float(result.status == "passed"),
        # the guard floor must never carry the slider (DESIGN: wide gaps); 1e-3 base of slack
        "floor_touched": float(np.min(result.y) - scene.slider.depth
                               <= scene.floor + 1e-3 * scene.base),
        # a lower asperity pushed to the bottom of its track (the load is too large for it)
        "track_bottomed": float(np.min(result.lower_dy) <= -(1 - 1e-3) * scene.lower.travel_down),
    }
    return out, result


def _missed_within_a_step(scene: Scene, result, touched, above, level: float, fixed: bool) -> dict:
    """``missed_within_step``: summits above the track that no tip touched and that rise less
    above it than the slider's travel in the recorded step where a tip crossed their apex;
    ``touched_matches_resolvable``: 1 if the touched set is the set above the track apart from
    those; ``max_step_travel_m``: the largest step the slider took (all with ``record_every=1``)."""
    if not fixed:
        return {"missed_within_step": math.nan, "touched_matches_resolvable": math.nan,
                "max_step_travel_m": math.nan}
    x = np.asarray(result.x, dtype=float)
    travel = np.abs(np.diff(x))
    margin = scene.lower.summits() - level
    within = np.zeros(scene.lower.count, dtype=bool)
    for i in np.flatnonzero(above & ~touched):
        steps = []
        for offset in np.ravel(scene.slider.tips()):
            j = int(np.searchsorted(x + offset, scene.lower.tips()[i]))
            if 0 < j < x.size:
                steps.append(travel[j - 1])
        within[i] = bool(steps) and margin[i] < min(steps)
    mismatch = (touched != above) & ~within
    return {"missed_within_step": float(within.sum()), "touched_matches_resolvable": float(not mismatch.any()),
            "max_step_travel_m": float(travel.max()) if travel.size else math.nan}


def rough_run(*, seed: int = 0, critical: bool = True, **params) -> dict:
    """:func:`measure` of ``make_scene(seed=seed, **params)``: a sweep's run function.

    Parameters
    ----------
    seed : int, default 0
        The scene's seed.
    critical : bool, default True
        Also find the critical force (as in :func:`measure`).
    **params
        Keyword arguments of :func:`asperity2d.make_scene` (e.g. ``height_std=...``).

    Returns
    -------
    dict of str to float
        The measures of :func:`measure`.
    """
    return measure(make_scene(seed=seed, **params), critical=critical)


def fixed_track_interference(lower, separation: float, margin: float) -> tuple[float, bool]:
    """The interference that runs a fixed track's deepest tip a given height above a profile.

    The tip runs ``separation`` above the lower profile's mean line, or ``margin`` above its
    rigid valley floor where that is higher (a rigid slider cannot pass below the valleys
    between summits: it would jam).

    Parameters
    ----------
    lower : LowerSurface
        The lower surface of a scene made from a profile (``scene.lower``).
    separation : float
        Height (m) of the track above the profile's mean line.
    margin : float
        Smallest height (m) of the track above the rigid valley floor.

    Returns
    -------
    interference : float
        The interference (m) to give :func:`asperity2d.make_scene`.
    raised : bool
        Whether the valley floor set it.
    """
    floor = max((z for line in lower.substrate or () for _, z in line), default=-math.inf)
    level = max(separation, floor + margin)
    return lower.top - level, level > separation


def self_affine_run(*, seed: int = 0, hurst: float, rms_height: float, length: float, points: int,
                    shortest: float, longest: float, separation: float | None = None,
                    critical: bool = True, **params) -> dict:
    """:func:`measure` of a scene whose lower surface is a self-affine profile.

    On a fixed track the deepest upper tip runs ``separation`` above the profile's mean line,
    or 5 % of the rms height above its rigid valley floor where that is higher
    (:func:`fixed_track_interference`).

    Parameters
    ----------
    seed : int, default 0
        Seed of the profile (:func:`asperity2d.surface.self_affine_profile`) and the scene.
    hurst : float
        Hurst exponent of the profile.
    rms_height : float
        Its rms height (m).
    length : float
        Its length (m).
    points : int
        Its number of samples.
    shortest, longest : float
        The wavelengths (m) its power lies between (a roll-off plateau beyond ``longest``).
    separation : float, optional
        Height (m) of the fixed track above the mean line; required on the fixed track.
    critical : bool, default True
        Also find the critical force (as in :func:`measure`).
    **params
        Further keyword arguments of :func:`asperity2d.make_scene` (``track`` defaults to fixed).

    Returns
    -------
    dict of str to float
        The measures of :func:`measure`, ``valid`` (1), ``rms_slope`` and, on a fixed track,
        ``level_raised`` (1 if the valley floor set the track); only ``valid`` = 0 and
        ``level_raised`` when the track would lie above every summit.
    """
    from ..surface import rms_slope, self_affine_profile

    profile = self_affine_profile(n=points, length=length, rms_height=rms_height, hurst=hurst,
                                  q_min=2 * math.pi / longest, q_max=2 * math.pi / shortest,
                                  rolloff=True, seed=seed)
    extra = {}
    if params.get("track", "fixed") == "fixed":
        if separation is None:
            raise SceneError("`separation` is required on the fixed track")
        probe = make_scene(lower_surface=profile, track="free", seed=seed).lower
        interference, raised = fixed_track_interference(probe, separation, 0.05 * rms_height)
        if interference <= 0:
            return {"valid": 0.0, "level_raised": float(raised)}
        params = {**params, "interference": interference}
        extra["level_raised"] = float(raised)
    out = measure(make_scene(lower_surface=profile, seed=seed, **params), critical=critical)
    out.update({"valid": 1.0, "rms_slope": rms_slope(profile), **extra})
    return out


def trend_claim(text: str, x, y, sign: int, *, setup: str | None = None, alpha: float = 0.05) -> dict:
    """The claim that ``y`` rises or falls with ``x``, judged by a Spearman rank correlation.

    Parameters
    ----------
    text : str
        The claim's statement.
    x, y : array_like
        The paired values (non-finite pairs are left out).
    sign : {1, -1}
        1: ``y`` rises with ``x``; -1: it falls.
    setup : str, optional
        The set-up the claim is about (e.g. ``"fixed"``).
    alpha : float, default 0.05
        The two-sided p-value the correlation must be under.

    Returns
    -------
    dict
        A claim record (:func:`asperity2d.experiments.verdicts.claim`): holds if the
        correlation has the sign ``sign`` with p < ``alpha``; does not hold if it has the other
        sign with p < ``alpha``; undecided otherwise; not testable when fewer than 3 finite
        pairs or a constant series give no p-value.
    """
    from ..experiments.verdicts import FAILS, HOLDS, UNDECIDED, UNTESTABLE, claim

    rho, p = spearman(x, y)
    n = int(np.sum(np.isfinite(np.asarray(x, float)) & np.isfinite(np.asarray(y, float))))
    verdict = (UNTESTABLE if not math.isfinite(p) else UNDECIDED if not p < alpha
               else HOLDS if np.sign(rho) == sign else FAILS)
    return claim(text, verdict, {"spearman_rho": rho, "p": p, "n": n},
                 f"Spearman rank correlation over {n} runs, two-sided; holds if "
                 f"{'positive' if sign > 0 else 'negative'} with p < {alpha:g}", setup=setup)


def spearman(x, y) -> tuple[float, float]:
    """Spearman rank correlation of the finite pairs and its two-sided p-value.

    Parameters
    ----------
    x, y : array_like
        The paired values.

    Returns
    -------
    rho : float
        The correlation (:func:`scipy.stats.spearmanr`); NaN for fewer than 3 finite pairs or a
        constant series.
    p : float
        Its two-sided p-value (NaN likewise).
    """
    from scipy.stats import spearmanr

    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    keep = np.isfinite(x) & np.isfinite(y)
    if keep.sum() < 3 or np.ptp(x[keep]) == 0 or np.ptp(y[keep]) == 0:
        return math.nan, math.nan
    res = spearmanr(x[keep], y[keep])
    return float(res.statistic), float(res.pvalue)
