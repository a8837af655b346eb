"""Contacts that open: the studies behind ``scenes/belt_contact.py``.

The multi-DOF belt thesis lets its Coulomb contact be "separated, sliding or
sticking" and names the mechanisms of friction-induced vibration beyond
stick-slip: mode coupling (Hoffmann's minimal model), sprag-slip, a falling
friction curve. Here:

* :func:`minimal_map` -- regimes of the minimal model over (mu, belt speed), one exact
  run per grid point through the sweep machinery (resumable store, local
  processes or Dask), classified by :func:`asperity2d.belt.classify_contact`;
* :func:`thesis_opening` -- when the thesis' 3-DOF chain (Table 2), given normal
  compliance k_c and one inclined spring per mass, loses contact: its steady
  sliding's growth rate (the solver's phase matrix) against the simulated first
  opening, over (k_c, mu, belt speed);
* :func:`chain_states` -- the three states of a belt run in the table that
  :func:`asperity_states` fills for an asperity run;
* :func:`plot_map`, :func:`plot_cycle`, :func:`plot_opening` and :func:`normal_sound` -- the
  study's pictures and its sound.
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass

import numpy as np

from ..belt import MinimalModel, NormalContact, classify_contact, presets, simulate_chain, steady_sliding
from ..belt.regime import CONTACT_REGIMES  # the regimes classify_contact names, in its order
from ..errors import SceneError

MAP_RUN = "asperity2d.studies.contact:contact_map_run"
MAP_KEYS = ("label", "first", "t_first", "separated_fraction", "stuck_fraction", "events")
#: first nonlinearity a run meets: none, a stick, a contact opening
FIRST = ("none", "stick", "open")


def contact_map_run(*, mu: float, v_belt: float, model: str, t_end: float, kick: float, n_samples: int,
                    seed: int = 0) -> dict:
    """Sweep run function: one run of the minimal model from kicked steady sliding.

    ``model`` is the JSON of a :class:`asperity2d.belt.MinimalModel`'s fields; the run starts at
    (``mu``, ``v_belt``) from steady sliding kicked by ``kick`` (m/s, normal velocity); ``seed`` is
    unused. Returns the ``MAP_KEYS`` of the run as floats."""
    from ..dynamics.basins import RUN_CPU_LIMIT, cpu_limit

    mm = MinimalModel(**json.loads(model))
    with cpu_limit(RUN_CPU_LIMIT):
        r = simulate_chain(**mm.chain(mu=mu, v_belt=v_belt, t_end=t_end, kick=kick, n_samples=n_samples))
    first = next((e for e in r.events if e.kind in ("stick", "open")), None)
    states = chain_states(r, window=0.5)
    return {"label": float(CONTACT_REGIMES.index(classify_contact(r))),
            "first": float(0 if first is None else FIRST.index("stick" if first.kind == "stick" else "open")),
            "t_first": float("nan") if first is None else first.t,
            "separated_fraction": states["separated"], "stuck_fraction": states["sticking"],
            "events": float(len(r.events))}


@dataclass(frozen=True)
class ContactMap:
    """Regimes of the minimal model over ``mu`` (rows) x ``v_belt`` (columns, m/s).

    ``values[key]`` (len(mu), len(v)) for ``MAP_KEYS``: ``label`` indexes ``CONTACT_REGIMES`` (-1 a
    failed run), ``first`` indexes ``FIRST``; ``model`` the :class:`asperity2d.belt.MinimalModel`;
    ``t_end`` (s).
    """

    mu: np.ndarray
    v_belt: np.ndarray
    values: dict
    model: MinimalModel
    t_end: float
    kick: float
    failed: int
    wall_time: float

    def counts(self) -> dict:
        lab = self.values["label"]
        return {name: int(np.sum(lab == i)) for i, name in enumerate(CONTACT_REGIMES)} | {"failed": self.failed}

    def onset(self) -> tuple[float, float]:
        """(largest mu of the first column band that is steady, smallest mu that is not) over all speeds:
        the grid's bracket of the flutter onset."""
        lab = self.values["label"]
        steady = np.all(lab == CONTACT_REGIMES.index("steady sliding"), axis=1)
        unsteady = np.all(lab != CONTACT_REGIMES.index("steady sliding"), axis=1)
        lo = float(self.mu[steady].max()) if steady.any() else float("nan")
        hi = float(self.mu[unsteady].min()) if unsteady.any() else float("nan")
        return lo, hi

    def to_dict(self) -> dict:
        n = self.values["label"].size
        counts = self.counts()
        return {"mu": self.mu.tolist(), "v_belt_m_s": self.v_belt.tolist(), "t_end_s": self.t_end, "kick_m_s": self.kick,
                "model": asdict(self.model), "counts": counts,
                "fractions": {k: v / n for k, v in counts.items() if k != "failed"},
                "labels": [[CONTACT_REGIMES[int(v)] if v >= 0 else "failed" for v in row]
                           for row in self.values["label"]],
                "first": [[FIRST[int(v)] if np.isfinite(v) else "failed" for v in row] for row in self.values["first"]],
                "onset_bracket": list(self.onset()), "run_seconds_total": self.wall_time}


