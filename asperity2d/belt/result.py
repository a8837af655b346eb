"""BeltResult: the time series of one belt-chain run, with save / load / CSV export.

Mirrors :class:`asperity2d.result.Result` (the same result protocol: ``kind``,
``status``, ``message``, ``success``, ``summary()``, a format-tagged ``save`` and
a ``load`` that refuses a malformed or foreign file with one ``FileError``):
plain SI NumPy arrays on a small object, saved as one ``.npz`` (arrays plus a
JSON ``metadata`` entry holding the chain, the events, the exact stick
intervals and the run settings).
"""

from __future__ import annotations

import math
import os
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from .._io import FileError, atomic_write, check_format, load_npz, save_npz
from .._inputs import show
from ..errors import SceneError, SimulationError
from .backend import Event, RawRun
from .spec import ChainSpec, link_extension, link_force

#: Per-mass arrays (n, T).
MASS_SERIES = ("x", "v", "state", "friction_force", "spring_force", "damper_force")
#: Scalar series (T,), all in J.
ENERGY_SERIES = ("belt_work", "friction_dissipation", "damper_dissipation", "kinetic_energy", "spring_energy")
#: The format tag of a saved belt run (version 1: the previous release's untagged files).
FORMAT = "asperity2d.belt-result/2"


@dataclass(eq=False)
class BeltResult:
    """Time series of a chain on a belt (SI).

    Attributes
    ----------
    t : (T,) sample times (s), uniform samples merged with the event times.
    x, v : (n, T) positions (m, from the unstretched configuration) and velocities (m/s).
    state : (n, T) 0 stuck, +1 / -1 slipping faster / slower than the belt.
    friction_force : (n, T) friction on each mass (N), +x positive.
    spring_force, damper_force : (n, T) net spring / damper force on each mass (N).
    belt_work, friction_dissipation, damper_dissipation : (T,) cumulative energies (J).
    kinetic_energy, spring_energy : (T,) stored energies (J).
    stick_intervals : per mass, the list of (t_start, t_end) stick intervals (s).
    events : list of :class:`Event`.
    chain : the :class:`ChainSpec` (None when loaded with a callable belt speed).
    meta : run settings and diagnostics.

    See Also
    --------
    asperity2d.belt.simulate_chain : makes one.
    asperity2d.belt.load : reads a saved one (so does :func:`asperity2d.load`).
    asperity2d.render : ``render(result, "chain.png")`` plots it.

    Examples
    --------
    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0)
    >>> r.x.shape, r.state[0, :3]  # one row per mass; 0 = stuck to the belt
    ((1, 2006), array([0, 0, 0], dtype=int8))
    >>> f"{r.belt_work[-1]:.3g} J from the belt, {r.friction_dissipation[-1]:.3g} J dissipated"
    '...J from the belt, ...J dissipated'
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    state: np.ndarray
    friction_force: np.ndarray
    spring_force: np.ndarray
    damper_force: np.ndarray
    belt_work: np.ndarray
    friction_dissipation: np.ndarray
    damper_dissipation: np.ndarray
    kinetic_energy: np.ndarray
    spring_energy: np.ndarray
    stick_intervals: list
    events: list
    chain: ChainSpec | None
    meta: dict = field(default_factory=dict)

    #: What kind of result this is (the renderers and ``asperity2d analyze`` dispatch on it).
    kind = "belt"

    @property
    def n(self) -> int:
        return self.x.shape[0]

    # -- the result protocol -----------------------------------------------
    @property
    def status(self) -> str:
        """Why the run ended: ``"t_end"`` (a run over its budget raises instead)."""
        return self.meta.get("status", "t_end")

    @property
    def message(self) -> str:
        """The reason in words."""
        return self.meta.get("message", f"reached t_end = {self.t[-1]:.6g} s" if self.t.size else "")

    @property
    def success(self) -> bool:
        """True: a chain run either reaches ``t_end`` or raises (budgets, a bad belt speed)."""
        return self.status == "t_end"

    def summary(self) -> dict:
        """Headline numbers (SI), JSON-ready: the protocol's fields, the run's size and energy
        books, and per mass its stick/slip record (``sticks``: stick intervals; ``stuck_s`` and
        ``stuck_fraction``: time spent stuck; ``slip_starts``: stick-to-slip transitions)."""
        duration = float(self.t[-1] - self.t[0]) if self.t.size else 0.0
        masses = []
        for i, intervals in enumerate(self.stick_intervals):
            stuck = float(sum(b - a for a, b in intervals))
            masses.append({"mass": i + 1, "sticks": len(intervals), "stuck_s": stuck,
                           "stuck_fraction": stuck / duration if duration > 0 else 0.0,
                           "slip_starts": sum(1 for a, b in intervals if b < self.t[-1])})
        return {"kind": self.kind, "status": self.status, "success": self.success, "message": self.message,
                "n": self.n, "duration_s": duration, "samples": int(self.t.size), "events": len(self.events),
                "method": self.meta.get("method"), "energy_balance_error": self.energy_balance_error(),
                "checks": {name: "passed" if c.get("passed", True) else "failed"
                           for name, c in self.meta.get("checks", {}).items() if isinstance(c, dict)},
                "masses": masses}

    @property
    def stored_energy(self) -> np.ndarray:
        """Kinetic plus spring energy (J)."""
        return self.kinetic_energy + self.spring_energy

    @property
    def initial_energy(self) -> float:
        """Stored energy at t = 0 (J): the first sample's, or (samples that start later, ``t_eval``)
        the chain's initial state's; NaN when neither is known (a loaded callable-belt run)."""
        if self.t.size and self.t[0] == 0:
            return float(self.stored_energy[0])
        if self.chain is None:
            return math.nan
        spec = self.chain
        return float(0.5 * np.sum(spec.m * np.asarray(spec.v0) ** 2)
                     + 0.5 * np.sum(spec.k * link_extension(np.asarray(spec.x0)) ** 2))

    @property
    def energy_residual(self) -> np.ndarray:
        """(E - E0) - (W_belt - D_friction - D_damper) at every sample (J); zero for a closed balance."""
        return (self.stored_energy - self.initial_energy) - (
            self.belt_work - self.friction_dissipation - self.damper_dissipation
        )

    def _energy_parts(self) -> tuple:
        return (self.belt_work, self.friction_dissipation, self.damper_dissipation, self.kinetic_energy,
                self.spring_energy)

    def energy_balance_error(self) -> float:
        """max abs(residual) over the largest energy flow or store (dimensionless). The stores are
        taken one by one (kinetic, springs, ...): their sum can cancel to rounding (a mass
        swinging on its spring against a preload holds E = 0 throughout), and a residual of
        1e-16 J over a total of 1e-16 J is not an error of 1."""
        scale = max(np.max(np.abs(a)) for a in self._energy_parts())
        return float(np.max(np.abs(self.energy_residual)) / max(scale, 1e-300))

    def __repr__(self) -> str:
        return f"BeltResult(n={self.n}, {self.t.size} samples, t_end={self.t[-1]:.4g} s, events={len(self.events)})"

    def _repr_html_(self) -> str:
        """The interactive player of the chain (Jupyter shows it; :mod:`asperity2d.renderers.player`)."""
        from .._display import represent

        return represent(self, "html")

    # -- persistence -------------------------------------------------------
    #: The arrays a saved run holds (each ``(T,)`` or per mass ``(n, T)``), in export order.
    SAVED = ("t",) + MASS_SERIES + ENERGY_SERIES
    #: The format tag ``save()`` writes.
    FORMAT = FORMAT

    def _record(self) -> dict:
        """The JSON metadata of a saved run: the run's settings, the chain, events and intervals."""
        meta = dict(self.meta)
        meta["chain"] = self.chain.to_dict() if self.chain is not None else meta.get("chain")
        meta["events"] = [asdict(e) for e in self.events]
        meta["stick_intervals"] = [[list(iv) for iv in per] for per in self.stick_intervals]
        return meta

    def save(self, path: str | os.PathLike) -> Path:
        """Write the result to ``path`` (``.npz``, tagged :attr:`FORMAT`) atomically and return the path."""
        return save_npz(path, {name: getattr(self, name) for name in self.SAVED}, self._record(),
                        format=self.FORMAT)

    def columns(self) -> list[tuple[str, np.ndarray]]:
        """Every saved array as named 1-D columns: ``t``; per mass i (1-based) ``x_i``, ``v_i``,
        ``state_i``, ``friction_force_i``, ``spring_force_i``, ``damper_force_i`` (and the
        kind's own per-mass series); then the scalar series (energies, J)."""
        per_mass = [name for name in self.SAVED if np.ndim(getattr(self, name)) == 2]
        scalar = [name for name in self.SAVED if name != "t" and name not in per_mass]
        cols = [("t", self.t)]
        cols += [(f"{name}_{i + 1}", getattr(self, name)[i]) for i in range(self.n) for name in per_mass]
        cols += [(name, getattr(self, name)) for name in scalar]
        return cols

    def export(self, path: str | os.PathLike) -> Path:
        """Write every saved array to ``path``: a ``.csv`` table (:meth:`columns`, one row per
        sample) or a MATLAB ``.mat`` file (the arrays by name, (n, T) per mass, and the metadata
        as JSON text)."""
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".csv":
            names, cols = zip(*self.columns())
            table = np.column_stack([np.asarray(c, dtype=float) for c in cols])

            def write(fh):
                np.savetxt(fh, table, delimiter=",", header=",".join(names), comments="", fmt="%.17g")

            return atomic_write(path, write)
        if suffix == ".mat":
            import json

            from scipy.io import savemat

            data = {name: np.asarray(getattr(self, name)) for name in self.SAVED}
            data["metadata"] = json.dumps(self._record(), sort_keys=True, default=str)
            return atomic_write(path, lambda fh: savemat(fh, data))
        raise SceneError(f"`path` must end in .csv or .mat, got {str(path)!r}")


