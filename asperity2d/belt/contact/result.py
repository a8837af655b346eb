"""ContactResult: a belt-chain result with the normal degree of freedom (gap, normal force, separations).

A :class:`~.result.BeltResult` (so every tool that reads one -- regimes, cycles,
spectra, sound, plots -- reads this too) with, per mass, the gap ``y`` and its
rate ``vy``, the ``normal_force`` and the exact ``separation_intervals``; ``state``
is 0 stuck, ±1 sliding, 2 separated (:data:`~.normal.SEPARATED`). Its energy book
adds the normal, inclined and contact springs and the work against the load W·y
to the stored energy, and the ``impact_dissipation`` to the losses.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np

from ..._io import FileError, check_format, load_npz
from ..normal import SEPARATED, NormalContact
from .. import result as result_module
from ..result import ENERGY_SERIES, BeltResult, read_intervals, check_arrays, check_books, describe_error, read_record
from ..spec import ContactSpec, link_force

#: per-mass (n, T) and scalar (T,) series a contact result adds to a BeltResult's
CONTACT_SERIES = ("y", "vy", "normal_force")
CONTACT_ENERGY = ("load_energy", "impact_dissipation")
#: The format tag of a saved contact run (version 1: the previous release's untagged files, told
#: apart from a plain chain's by their ``normal`` record).
FORMAT = "asperity2d.belt-contact-result/2"


@dataclass(eq=False)
class ContactResult(BeltResult):
    """Time series of a chain with a normal degree of freedom (SI); see :class:`BeltResult` for the rest.

    Attributes
    ----------
    y, vy : (n, T) gap above the belt surface (m; negative: penetration of a compliant contact)
        and its rate (m/s).
    normal_force : (n, T) contact force pressing each mass off the belt (N, >= 0; 0 when separated).
    load_energy : (T,) Σ W_i·y_i (J), the work done against the weights and preloads.
    impact_dissipation : (T,) cumulative kinetic energy lost in impacts (J).
    separation_intervals : per mass, the (t_open, t_close) intervals (s) out of contact.
    contact : the ``ContactSpec`` (normal parameters and initial gaps).

    See Also
    --------
    asperity2d.belt.NormalContact, asperity2d.belt.simulate_chain, asperity2d.belt.load_contact

    Examples
    --------
    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0,
    ...                         normal=belt.NormalContact(stiffness=1e4, contact_stiffness=1e5))
    >>> r.separation_intervals  # the mass never leaves the belt
    [[]]
    """

    y: np.ndarray = None
    vy: np.ndarray = None
    normal_force: np.ndarray = None
    load_energy: np.ndarray = None
    impact_dissipation: np.ndarray = None
    separation_intervals: list = field(default_factory=list)
    contact: ContactSpec | None = None

    @property
    def stored_energy(self) -> np.ndarray:
        """Kinetic (both directions) + every spring (contact spring included) + load energy (J)."""
        return self.kinetic_energy + self.spring_energy + self.load_energy

    @property
    def initial_energy(self) -> float:
        """Stored energy at t = 0 (J): the first sample's; NaN when the samples start later."""
        return float(self.stored_energy[0]) if self.t.size and self.t[0] == 0 else math.nan

    @property
    def energy_residual(self) -> np.ndarray:
        """(E - E0) - (W_belt - D_friction - D_damper - D_impact) at every sample (J)."""
        return (self.stored_energy - self.initial_energy) - (
            self.belt_work - self.friction_dissipation - self.damper_dissipation - self.impact_dissipation)

    def _energy_parts(self) -> tuple:
        return (self.belt_work, self.friction_dissipation, self.damper_dissipation, self.impact_dissipation,
                self.kinetic_energy, self.spring_energy, self.load_energy)

    def summary(self) -> dict:
        """:meth:`BeltResult.summary` plus the normal contact's record: ``separations`` (how many
        times the masses left the belt) and, per mass, its ``separations`` and ``separated_s``
        (time out of contact, s)."""
        out = super().summary()
        for entry, intervals in zip(out["masses"], self.separation_intervals):
            entry["separations"] = len(intervals)
            entry["separated_s"] = float(sum(b - a for a, b in intervals))
        out["separations"] = sum(len(per) for per in self.separation_intervals)
        return out

    @property
    def separated(self) -> np.ndarray:
        """(n, T) True where a mass is out of contact."""
        return self.state == SEPARATED

    def __repr__(self) -> str:
        opened = sum(len(s) for s in self.separation_intervals)
        return (f"ContactResult(n={self.n}, {self.t.size} samples, t_end={self.t[-1]:.4g} s, "
                f"events={len(self.events)}, separations={opened})")

    # -- persistence: BeltResult's save / export with the contact's arrays and records ---------
    SAVED = BeltResult.SAVED + CONTACT_SERIES + CONTACT_ENERGY
    FORMAT = FORMAT

    def _record(self) -> dict:
        meta = super()._record()
        meta["normal"] = self.contact.to_dict() if self.contact is not None else meta.get("normal")
        meta["separation_intervals"] = [[list(iv) for iv in per] for per in self.separation_intervals]
        return meta