def minimal_map(model: MinimalModel, mu_values, v_values, *, t_end: float, kick: float = 1e-2,
                samples_per_period: int = 24, store=None, workers: int | None = None, progress: bool = True
                ) -> ContactMap:
    """Run the minimal model over ``mu_values`` x ``v_values`` from kicked steady sliding.

    One exact run per grid point through the sweep machinery, classified by
    :func:`asperity2d.belt.classify_contact`.

    Parameters
    ----------
    model : asperity2d.belt.MinimalModel
        The pad.
    mu_values : sequence of float
        Friction coefficients (mu_s = mu_k), the map's rows.
    v_values : sequence of float
        Belt speeds (m/s), its columns.
    t_end : float
        Length of each run (s).
    kick : float, default 0.01
        Normal velocity (m/s) added to steady sliding at t = 0.
    samples_per_period : int, default 24
        Output samples per period of the coalesced modes.
    store : str or os.PathLike, optional
        The sweep's results folder (resumable); default a temporary one.
    workers : int, optional
        Worker processes (None: decided by cost).
    progress : bool, default True
        Show a progress bar.

    Returns
    -------
    ContactMap
        The regimes, first events and fractions over the grid.
    """
    from ..dynamics.basins import _run as run_grid
    from ..sweep import Study

    if not isinstance(model, MinimalModel):
        raise SceneError(f"`model` must be a MinimalModel, got {model!r}")
    mus = tuple(float(m) for m in mu_values)
    vs = tuple(float(v) for v in v_values)
    if not mus or not vs:
        raise SceneError("`mu_values` and `v_values` must not be empty")
    period = 2 * np.pi / model.coalescence_frequency
    n_samples = int(min(200_000, max(201, samples_per_period * t_end / period)))
    study = Study(name="contact-map", run=MAP_RUN, grid={"mu": mus, "v_belt": vs},
                  fixed={"model": json.dumps(asdict(model), sort_keys=True), "t_end": float(t_end),
                         "kick": float(kick), "n_samples": n_samples})
    im, iv = {v: i for i, v in enumerate(mus)}, {v: j for j, v in enumerate(vs)}
    values, failed, wall = run_grid(study, store, workers, None, progress, (len(mus), len(vs)), MAP_KEYS,
                                    lambda spec: (im[spec.params["mu"]], iv[spec.params["v_belt"]]))
    return ContactMap(np.array(mus), np.array(vs), values, model, float(t_end), float(kick), failed, wall)


def chain_states(result, *, window: float = 1.0) -> dict:
    """The three states of a belt run: time separated, sliding and sticking.

    From the exact stick and separation intervals over the run's last ``window`` fraction, all
    masses pooled.

    Parameters
    ----------
    result : asperity2d.belt.BeltResult or asperity2d.belt.ContactResult
        A run (without a normal contact nothing separates).
    window : float, default 1.0
        The fraction of the run, at its end, that is counted.

    Returns
    -------
    dict
        ``separated``, ``sliding``, ``sticking`` (fractions of time), ``hops`` (contacts opened
        and closed again in the window), ``hops_per_second`` and ``contacts_mean`` (masses in
        contact, time average).
    """
    t0, t1 = result.t[-1] - window * (result.t[-1] - result.t[0]), result.t[-1]
    span = (t1 - t0) * result.n

    def inside(intervals):
        return sum(max(0.0, min(b, t1) - max(a, t0)) for per in intervals for a, b in per)

    seps = getattr(result, "separation_intervals", [[] for _ in range(result.n)])
    separated, sticking = inside(seps) / span, inside(result.stick_intervals) / span
    hops = sum(1 for per in seps for a, b in per if t0 <= a and b < t1)
    return {"separated": separated, "sticking": sticking, "sliding": max(0.0, 1.0 - separated - sticking),
            "hops": hops, "hops_per_second": hops / (t1 - t0), "contacts_mean": result.n * (1 - separated)}