#: Energy books a returned run must close to (``energy_balance_error``): closed-form phases
#: integrate the work exactly (measured 1e-16 - 1e-11 on every chain of the tests and the
#: fuzzers); integrated phases carry it as ODE states, good to the integrator's tolerance
#: (measured up to ~3e-6 at rtol = 1e-8; the sign() method's chatter included).
BOOKS_TOLERANCE = 1e-6
BOOKS_PER_RTOL = 1e3


def books_tolerance(meta: dict) -> float:
    """The energy-book tolerance of a run with ``meta`` (its back-end and ``rtol``)."""
    if meta.get("backend") in ("closed-form phases", "closed-form contact phases"):
        return BOOKS_TOLERANCE
    return max(BOOKS_TOLERANCE, BOOKS_PER_RTOL * float(meta.get("rtol", 1e-8)))


def check_books(result) -> None:
    """Raise SimulationError if ``result``'s energy books are off by more than their tolerance
    (:func:`books_tolerance`); else record the check in ``result.meta["checks"]``. A result
    whose books do not close created or lost energy the model has no term for: switches
    mis-resolved (a velocity snapped to the belt's), an integrator that did not converge."""
    if math.isnan(result.initial_energy):  # samples from t > 0 of a contact run: no E(0) to check against
        result.meta.setdefault("checks", {})["energy_books"] = {
            "passed": True, "worst": None, "limit": books_tolerance(result.meta),
            "what": "not checked: the samples start after t = 0"}
        return
    error = result.energy_balance_error()
    limit = books_tolerance(result.meta)
    t = float(result.t[-1]) if result.t.size else 0.0
    if not error <= limit:  # also NaN
        residual = np.abs(result.energy_residual)
        wrong = ~(residual <= limit / error * np.max(residual)) if error > 0 else np.ones(residual.size, bool)
        at = int(np.argmax(wrong)) if result.t.size else 0
        raise SimulationError(
            f"the energy books do not close: off by {error:.3g} of the largest energy flow (tolerance "
            f"{limit:.3g}), first beyond the tolerance at t = {float(result.t[at]):.6g} s; the run "
            f"({result.meta.get('backend')}) created or lost energy; use a smaller `rtol`, or bring the "
            "chain's forces and speeds closer together (friction limits far beyond the spring forces, "
            "a belt speed far from the initial speeds)", time=t)
    result.meta.setdefault("checks", {})["energy_books"] = {
        "passed": True, "worst": error, "limit": limit, "what": "energy balance error / largest energy flow"}