def load_contact(path: str | os.PathLike) -> ContactResult:
    """Read a :class:`ContactResult` written by ``ContactResult.save()`` (this release's
    ``FORMAT``, or the previous release's untagged file), with every array and interval.

    A file that is not one (missing, foreign, a plain belt result, damaged, arrays that do not
    fit together, time running backwards, a malformed chain or normal record) raises one
    ``FileError`` naming ``path``; never a KeyError.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file written by ``ContactResult.save``.

    Returns
    -------
    ContactResult

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
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0,
    ...                         normal=belt.NormalContact(stiffness=1e4, contact_stiffness=1e5))
    >>> belt.load_contact(r.save("contact.npz"))
    ContactResult(n=1, 2006 samples, t_end=2 s, events=5, separations=0)
    """
    kind = "a belt contact result file"
    arrays, meta = load_npz(path, ContactResult.SAVED, kind=kind,
                            meta_keys=("chain", "normal", "events", "stick_intervals", "separation_intervals"))
    check_format(path, meta, FORMAT, kind=kind)
    n = check_arrays(path, arrays, kind, scalar=ENERGY_SERIES + CONTACT_ENERGY, states=(-1, 0, 1, SEPARATED))
    record = read_record(path, meta, n, kind)
    try:
        separations = read_intervals(meta.pop("separation_intervals"), n, "separation_intervals")
        if record["chain"] is None:
            raise ValueError("a contact run's chain has a constant belt speed")
        normal = dict(meta["normal"])
        y0, vy0 = normal.pop("y0"), normal.pop("vy0")
        spec = ContactSpec(record["chain"], NormalContact.from_dict(normal), y0, vy0)
    except Exception as exc:  # noqa: BLE001 - any malformed record; the file is not ours to trust
        raise FileError("path", path, f"is not {kind}",
                        f"its metadata is invalid: {describe_error(exc)}") from None
    return ContactResult(**arrays, **record, meta=meta, separation_intervals=separations, contact=spec)


def load(path: str | os.PathLike) -> BeltResult:
    """Read a saved belt chain of either kind (``asperity2d.belt.load``): a
    :class:`ContactResult` when the file holds a normal contact (its tag, or the previous
    release's ``normal`` record), else a :class:`BeltResult`.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.npz`` file written by ``BeltResult.save`` or ``ContactResult.save``.

    Returns
    -------
    BeltResult or ContactResult
        The kind that was saved, with every array.

    Raises
    ------
    FileError
        Not a saved belt chain, naming ``path``.

    See Also
    --------
    asperity2d.load : reads every kind of result.

    Examples
    --------
    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0,
    ...                         normal=belt.NormalContact(stiffness=1e4, contact_stiffness=1e5))
    >>> type(belt.load(r.save("contact.npz"))).__name__
    'ContactResult'
    """
    _, meta = load_npz(path, (), kind="a belt result file")
    if meta.get("format") == FORMAT or (meta.get("format") is None and "normal" in meta):
        return load_contact(path)
    return result_module.load(path)


def assemble_contact(spec: ContactSpec, raw, meta: dict) -> ContactResult:
    """Build a ContactResult from :class:`~.backend.ContactRun` (adds forces and stored energies)."""
    n, D = spec.n, 2 * spec.n
    Z = raw.Z
    q, qd = Z[:D], Z[D:]
    x, y, v, vy = q[:n], q[n:], qd[:n], qd[n:]
    Ks = spec.stiffness_matrix
    contact = raw.modes != SEPARATED
    spring = 0.5 * np.einsum("it,ij,jt->t", q, Ks, q)
    if not spec.normal.rigid:
        depth = np.where(contact, np.maximum(-y, 0.0), 0.0)
        spring = spring + 0.5 * spec.normal.contact_stiffness * np.sum(depth * depth, axis=0)
    meta = dict(meta)
    meta["chain"] = spec.chain.to_dict()
    meta["normal"] = spec.to_dict()
    result = ContactResult(
        t=raw.t, x=x, v=v, state=np.asarray(raw.modes, dtype=np.int8), friction_force=raw.friction_force,
        spring_force=-(Ks[:n] @ q), damper_force=link_force(spec.chain.c, v),
        belt_work=raw.work[0], friction_dissipation=raw.work[1], damper_dissipation=raw.work[2],
        kinetic_energy=0.5 * (spec.mass_vector[:, None] * qd * qd).sum(axis=0), spring_energy=spring,
        stick_intervals=[[tuple(map(float, iv)) for iv in per] for per in raw.stick_intervals],
        events=list(raw.events), chain=spec.chain, meta=meta,
        y=y, vy=vy, normal_force=raw.normal_force, load_energy=spec.load @ y, impact_dissipation=raw.work[3],
        separation_intervals=[[tuple(map(float, iv)) for iv in per] for per in raw.separation_intervals],
        contact=spec)
    check_books(result)
    return result