def thesis_opening(contact_stiffness, mu_values, v_values, *, inclined=((10.0, 135.0),), t_end: float = 60.0,
                   progress: bool = True) -> list[dict]:
    """The thesis' Table 2 chain with a normal compliance: does its contact open, and where?

    The chain from eq 3.12 with ``NormalContact(contact_stiffness=k_c, inclined=inclined)`` on
    every mass, over k_c x mu x v_belt.

    Parameters
    ----------
    contact_stiffness : sequence of float
        Contact stiffnesses k_c (N/m).
    mu_values : sequence of float
        Friction coefficients (mu_s = mu_k).
    v_values : sequence of float
        Belt speeds (m/s).
    inclined : tuple of (float, float), default ((10.0, 135.0),)
        Inclined springs per mass: (stiffness in N/m, angle in degrees).
    t_end : float, default 60.0
        Length of each run (s).
    progress : bool, default True
        Show a progress bar.

    Returns
    -------
    list of dict
        One row per point: ``contact_stiffness``, ``mu``, ``v_belt``, steady sliding's
        ``growth_rate`` (1/s) and ``steady_normal_force`` (N), the run's ``first_open_s`` (NaN if
        none), ``openings``, ``separated_fraction`` and ``regime``.
    """
    from tqdm import tqdm

    grid = [(float(k), float(m), float(v)) for k in contact_stiffness for m in mu_values for v in v_values]
    rows = []
    for kc, mu, v in tqdm(grid, desc="thesis chain, normal compliance", disable=not progress, leave=False):
        normal = NormalContact(contact_stiffness=kc, inclined=tuple(inclined))
        kw = presets.preset("table2-3dof", mu_s=mu, mu_k=mu, v_belt=v, t_end=t_end, n_samples=int(50 * t_end) + 1)
        lin = steady_sliding(**kw, normal=normal)
        r = simulate_chain(**kw, normal=normal)
        opens = [a for per in r.separation_intervals for a, _ in per]
        rows.append({"contact_stiffness": kc, "mu": mu, "v_belt": v, "growth_rate": lin.growth_rate,
                     "steady_normal_force": lin.normal_force.tolist(), "first_open_s": min(opens, default=float("nan")),
                     "openings": len(opens), "separated_fraction": chain_states(r)["separated"],
                     "regime": classify_contact(r)})
    return rows


def normal_force_without_coupling(*, stiff: bool = True) -> dict:
    """Without an inclined spring the normal force stays m g: every thesis preset, checked.

    Each preset with a rigid (and, if ``stiff``, a compliant k_c = 1e6 N/m) contact and no
    inclined spring: the normal equation is decoupled from x, so N must stay m g.

    Parameters
    ----------
    stiff : bool, default True
        Check the compliant contact too.

    Returns
    -------
    dict
        ``presets`` (how many), ``contacts`` (which), ``max_relative_departure`` (the largest
        ``abs(N - m g) / (m g)``) and ``openings`` (contacts that opened).
    """
    worst, openings = 0.0, 0
    contacts = (NormalContact(), NormalContact(contact_stiffness=1e6)) if stiff else (NormalContact(),)
    for name in presets.names():
        kw = presets.preset(name)
        for normal in contacts:
            r = simulate_chain(**kw, normal=normal)
            weight = r.chain.m[:, None] * r.chain.g
            if np.any(weight > 0):
                worst = max(worst, float(np.max(np.abs(r.normal_force - weight) / weight)))
            openings += sum(len(s) for s in r.separation_intervals) + int(np.any(r.separated))
    return {"presets": len(presets.names()), "contacts": ["rigid", "compliant k_c = 1e6 N/m"][:len(contacts)],
            "max_relative_departure": worst, "openings": openings}


