"""The parts of a scene: the lower surface (:class:`LowerSurface`), the slider (:class:`Slider`),
the drive (:class:`ConstantForce`, :class:`SpringDrive`) and the friction at the contacts
(:class:`Contact`); frozen dataclasses in SI units, each validated when built (a
``SceneError`` naming the parameter). ``asperity2d.scene`` re-exports every name here;
:class:`~asperity2d.Scene` puts them together.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ._inputs import check_choice, check_finite, check_nonnegative, check_positive, per_item, show
from .errors import SceneError
from .contact_laws import DEFAULT_CONTACT_LAW, check_law_params, contact_law
from .geometry import Profile, RegularSpacing, Spacing
from .scene_parameters import OOTEN_DEFAULTS, kinetic_default
from .shapes import Shapes, SurfaceGeometry, check_substrate

TRACKS = ("free", "fixed")

_FULL = Profile.from_angle("full", base=OOTEN_DEFAULTS["base"], flank_angle=OOTEN_DEFAULTS["flank_angle"])


@dataclass(frozen=True)
class LowerSurface(SurfaceGeometry):
    """Asperities on vertical spring-damper tracks (Ooten's figures 5, 7, 8).

    Every asperity has ``profile``'s shape unless ``shapes`` (a
    ``Shapes`` record) gives each its own height,
    flank runs and base level; ``profile`` then still sets the kind and the
    scene's length scale (its base). ``substrate`` (polylines of (x, z)
    points, m, x in the tips' frame, z in the datum) is rigid valley floor
    between asperities, touched only by the slider: a measured profile's
    valleys, so the slider's tips cannot sink below them (see
    ``asperity2d.surface.source``).

    ``mass`` (kg), ``stiffness`` (N/m) and ``damping`` (N s/m) are scalars or
    one value per asperity; they are stored as tuples. ``damping=None`` gives
    each track ``damping_ratio`` of its critical damping 2 sqrt(k m).
    ``travel_down`` and ``travel_up`` (m) limit each track below / above the
    rest position (default: the (tallest) asperity height).

    ``lateral_stiffness`` (N/m) turns the tracks into Ooten's MATLAB
    lattice (its figure 14, equations 9-18): the peaks then move in x and y,
    each held by its vertical spring to ground and joined to its neighbours
    and the two walls by horizontal springs: n + 1 values (wall-peak 1,
    peak 1-peak 2, ..., peak n-wall; a scalar applies to all, 0 removes a
    link), with ``lateral_damping`` (N s/m) in parallel. Track travel limits
    do not apply to the lattice.

    Each field is one of :func:`~asperity2d.make_scene`'s keywords (``lower_count``, ``stiffness``,
    ``mass``, ``damping_ratio``, ...), with its unit and default in the parameter table.

    Raises
    ------
    SceneError
        A value out of range or of the wrong length, named.

    See Also
    --------
    asperity2d.make_scene : builds one from named parameters.
    asperity2d.Slider : the body above it.

    Examples
    --------
    >>> import asperity2d as a
    >>> lower = a.make_scene(lower_count=4, upper_count=2).lower
    >>> lower.count, lower.stiffness[0], lower.mass[0]  # N/m, kg: Ooten's Table 1
    (4, 37200.0, 2.88e-16)
    >>> f"{lower.damping[0]:.3g} N s/m"  # 0.1 of the critical damping 2 sqrt(k m)
    '6.55e-07 N s/m'
    """

    profile: Profile = field(default_factory=lambda: _FULL)
    spacing: Spacing = field(default_factory=lambda: RegularSpacing(
        count=OOTEN_DEFAULTS["lower_count"], pitch=OOTEN_DEFAULTS["pitch"]))
    mass: float | tuple[float, ...] = OOTEN_DEFAULTS["mass"]
    stiffness: float | tuple[float, ...] = OOTEN_DEFAULTS["stiffness"]
    damping: float | tuple[float, ...] | None = None
    damping_ratio: float = OOTEN_DEFAULTS["damping_ratio"]
    travel_down: float | None = None
    travel_up: float | None = None
    lateral_stiffness: float | tuple[float, ...] | None = None
    lateral_damping: float | tuple[float, ...] = 0.0
    shapes: Shapes | None = None
    substrate: tuple | None = None

    def __post_init__(self):
        n = self.spacing.count
        s = object.__setattr__
        self._check_shapes()
        if self.substrate is not None:
            s(self, "substrate", check_substrate(self.substrate))
        s(self, "mass", per_item("mass", self.mass, n, allow_zero=False))
        s(self, "stiffness", per_item("stiffness", self.stiffness, n, allow_zero=False))
        s(self, "damping_ratio", check_nonnegative("damping_ratio", self.damping_ratio))
        if self.damping is None:
            s(self, "damping", tuple(2.0 * self.damping_ratio * math.sqrt(k * m)
                                     for k, m in zip(self.stiffness, self.mass)))
        else:
            s(self, "damping", per_item("damping", self.damping, n, allow_zero=True))
        if self.lateral_stiffness is not None:
            s(self, "lateral_stiffness", per_item("lateral_stiffness", self.lateral_stiffness, n + 1,
                                                  allow_zero=True))
        s(self, "lateral_damping", per_item("lateral_damping", self.lateral_damping, n + 1,
                                            allow_zero=True))
        tallest = self.profile.height if self.shapes is None else max(self.shapes.heights)
        for name in ("travel_down", "travel_up"):
            value = getattr(self, name)
            s(self, name, tallest if value is None else check_positive(name, value))
        self.tips()  # validates that asperities do not overlap

    @property
    def top(self) -> float:
        """Rest height of the highest tip above the datum (m)."""
        return self.profile.height if self.shapes is None else float(np.max(self.shapes.summits))

    @property
    def floor(self) -> float:
        """Height of the engine's guard floor (m): ``travel_down`` below the lowest base level
        (or substrate point), the bottom of the tracks."""
        if self.shapes is None and self.substrate is None:
            return 0.0 - self.travel_down
        lowest = min(self.shape_set().levels)
        if self.substrate:
            lowest = min(lowest, min(z for line in self.substrate for _, z in line))
        return lowest - self.travel_down

    @property
    def is_lattice(self) -> bool:
        """True when the peaks move in x too (Ooten's MATLAB model)."""
        return self.lateral_stiffness is not None

    def tips(self) -> np.ndarray:
        """Tip x positions (m)."""
        return self._tips.copy()

    @cached_property
    def _tips(self) -> np.ndarray:  # drawn once per part (a seeded generator each time: 0.1 ms)
        return self.spacing.tips(*self.runs())

    def lateral_stiffness_matrix(self) -> np.ndarray:
        """The n x n horizontal stiffness matrix K (N/m) of the lattice's springs."""
        n = self.count
        k = np.asarray(self.lateral_stiffness if self.is_lattice else np.zeros(n + 1), dtype=float)
        K = np.diag(k[:-1] + k[1:])
        K -= np.diag(k[1:-1], 1) + np.diag(k[1:-1], -1)
        return K


#: NumPy's pairwise-summation block (``PW_BLOCKSIZE`` in its loops): a row longer than this is
#: summed as two halves, each a multiple of 8 long; a block of 8..128 with eight accumulators.
_PAIRWISE_BLOCK = 128


def _meet(p, q):
    """The level (1, 2, 3) at which accumulators ``p`` and ``q`` (0..7) are first added together in
    NumPy's ``((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))``."""
    return np.where(p // 2 == q // 2, 1, np.where(p // 4 == q // 4, 2, 3))


def gershgorin_rows(links) -> np.ndarray:
    """Row sums of abs(K) for the tridiagonal stiffness matrix K of ``links`` (n + 1 springs, N/m),
    in O(n) memory and time: the Gershgorin bound on its eigenvalues without the n x n matrix.

    Bit-identical to ``np.abs(K).sum(axis=1)`` (the dense computation the scenes' time steps were
    derived from, so no run's numbers change): a row holds three non-zero terms a, b, c (columns
    i - 1, i, i + 1) and zeros, which add exactly, so NumPy's pairwise sum of the row is
    (a + b) + c or a + (b + c) by where the three fall in its summation tree; this function
    walks that tree for every row at once (the test compares it with the dense sum)."""
    links = np.asarray(links, dtype=float).ravel()
    n = links.size - 1
    if n < 1:
        return np.zeros(0)
    a = np.abs(links[:-1])  # |K[i, i - 1]| (none on row 0)
    b = np.abs(links[:-1] + links[1:])  # |K[i, i]|
    c = np.abs(links[1:])  # |K[i, i + 1]| (none on row n - 1)
    a[0] = c[-1] = 0.0  # fresh arrays (np.abs), so the links are not touched
    left_first = np.ones(n, bool)  # (a + b) + c; else a + (b + c)
    stack = [(0, n, np.arange(1, n - 1))]  # (first column, length, rows with all three terms)
    while stack:
        lo, size, rows = stack.pop()
        if rows.size == 0 or size < 8:  # under 8: added in order, (a + b) + c
            continue
        if size > _PAIRWISE_BLOCK:
            half = size // 2
            half -= half % 8
            split = lo + half
            left_first[rows[rows == split]] = False  # {a} + {b, c}
            stack.append((lo, half, rows[rows + 1 < split]))
            stack.append((split, size - half, rows[rows - 1 >= split]))
            continue
        full = lo + size - size % 8  # columns from here on are added one by one after the tree
        r = rows[rows + 1 < full]
        pa, pb, pc = (r - 1 - lo) % 8, (r - lo) % 8, (r + 1 - lo) % 8
        left_first[r] = _meet(pa, pb) < _meet(pb, pc)
    return np.where(left_first, (a + b) + c, a + (b + c))


@dataclass(frozen=True)
class Slider(SurfaceGeometry):
    """The upper body carrying its own asperities, on a horizontal track.

    ``track="fixed"`` (Ooten's Working Model set-up): held at a fixed height
    such that its deepest tip reaches ``interference`` (m, default a quarter
    of its profile's height) below the rest height of the highest lower tip
    (with varied heights: the tallest lower summit; with equal ones, every
    lower tip). ``track="free"``: free to move vertically, pressed down by
    ``normal_load`` (N). ``shapes`` gives each upper asperity its own shape
    (heights and levels measured downwards), as for :class:`~asperity2d.LowerSurface`.
    ``start`` (m) is where its rear tip starts along the track, in the lower surface's x (its
    first tip at 0); None: the set-up's start (left of the surface on the fixed track, its front
    base a tenth of a base clear of the first lower base; over the first valley when free). A
    run that starts the slider engaged (the critical force from rest) starts it over the first
    valley whatever ``start`` says.

    Each field is one of :func:`~asperity2d.make_scene`'s keywords (``upper_count``, ``slider_mass``,
    ``track``, ``normal_load``, ``interference``, ``slider_start``, ...).

    Raises
    ------
    SceneError
        A value out of range, named.

    See Also
    --------
    asperity2d.make_scene : builds one from named parameters.
    asperity2d.LowerSurface : the surface below it.

    Examples
    --------
    >>> import asperity2d as a
    >>> slider = a.make_scene(lower_count=4, upper_count=2, track="free").slider
    >>> slider.count, slider.track, slider.normal_load  # N
    (2, 'free', 0.01)
    >>> f"interference {slider.interference * 1e9:.3g} nm"  # a quarter of the 500 nm height
    'interference 125 nm'
    """

    _upper = True

    profile: Profile = field(default_factory=lambda: _FULL)
    spacing: Spacing = field(default_factory=lambda: RegularSpacing(
        count=OOTEN_DEFAULTS["upper_count"], pitch=OOTEN_DEFAULTS["pitch"]))
    mass: float = OOTEN_DEFAULTS["slider_mass"]
    track: str = OOTEN_DEFAULTS["track"]
    normal_load: float = OOTEN_DEFAULTS["normal_load"]
    interference: float | None = None
    shapes: Shapes | None = None
    start: float | None = None

    def __post_init__(self):
        self._check_shapes()
        object.__setattr__(self, "mass", check_positive("slider_mass", self.mass))
        if self.start is not None:  # where it lies against the surface is the Scene's check
            object.__setattr__(self, "start", check_finite("slider_start", self.start))
        check_choice("track", self.track, TRACKS)
        object.__setattr__(self, "normal_load", check_nonnegative("normal_load", self.normal_load))
        if self.interference is None:
            object.__setattr__(self, "interference", self.profile.height / 4.0)
        else:
            object.__setattr__(self, "interference", check_positive("interference", self.interference))
        self.tips()

    @property
    def depth(self) -> float:
        """How far the deepest tip reaches below the slider's datum (m)."""
        return self.profile.height if self.shapes is None else float(np.max(self.shapes.summits))

    def tips(self) -> np.ndarray:
        """Tip x positions relative to the rearmost tip (m)."""
        return self._tips.copy()

    @cached_property
    def _tips(self) -> np.ndarray:  # drawn once per part (a seeded generator each time: 0.1 ms)
        t = self.spacing.tips(*self.runs())
        return t - t[0]


@dataclass(frozen=True)
class ConstantForce:
    """A constant horizontal force on the slider (N), as in Working Model.

    Parameters
    ----------
    force : float, default 0.02
        The force (N); finite.

    See Also
    --------
    asperity2d.SpringDrive : the other drive.
    asperity2d.make_scene : ``drive="force", drive_force=...``.
    asperity2d.critical_force : the smallest such force that carries the slider across.

    Examples
    --------
    >>> import asperity2d as a
    >>> a.make_scene(drive="force", drive_force=0.01).drive
    ConstantForce(force=0.01)
    """

    force: float = OOTEN_DEFAULTS["drive_force"]

    def __post_init__(self):
        object.__setattr__(self, "force", check_finite("drive_force", self.force))


@dataclass(frozen=True)
class SpringDrive:
    """A spring (N/m) and parallel damper (N s/m) whose far end moves at ``velocity`` (m/s).

    The pull is horizontal. The spring starts stretched to hold ``preload``
    (N, default 0: unstretched).

    Parameters
    ----------
    stiffness : float, default 3720.0
        Spring stiffness (N/m), > 0 (``drive_stiffness`` in :func:`~asperity2d.make_scene`).
    velocity : float, default 20.0
        Speed of the spring's far end (m/s), > 0 (``drive_velocity``).
    damping : float, default 0.0
        Parallel damper (N s/m), >= 0 (``drive_damping``).
    preload : float, default 0.0
        Initial spring force (N) (``drive_preload``).

    See Also
    --------
    asperity2d.ConstantForce : the other drive.
    asperity2d.stick_slip_events : what a spring drive makes.

    Examples
    --------
    >>> import asperity2d as a
    >>> a.make_scene().drive
    SpringDrive(stiffness=3720.0, velocity=20.0, damping=0.0, preload=0.0)
    >>> a.SpringDrive(stiffness=-1.0)
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `drive_stiffness` must be > 0, got -1.0
    """

    stiffness: float = OOTEN_DEFAULTS["drive_stiffness"]
    velocity: float = OOTEN_DEFAULTS["drive_velocity"]
    damping: float = 0.0
    preload: float = 0.0

    def __post_init__(self):
        s = object.__setattr__
        s(self, "stiffness", check_positive("drive_stiffness", self.stiffness))
        s(self, "velocity", check_positive("drive_velocity", self.velocity))
        s(self, "damping", check_nonnegative("drive_damping", self.damping))
        s(self, "preload", check_finite("drive_preload", self.preload))


Drive = ConstantForce | SpringDrive


@dataclass(frozen=True)
class Contact:
    """Friction at the asperity contacts (both surfaces).

    ``mu_static`` >= ``mu_kinetic`` (default: :func:`~asperity2d.scene.kinetic_default`, two
    thirds of ``mu_static``). A stuck contact keeps ``mu_static`` until it has
    slid ``slip_distance`` (m, default 0.1 % of the asperity base) without
    pause, so a micro-slip of a step or two under a suddenly applied load
    (measured: ~2e-5 base) does not drop it to ``mu_kinetic``;
    ``slip_distance=0`` switches on the instantaneous slip speed alone. A
    sliding contact sticks again when its slip speed falls below
    ``stick_speed`` (m/s, default 1e-4 of base x natural frequency).

    ``restitution`` (in [0, 1], pymunk's elasticity) is the ratio of the
    normal relative speed after an impact to that before: 0 (the default) is
    a perfectly inelastic impact, which loses the normal part of the relative
    kinetic energy; 1 loses nothing.

    Parameters
    ----------
    mu_static : float, default 0.3
        Static friction coefficient, >= 0.
    mu_kinetic : float, optional
        Kinetic coefficient, <= ``mu_static`` (default two thirds of it).
    slip_distance : float, optional
        Slip (m) before a stuck contact drops to ``mu_kinetic``.
    stick_speed : float, optional
        Slip speed (m/s) below which a sliding contact sticks again.
    restitution : float, default 0.0
        Normal coefficient of restitution, in [0, 1].
    law : str, default "static-kinetic"
        The per-contact friction law, by its name in :data:`asperity2d.contact_laws.LAWS`:
        ``"static-kinetic"`` (the hold rule), ``"velocity-weakening"``, ``"viscous"``,
        ``"rate-state"`` or one registered from outside.
    law_params : mapping or tuple of (str, float) pairs, default ()
        The law's own parameters in SI (its :attr:`~asperity2d.contact_laws.ContactLaw.parameters`;
        one not given takes its default), held as ``(name, value)`` pairs in the law's order.

    Raises
    ------
    SceneError
        A value out of range, or ``mu_kinetic > mu_static``.

    See Also
    --------
    asperity2d.make_scene : ``mu_static=``, ``mu_kinetic=``, ``restitution=`` build it.

    Examples
    --------
    >>> from asperity2d import Contact
    >>> Contact(mu_static=0.3)
    Contact(mu_static=0.3, mu_kinetic=0.2, slip_distance=None, stick_speed=None, restitution=0.0, law='static-kinetic', law_params=())
    >>> Contact(law="rate-state", law_params={"d_c": 2e-9, "rs_a": 0.01}).law_params
    (('rs_a', 0.01), ('d_c', 2e-09))
    >>> Contact(law="viscous", law_params={"v_s": 1.0})
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `v_s` is not a parameter of the contact law 'viscous' (its parameters: viscosity)
    >>> Contact(mu_static=0.2, mu_kinetic=0.3)
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `mu_static` (0.2) must be >= `mu_kinetic` (0.3)
    """

    mu_static: float = OOTEN_DEFAULTS["mu_static"]
    mu_kinetic: float | None = None
    slip_distance: float | None = None
    stick_speed: float | None = None
    restitution: float = 0.0
    #: The per-contact friction law, by its name in ``asperity2d.contact_laws.LAWS``.
    law: str = DEFAULT_CONTACT_LAW
    #: The law's own parameters (SI), ``(name, value)`` pairs in the law's order.
    law_params: tuple = ()

    def __post_init__(self):
        s = object.__setattr__
        contact_law(self.law)  # a registered asperity-model law (SceneError naming `law` if not)
        s(self, "law_params", check_law_params(self.law, self.law_params))
        s(self, "mu_static", check_nonnegative("mu_static", self.mu_static))
        if self.mu_kinetic is None:
            s(self, "mu_kinetic", kinetic_default(self.mu_static))
        s(self, "mu_kinetic", check_nonnegative("mu_kinetic", self.mu_kinetic))
        if self.mu_kinetic > self.mu_static:
            raise SceneError(f"`mu_static` ({show(self.mu_static)}) must be >= `mu_kinetic` "
                             f"({show(self.mu_kinetic)})")
        if self.slip_distance is not None:
            s(self, "slip_distance", check_nonnegative("slip_distance", self.slip_distance))
        if self.stick_speed is not None:
            s(self, "stick_speed", check_positive("stick_speed", self.stick_speed))
        s(self, "restitution", check_nonnegative("restitution", self.restitution))
        if self.restitution > 1:
            raise SceneError(f"`restitution` must be <= 1, got {self.restitution!r}")


# The parts are documented, reprinted and pickled under the module users import them from,
# ``asperity2d.scene`` (as NumPy's ``set_module`` does): this file is where they are written, not
# their address (the API reference would otherwise describe each twice under this module's name).
for _part in (LowerSurface, Slider, ConstantForce, SpringDrive, Contact):
    _part.__module__ = "asperity2d.scene"
del _part
