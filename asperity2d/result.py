"""The outcome of one asperity run: SI time series plus the metadata to reproduce it.

A :class:`~asperity2d.Result` is plain NumPy arrays in SI units on a small object that can
save and load itself (one ``.npz`` file holding the arrays and a JSON metadata
record: the scene, the run settings, package and pymunk versions), so a run is
simulated once and then re-analysed or re-rendered any number of times.

The result protocol, shared with :class:`asperity2d.belt.BeltResult`: ``kind``,
``status``, ``message``, ``success``, ``summary()``, ``save(path)`` writing a
format tag (``FORMAT``) and a ``load`` that refuses a malformed or foreign
file with one ``FileError``. :func:`asperity2d.load` reads
either kind by its tag.
"""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ._format import si
from ._io import FileError, atomic_write, check_format, load_mat, load_npz, save_mat, save_npz
from .errors import SceneError
from .scene import Scene

#: Arrays every result carries, in the order they are written to CSV.
SERIES = (
    "t",  # s
    "x",  # slider position, m (its reference point; see Scene docs)
    "v",  # slider horizontal velocity, m/s
    "y",  # slider vertical position, m
    "vy",  # slider vertical velocity, m/s
    "drive_x",  # far end of the drive spring (spring drive) or NaN, m
    "drive_force",  # horizontal force the drive applies to the slider, N
    "normal_force",  # vertical contact force on the slider (upward > 0), N
    "friction_force",  # horizontal contact force resisting +x motion (= -Fx), N
    "tangential_force",  # sum of the contacts' own tangential (Coulomb) forces, N
    "contact_count",  # number of slider contacts at the sample
)
#: Per-asperity arrays, shape (N_lower, T).
LOWER_SERIES = ("lower_dx", "lower_dy", "lower_contact")
#: The format tag of a saved asperity run (version 1: the previous release's untagged files).
FORMAT = "asperity2d.result/2"
#: Statuses of a run that did not do what was asked (``success`` is False): with
#: ``duration=None`` no stop condition (passed, stuck) held before the time limit; a record
#: streamed to disk whose run stopped before it finished (``asperity2d.streamed``).
UNSUCCESSFUL = ("time limit", "interrupted")