def asperity_states(result, *, stick_speed: float | None = None):
    """Separated / sliding / sticking time fractions, hops and touching tips of an asperity run.

    The asperity model's row of the three-state table beside :func:`chain_states`' belt rows.

    Parameters
    ----------
    result : asperity2d.Result
        An asperity run (a free slider's, to see it separate).
    stick_speed : float, optional
        Below this slider speed (m/s) a sample counts as stuck; default half the drive speed.

    Returns
    -------
    object
        ``fractions`` ({"separated", "sliding", "sticking"}), ``hops``, ``hops_per_pass``,
        ``touching_mean`` (lower tips touching, time average) and ``to_dict()``.
    """
    from ..analysis import contact_states

    return contact_states(result, stick_speed=stick_speed)


def normal_acceleration(result, mass: int = 0) -> np.ndarray:
    """The pad's out-of-plane acceleration y'' (m/s²) of ``mass``, exact from the state.

    (f0 - K_s q - C_s q' + N) / m: what a vibrating plate radiates follows its normal surface
    motion, so the study's sounds play this.

    Parameters
    ----------
    result : asperity2d.belt.ContactResult
        A run with a normal contact.
    mass : int, default 0
        The mass (0-based).

    Returns
    -------
    numpy.ndarray
        y'' at every sample of ``result.t`` (m/s²).
    """
    spec = result.contact
    n = spec.n
    q = np.vstack([result.x, result.y])
    qd = np.vstack([result.v, result.vy])
    force = spec.constant_force[n + mass] - spec.stiffness_matrix[n + mass] @ q - spec.damping_matrix[n + mass] @ qd
    return (force + result.normal_force[mass]) / spec.chain.m[mass]


def normal_sound(result, path, *, mass: int = 0, time_scale: float = 1.0) -> dict:
    """Write the normal acceleration of ``mass`` (:func:`normal_acceleration`) as a WAV.

    Parameters
    ----------
    result : asperity2d.belt.ContactResult
        A run with a normal contact, sampled finely enough for the sound (44.1 kHz for real time).
    path : str or os.PathLike
        The ``.wav`` file; its spectrogram goes beside it (``<name>.spectrogram.png``).
    mass : int, default 0
        The mass (0-based).
    time_scale : float, default 1.0
        Playback frequency over simulated frequency (1: real time).

    Returns
    -------
    dict
        What was written: ``path``, ``spectrogram``, ``sample_rate`` (Hz), ``samples``,
        ``duration`` (s), ``time_scale``, ``dominant_hz``, ``gain``, ``level_db``, ``signal``.
    """
    from ..renderers.sound import write_wav

    return write_wav((result.t, normal_acceleration(result, mass)), path, time_scale=time_scale).to_dict()


def plot_map(contact_map: ContactMap, path, *, title: str = ""):
    """Draw a :class:`ContactMap`: the regime of every (mu, belt speed), the closed-form flutter
    onset mu_crit(eta) and the speed V*(mu) below which a growing flutter meets stick first.

    Parameters
    ----------
    contact_map : ContactMap
        A map of :func:`minimal_map`.
    path : str or os.PathLike
        The image file (``.png``, ``.svg``, ``.pdf``).
    title : str, default ""
        The title (default: the run length).

    Returns
    -------
    pathlib.Path
        The file written.
    """
    from ..renderers.belt import plot_contact_map

    return plot_contact_map(contact_map, path, title=title)


def plot_cycle(result, path, *, title: str = ""):
    """Draw a contact run: mass 1's slip velocity, gap and normal force over the last 3 % of the
    run (separated intervals blue, stuck orange) and its normal phase portrait.

    Parameters
    ----------
    result : asperity2d.belt.ContactResult
        A run with a normal contact.
    path : str or os.PathLike
        The image file (``.png``, ``.svg``, ``.pdf``).
    title : str, default ""
        The title.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    from ..renderers.belt import plot_contact_run

    return plot_contact_run(result, path, title=title)


def plot_opening(rows: list[dict], path, *, curves: dict | None = None):
    """Draw :func:`thesis_opening`'s rows: steady sliding's growth rate against the contact
    stiffness, one marker per run (filled where the contact opened).

    Parameters
    ----------
    rows : list of dict
        The rows of :func:`thesis_opening`.
    path : str or os.PathLike
        The image file (``.png``, ``.svg``, ``.pdf``).
    curves : dict, optional
        mu -> (contact stiffnesses, growth rates): the linearisation on a fine grid, drawn as lines.

    Returns
    -------
    pathlib.Path
        The file written.
    """
    from ..renderers.belt import plot_opening as draw

    return draw(rows, path, curves=curves)