def assemble(spec: ChainSpec, raw: RawRun, meta: dict) -> BeltResult:
    """Build a BeltResult from a back-end's raw run (adds forces and stored energies); ``meta`` replaces raw.meta.
    Its energy books are checked (:func:`check_books`)."""
    x, v = raw.x, raw.v
    state = np.array(raw.state, dtype=np.int8)
    frictionless = ~spec.frictional
    if frictionless.any():
        V = spec.belt_velocity(raw.t)
        state[frictionless] = np.sign(v[frictionless] - V[None, :])
    meta = dict(meta)
    meta["chain"] = spec.to_dict()
    meta.setdefault("status", "t_end")
    meta.setdefault("message", f"reached t_end = {float(raw.t[-1]):.6g} s")
    result = BeltResult(
        t=raw.t, x=x, v=v, state=state,
        friction_force=raw.friction_force,
        spring_force=link_force(spec.k, x),
        damper_force=link_force(spec.c, v),
        belt_work=raw.work[0], friction_dissipation=raw.work[1], damper_dissipation=raw.work[2],
        kinetic_energy=0.5 * (spec.m[:, None] * v**2).sum(axis=0),
        spring_energy=0.5 * (spec.k[:, None] * link_extension(x) ** 2).sum(axis=0),
        stick_intervals=[[tuple(map(float, iv)) for iv in per] for per in raw.stick_intervals],
        events=list(raw.events), chain=spec, meta=meta,
    )
    check_books(result)
    return result