@dataclass(eq=False)
class Result:
    """Time series of one run (SI units) and what produced them.

    Attributes
    ----------
    t, x, v, y, vy : ndarray (T,)
        Time (s), slider position (m), horizontal velocity (m/s), vertical
        position (m) and vertical velocity (m/s).
    drive_x : ndarray (T,)
        Position of the moving end of the drive spring (m); NaN for a constant
        force drive.
    drive_force : ndarray (T,)
        Horizontal force the drive applies to the slider (N).
    normal_force, friction_force : ndarray (T,)
        Total contact force of the lower surface on the slider, from the
        contact impulses divided by the step: its upward component, and its
        horizontal component with the sign flipped so that resistance to +x
        motion is positive (N). This is the macroscopic friction: geometric
        interlocking plus Coulomb friction at the flanks.
    tangential_force : ndarray (T,)
        Sum over contacts of the tangential (Coulomb) impulse / dt, projected
        on the +x side of each contact tangent (N).
    contact_count : ndarray (T,)
        Contacts touching the slider at each sample.
    lower_dx, lower_dy : ndarray (N, T)
        Displacement of each lower asperity from its rest position (m).
    lower_contact : ndarray of bool (N, T)
        Which lower asperities touch the slider at each sample. The three have no samples,
        shape (N, 0), when the run kept only the slider (``simulate(..., record_lower=False)``;
        :attr:`lower_recorded`).
    scene : Scene
        The scene that was run.
    meta : dict
        Run settings and diagnostics: ``dt``, ``record_every``, ``status``,
        ``message``, ``max_overlap_fraction``, ``max_track_drift_fraction``,
        ``units`` (internal scale), versions.

    See Also
    --------
    asperity2d.simulate : makes one.
    asperity2d.load : reads a saved one.
    asperity2d.stick_slip_events : what to do with one.
    asperity2d.peak_stick_force
    asperity2d.render

    Examples
    --------
    >>> import asperity2d as a
    >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
    >>> result.status, result.success, len(result)
    ('passed', True, 3731)
    >>> f"slider moved {(result.x[-1] - result.x[0]) * 1e6:.3g} um in {result.t[-1] * 1e9:.3g} ns"
    'slider moved 6.76 um in 412 ns'
    >>> result.lower_dy.shape  # one row per lower asperity
    (4, 3731)

    Saved as ``.npz`` (read back by :func:`asperity2d.load`) or exported for MATLAB:

    >>> result.export("run.mat").name
    'run.mat'
    """

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    y: np.ndarray
    vy: np.ndarray
    drive_x: np.ndarray
    drive_force: np.ndarray
    normal_force: np.ndarray
    friction_force: np.ndarray
    tangential_force: np.ndarray
    contact_count: np.ndarray
    lower_dx: np.ndarray
    lower_dy: np.ndarray
    lower_contact: np.ndarray
    scene: Any
    meta: dict = field(default_factory=dict)

    #: What kind of result this is (the renderers and ``asperity2d analyze`` dispatch on it).
    kind = "asperity"

    # -- the result protocol -----------------------------------------------
    @property
    def status(self) -> str:
        """Why the run ended: ``"duration"``, a stop condition's name (``"passed"``,
        ``"stuck"``, ``"travelled"``, ...), ``"off-surface"`` (the slider left the far end of
        the lower surface) or ``"time limit"``."""
        return self.meta.get("status", "")

    @property
    def message(self) -> str:
        """The reason in words, e.g. "stop condition 'passed' met at t = 1.2e-07 s"."""
        return self.meta.get("message", "")

    @property
    def success(self) -> bool:
        """True unless the run ended without doing what was asked (``UNSUCCESSFUL``: the
        time limit of ``duration=None`` reached before any stop condition). A run that
        diverged raises :class:`~asperity2d.SimulationError` and has no result."""
        return bool(self.status) and self.status not in UNSUCCESSFUL and all(
            c.get("passed", True) for c in self.checks.values())

    @property
    def checks(self) -> dict:
        """The checks the run passed (``meta["checks"]``): the divergence guard, the physical-validity
        checks (step resolution, floor, contacts) and the step size, each ``{"passed", "worst",
        "limit", "what"}``. A run that fails a check raises :class:`~asperity2d.SimulationError`,
        except the step size (``unsafe_dt=True``), which marks the result unsuccessful."""
        checks = self.meta.get("checks")
        return checks if isinstance(checks, dict) else {}

    @property
    def dt(self) -> float:
        """Integration step (s)."""
        return float(self.meta["dt"])

    @property
    def lower_recorded(self) -> bool:
        """True if the lower asperities' arrays hold every sample (False: the run kept only the
        slider's series, ``record_lower=False``)."""
        return np.shape(self.lower_dy)[-1] == len(self.t)

    def require_lower(self, what: str) -> None:
        """Raise ``SceneError`` if :attr:`lower_recorded` is False: ``what`` needs them."""
        if not self.lower_recorded:
            raise SceneError(f"`result` was recorded without the lower asperities (record_lower=False); "
                             f"{what} needs them: run it again with record_lower=True")

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return (
            f"Result({len(self.t)} samples, t_end={si(self.t[-1] if len(self.t) else 0.0, 's', 4)}, "
            f"status={self.status!r})"
        )

    def _repr_html_(self) -> str:
        """The interactive player of the run (Jupyter shows it; :mod:`asperity2d.renderers.player`)."""
        from ._display import represent

        return represent(self, "html")

    def summary(self) -> dict:
        """A few headline numbers of the run (SI), JSON-ready."""
        return {
            "kind": self.kind,
            "scene": self.scene.name,
            "status": self.status,
            "success": self.success,
            "message": self.message,
            "duration_s": float(self.t[-1]) if len(self.t) else 0.0,
            "samples": int(len(self.t)),
            "distance_m": float(self.x[-1] - self.x[0]) if len(self.x) else 0.0,
            "peak_drive_force_N": float(np.max(self.drive_force)) if len(self.t) else 0.0,
            "mean_friction_force_N": float(np.mean(self.friction_force)) if len(self.t) else 0.0,
            "mean_normal_force_N": float(np.mean(self.normal_force)) if len(self.t) else 0.0,
            "max_overlap_fraction": self.meta.get("max_overlap_fraction"),
            "dt_s": self.meta.get("dt"),
            "checks": {name: "passed" if c.get("passed", True) else f"failed ({c.get('what', '')})"
                       for name, c in self.checks.items() if isinstance(c, dict)},
        }

    # -- persistence -------------------------------------------------------
    def save(self, path: str | os.PathLike) -> Path:
        """Write the result to ``path`` (``.npz``) atomically and return the path.

        The file holds every array plus a ``metadata`` entry: a JSON record of
        the scene, the run settings and the package / pymunk versions, tagged
        ``FORMAT``.
        """
        meta = {**self.meta, "scene": self.scene.to_dict()}
        return save_npz(path, {name: getattr(self, name) for name in SERIES + LOWER_SERIES}, meta,
                        format=FORMAT)

    def export(self, path: str | os.PathLike) -> Path:
        """Export the slider time series as ``.csv`` or MATLAB ``.mat`` (by extension).

        ``.mat`` holds every series of :class:`~asperity2d.Result` (SI; ``load("run.mat")`` in MATLAB gives
        row vectors ``t``, ``x``, ``drive_force``, ... and the ``lower_*`` matrices, ``lower_contact``
        a ``logical`` matrix) and a ``metadata`` JSON string; ``asperity2d.result.read_mat`` reads it back in Python
        with ``lower_contact`` as ``bool`` (``scipy.io.loadmat`` alone gives ``uint8``); ``.csv`` the slider's eleven series, one column each, with a
        header line.

        Parameters
        ----------
        path : str or os.PathLike
            Ending in ``.mat`` or ``.csv``.

        Returns
        -------
        pathlib.Path
            The path written (atomically).

        Raises
        ------
        SceneError
            Another extension.

        Examples
        --------
        >>> import scipy.io
        >>> import asperity2d as a
        >>> result = a.simulate(a.make_scene(lower_count=4, upper_count=2))
        >>> path = result.export("run.mat")
        >>> scipy.io.loadmat(path)["drive_force"].shape
        (1, 3731)
        >>> read_mat(path)["lower_contact"].dtype
        dtype('bool')
        """
        path = Path(path)
        suffix = path.suffix.lower()
        if suffix == ".csv":
            table = np.column_stack([np.asarray(getattr(self, n), dtype=float) for n in SERIES])
            header = ",".join(SERIES)

            def write(fh):
                np.savetxt(fh, table, delimiter=",", header=header, comments="", fmt="%.17g")

            return atomic_write(path, write)
        if suffix == ".mat":
            data = {n: np.asarray(getattr(self, n)) for n in SERIES + LOWER_SERIES}
            data["metadata"] = json.dumps(self.meta, sort_keys=True, default=str)
            return save_mat(path, data)
        raise SceneError(f"`path` must end in .csv or .mat, got {str(path)!r}")


