"""Contact states: how the slider touched the lower surface over a run, in the belt chains'
three states, separated, sliding and sticking (:func:`contact_states`, :class:`ContactStates`).
A pure function of a Result; nothing simulates. ``asperity2d.analysis`` re-exports both names.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import SceneError
from .events import _asperity_run, _drive_scales, _runs
from .slip_thresholds import STICK_SPEED_FRACTION


# -- contact states: separated, sliding, sticking (the belt chains' vocabulary) --------------------------
@dataclass(frozen=True)
class ContactStates:
    """How the slider touched the lower surface over a run, in the belt chains' three states (SI).

    ``fractions``: time fractions {"separated", "sliding", "sticking"} (sum 1): no contact; contact
    with abs(v) >= ``stick_speed``; contact with abs(v) < ``stick_speed`` (the lower surface does not move
    along x, so v is the slip velocity). ``hops``: contact lost and regained (complete airborne
    intervals); ``passes``: slider travel over the span of the lower tips; ``hops_per_pass``;
    ``touching`` (T,): lower asperities touching at each sample; ``touching_mean`` its time
    average; ``separated_intervals``: the (t_lost, t_regained) intervals out of contact (s; the last
    may run to the end), which for the free slider (``track == "free"``) are its lift-offs.
    Times are sample times: each sample stands for the interval to the next one.
    """

    fractions: dict
    hops: int
    passes: float
    hops_per_pass: float
    touching: np.ndarray
    touching_mean: float
    separated_intervals: list
    stick_speed: float
    track: str

    @property
    def lift_off(self) -> list:
        """The free slider's lift-off intervals (empty on the fixed track, where it cannot lift)."""
        return self.separated_intervals if self.track == "free" else []

    def to_dict(self) -> dict:
        return {"fractions": dict(self.fractions), "hops": self.hops, "passes": self.passes,
                "hops_per_pass": self.hops_per_pass, "touching_mean": self.touching_mean,
                "touching_max": int(self.touching.max()) if self.touching.size else 0,
                "separated_intervals": [list(iv) for iv in self.separated_intervals],
                "lift_off_count": len(self.lift_off), "stick_speed": self.stick_speed, "track": self.track}


def contact_states(result, *, stick_speed: float | None = None) -> ContactStates:
    """Separated / sliding / sticking time fractions, hops and touching tips of an asperity run.

    ``stick_speed`` (m/s) defaults to 0.5 x the drive velocity (as :func:`~asperity2d.stick_slip_events`); a
    constant-force run needs it given.
    """
    _asperity_run(result)
    t = np.asarray(result.t, dtype=float)
    if t.size < 2:
        raise SceneError(f"`result` must have at least 2 samples, got {t.size}")
    result.require_lower("counting the touching asperities")
    if stick_speed is None:
        speed, _ = _drive_scales(result)
        if speed is None:
            raise SceneError("`stick_speed` must be given for a constant-force drive (no drive velocity)")
        stick_speed = STICK_SPEED_FRACTION * speed
    if not (isinstance(stick_speed, (int, float, np.floating)) and np.isfinite(stick_speed) and stick_speed > 0):
        raise SceneError(f"`stick_speed` must be > 0, got {stick_speed!r}")
    weight = np.diff(t, append=t[-1])  # sample k stands for [t_k, t_k+1)
    contact = np.asarray(result.contact_count) > 0
    slow = np.abs(np.asarray(result.v, dtype=float)) < stick_speed
    total = float(weight.sum())
    fractions = {"separated": float(weight[~contact].sum() / total),
                 "sliding": float(weight[contact & ~slow].sum() / total),
                 "sticking": float(weight[contact & slow].sum() / total)}
    runs = _runs(contact.astype(int))
    separated = [(float(t[a]), float(t[b]) if b < t.size else float(t[-1])) for value, a, b in runs if value == 0]
    hops = sum(1 for k, (value, a, b) in enumerate(runs) if value == 0 and 0 < k < len(runs) - 1)
    touching = np.asarray(result.lower_contact).sum(axis=0).astype(int)
    tips = result.scene.lower.tips()
    span = float(np.max(tips) - np.min(tips)) if tips.size > 1 else 0.0
    passes = float(abs(result.x[-1] - result.x[0]) / span) if span > 0 else float("nan")
    return ContactStates(fractions=fractions, hops=int(hops), passes=passes,
                         hops_per_pass=hops / passes if passes > 0 else float("nan"), touching=touching,
                         touching_mean=float(np.sum(weight * touching) / total), separated_intervals=separated,
                         stick_speed=float(stick_speed), track=result.scene.slider.track)