def check_arrays(path, arrays: dict, kind: str, *, scalar: tuple = ENERGY_SERIES, states: tuple = (-1, 0, 1)) -> int:
    """Check the arrays of a saved chain run fit together; return the number of masses.

    Every array is ``(T,)`` (``t`` and ``scalar``) or ``(n, T)``, real and finite; time never runs backwards; a mass'
    state is one of ``states``. A file that breaks one raises :class:`FileError` naming ``path``."""
    t = arrays["t"]
    n = arrays["x"].shape[0] if arrays["x"].ndim == 2 else -1
    for name, array in arrays.items():
        want = (t.size,) if name == "t" or name in scalar else (n, t.size)
        if t.ndim != 1 or array.shape != want or array.dtype.kind not in "biuf":
            raise FileError("path", path, f"is not {kind}", f"array {name!r} has shape {array.shape}, "
                            f"dtype {array.dtype}, for {t.size} samples of {n} masses")
        if not np.all(np.isfinite(array)):  # a chain run never returns non-finite values
            raise FileError("path", path, f"is damaged or not {kind}",
                            f"array {name!r} holds non-finite values (NaN or infinity)")
    if t.size > 1 and np.any(np.diff(t) < 0):
        at = int(np.argmax(np.diff(t) < 0))
        raise FileError("path", path, f"is damaged or not {kind}",
                        f"its time runs backwards (t[{at + 1}] = {t[at + 1]:.6g} s < t[{at}] = {t[at]:.6g} s)")
    if not np.all(np.isin(arrays["state"], states)):
        raise FileError("path", path, f"is damaged or not {kind}",
                        f"array 'state' holds values other than {', '.join(map(str, states))}")
    return n


def describe_error(exc: Exception) -> str:
    """``exc`` in words: our own errors already name the field; others get their type."""
    return str(exc) if isinstance(exc, SceneError) else f"{type(exc).__name__}: {exc}"


def read_intervals(record, n: int, what: str) -> list:
    """Per mass, a list of ordered (start, end) pairs of finite times."""
    if not isinstance(record, list) or len(record) != n:
        raise ValueError(f"{what}: expected {n} lists (one per mass), got {show(record)}")
    out = []
    for per in record:
        pairs = [(float(a), float(b)) for a, b in per]
        if any(not (math.isfinite(a) and math.isfinite(b) and a <= b) for a, b in pairs):
            raise ValueError(f"{what}: an interval that is not a finite (start <= end) pair")
        out.append(pairs)
    return out


def read_record(path, meta: dict, n: int, kind: str) -> dict:
    """The events, stick intervals and chain of a saved chain run's metadata (``meta`` loses them)."""
    try:
        events = [Event(**e) for e in meta.pop("events")]
        intervals = read_intervals(meta.pop("stick_intervals"), n, "stick_intervals")
        c = meta["chain"]
        # a callable belt speed is saved by name only: the chain cannot be rebuilt
        chain = None if isinstance(c, dict) and isinstance(c.get("v_belt"), str) else ChainSpec.from_dict(c)
        if chain is not None and chain.n != n:
            raise ValueError(f"the chain has {chain.n} masses, the arrays {n}")
    except Exception as exc:  # noqa: BLE001 - any malformed record; the file is not ours to trust
        raise FileError("path", path, f"is not {kind}",
                        f"its metadata is invalid: {describe_error(exc)}") from None
    return {"events": events, "stick_intervals": intervals, "chain": chain}


def load(path: str | os.PathLike) -> BeltResult:
    """Read a :class:`BeltResult` written by :meth:`BeltResult.save` (this release's
    :data:`FORMAT`, or the previous release's untagged file).

    A file that is not one (missing, empty, foreign -- an asperity result included --,
    truncated, damaged, arrays that do not fit together, time running backwards, metadata
    that is not a chain's) raises one :class:`~asperity2d._io.FileError` naming ``path``;
    never a KeyError. :func:`asperity2d.load` reads every kind of result by its tag.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file written by ``BeltResult.save``.

    Returns
    -------
    BeltResult

    Raises
    ------
    FileError
        Not such a file, naming ``path``.

    See Also
    --------
    asperity2d.load : reads either kind of result.

    Examples
    --------
    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0)
    >>> path = r.save("chain.npz")
    >>> belt.load(path).events == r.events
    True
    """
    kind = "a belt result file"
    arrays, meta = load_npz(path, BeltResult.SAVED, kind=kind,
                            meta_keys=("chain", "events", "stick_intervals"))
    check_format(path, meta, FORMAT, kind=kind)
    n = check_arrays(path, arrays, kind)
    return BeltResult(**arrays, **read_record(path, meta, n, kind), meta=meta)