def read_mat(path: str | os.PathLike) -> dict:
    """Read a ``.mat`` file written by :meth:`Result.export` (or a belt result's): name -> array.

    MATLAB ``logical`` arrays (``lower_contact``) come back as ``bool``, where ``scipy.io.loadmat``
    alone gives ``uint8``; series are (1, T) or (n, T) as MATLAB holds them, ``metadata`` a
    one-element string array (JSON).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.mat`` file.

    Returns
    -------
    dict
        Variable name -> NumPy array (SciPy's ``__header__`` keys dropped).

    Raises
    ------
    FileError
        A missing or unreadable file, naming ``path``.

    Examples
    --------
    >>> import asperity2d as a
    >>> from asperity2d.result import read_mat
    >>> data = read_mat(a.simulate(a.make_scene(lower_count=4, upper_count=2)).export("run.mat"))
    >>> data["lower_contact"].dtype, data["lower_contact"].shape
    (dtype('bool'), (4, 3731))
    """
    return load_mat(path)


def load(path: str | os.PathLike) -> Result:
    """Read a :class:`~asperity2d.Result` written by :meth:`Result.save` (this release's :data:`FORMAT`, or
    the previous release's untagged file).

    A file that is not one (missing, empty, foreign -- a belt result included --, truncated,
    damaged, or with arrays or a scene record that do not fit together) raises one
    ``FileError`` (a ``SceneError``) naming ``path``.
    :func:`asperity2d.load` reads either kind of result.
    """
    kind = "an asperity2d result file"
    arrays, meta = load_npz(path, SERIES + LOWER_SERIES, kind=kind, meta_keys=("scene",))
    check_format(path, meta, FORMAT, kind=kind)
    samples = len(arrays["t"]) if arrays["t"].ndim == 1 else -1
    lower = samples if meta.get("record_lower", True) else 0
    for name in SERIES + LOWER_SERIES:
        shape = arrays[name].shape
        if (shape[-1:] != ((lower if name in LOWER_SERIES else samples),)
                or len(shape) != (2 if name in LOWER_SERIES else 1)
                or arrays[name].dtype.kind not in "biuf"):
            raise FileError("path", path, f"is not {kind}", f"array {name!r} has shape {shape}, "
                            f"dtype {arrays[name].dtype}, for {samples} samples")
        # a run that went non-finite raises instead of returning: such a file was not written by
        # Result.save (the drive's far end is NaN for a constant force, by design)
        if name != "drive_x" and not np.all(np.isfinite(arrays[name])):
            raise FileError("path", path, f"is damaged or not {kind}",
                            f"array {name!r} holds non-finite values (NaN or infinity)")
    t = arrays["t"]
    if t.size > 1 and np.any(np.diff(t) < 0):
        at = int(np.argmax(np.diff(t) < 0))
        raise FileError("path", path, f"is damaged or not {kind}",
                        f"its time runs backwards (t[{at + 1}] = {t[at + 1]:.6g} s < t[{at}] = {t[at]:.6g} s)")
    counts = arrays["contact_count"]
    if np.any(counts < 0) or np.any(counts != np.floor(counts)):
        raise FileError("path", path, f"is damaged or not {kind}",
                        "array 'contact_count' holds negative or fractional counts")
    try:
        scene = Scene.from_dict(meta.pop("scene"))
    except Exception as exc:  # noqa: BLE001 - any malformed record; the file is not ours to trust
        raise FileError("path", path, f"is not {kind}", f"its scene record is invalid: {exc}") from None
    rows = {arrays[name].shape[0] for name in LOWER_SERIES}
    if rows != {scene.lower.count}:
        raise FileError("path", path, f"is not {kind}", f"its lower arrays have {sorted(rows)} rows for "
                        f"the scene's {scene.lower.count} lower asperities")
    return Result(**arrays, scene=scene, meta=meta)
