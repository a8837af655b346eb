"""Scene specification: frozen, validated dataclasses in SI units.

A :class:`~asperity2d.Scene` is pure data; it round-trips through plain dicts (JSON,
TOML). :data:`OOTEN_DEFAULTS` holds Ooten's fixed track (the Working Model
set-up of E. Ooten's thesis, see :data:`OOTEN_PARAMETERS`), the defaults of
both these dataclasses and :func:`asperity2d.make_scene` (in
:mod:`asperity2d.builders`), so ``Scene()`` and ``make_scene()`` build the
same scene. Nothing here touches pymunk.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ._format import si
from ._inputs import (check_choice, check_finite, check_nonnegative, check_positive, check_text,
                        per_item, show)
from .errors import SceneError
from .contact_laws import DEFAULT_CONTACT_LAW, check_law_params, contact_law
from .geometry import ExplicitSpacing, Profile, RandomSpacing, RegularSpacing, Spacing
from .shapes import Shapes, SurfaceGeometry, check_substrate

TRACKS = ("free", "fixed")
#: How far (fraction of the slider's tip depth) a slider lying on the guard floor still reaches
#: above the lower asperities' bases (:attr:`Scene.floor`): well above the collision slop (1e-3
#: base) and below every free slider's tips in ordinary contact (on Ooten's random spacing
#: the deepest tip in a valley, 0.25 um plus the springs' give, stays above -0.4 um).
FLOOR_OVERLAP = 0.1

@dataclass(frozen=True)
class Parameter:
    """One keyword of :func:`asperity2d.make_scene`: its default, SI unit and meaning.

    The records are the single source of the defaults: :data:`OOTEN_DEFAULTS`
    and :data:`asperity2d.builders.DEFAULTS` are built from them, and the
    documentation's parameter table is generated from them.

    Parameters
    ----------
    name : str
        The keyword, as ``make_scene`` and a TOML scene spell it.
    default : object
        Its default value (``None``: derived from other parameters, as
        ``meaning`` says).
    unit : str
        The SI unit of the value; ``"1"`` for a pure number, ``"-"`` for a
        choice, a text, a flag or a file.
    meaning : str
        What it is, in a sentence.
    """

    name: str
    default: object
    unit: str
    meaning: str


#: Ooten's fixed track: the Working Model set-up of E. Ooten's thesis (*Precision Motion Control
#: at Low Velocities in the Presence of Friction*, Texas A&M, 1997-98; its figures 5-8 and Table
#: 1): 45° full triangles on a 1 µm base, steel asperity mass and stiffness, lightly damped
#: tracks (figure 8), the slider on a fixed-height horizontal track ("the top surface was
#: constrained to move on a horizontal track") with its tips a quarter of the asperity height
#: into the lower surface, pulled through a spring. The drive speed is the quasi-static limit at
#: this scale (see :mod:`asperity2d.experiments.quasistatic`). These are the defaults of the
#: dataclasses below and of :func:`asperity2d.make_scene`.
OOTEN_PARAMETERS = (
    Parameter("base", 1e-6, "m", "base width of every triangular asperity (Ooten's Table 1)"),
    Parameter("flank_angle", 45.0, "°", "flank angle of the triangles above the horizontal "
              "(sets their height on the given base; give `height` instead to set it directly)"),
    Parameter("lower_count", 16, "1", "number of lower asperities, each on its own vertical "
              "spring-damper track"),
    Parameter("upper_count", 4, "1", "number of asperities (tips) the slider carries"),
    Parameter("pitch", 1.25e-6, "m", "centre-to-centre spacing of the asperities on both surfaces "
              "(the mean spacing when random)"),
    Parameter("mass", 2.88e-16, "kg", "mass of each lower asperity (Ooten's Table 1, steel); one "
              "value or one per asperity"),
    Parameter("stiffness", 37_200.0, "N/m", "stiffness of each lower asperity's vertical track "
              "spring (Ooten's Table 1, steel); one value or one per asperity"),
    Parameter("damping_ratio", 0.1, "1", "damping of each lower track as a fraction of its "
              "critical damping 2√(k m) (Ooten's figure 8 dampers)"),
    Parameter("slider_mass", 2.88e-15, "kg", "mass of the slider with all its tips"),
    Parameter("track", "fixed", "-", '"fixed": the slider runs at a fixed height (Ooten\'s fixed '
              'track); "free": it rides the surface pressed down by `normal_load` (the free slider '
              'under a load)'),
    Parameter("normal_load", 0.01, "N", "downward load on the slider (used with `track=\"free\"`)"),
    Parameter("mu_static", 0.3, "1", "static friction coefficient of every asperity contact"),
    Parameter("drive_stiffness", 3_720.0, "N/m", "stiffness of the drive spring (spring drive)"),
    Parameter("drive_velocity", 20.0, "m/s", "speed of the drive spring's far end (spring drive): "
              "1.8e-3 of ω × base, the quasi-static limit at this scale"),
    Parameter("drive_force", 0.02, "N", "the constant horizontal force on the slider "
              '(`drive="force"`)'),
)
#: Ooten's fixed track as a dict: parameter name -> default (from :data:`OOTEN_PARAMETERS`).
OOTEN_DEFAULTS = {p.name: p.default for p in OOTEN_PARAMETERS}


_FULL = Profile.from_angle("full", base=OOTEN_DEFAULTS["base"], flank_angle=OOTEN_DEFAULTS["flank_angle"])


def kinetic_default(mu_static: float) -> float:
    """The default kinetic coefficient: two thirds of the static one (0.2 for 0.3)."""
    return float(f"{2.0 * mu_static / 3.0:.12g}")


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

    Each field is one of :func:`~asperity2d.make_scene`'s keywords (``upper_count``, ``slider_mass``,
    ``track``, ``normal_load``, ``interference``, ...).

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

    def __post_init__(self):
        self._check_shapes()
        object.__setattr__(self, "mass", check_positive("slider_mass", self.mass))
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


@dataclass(frozen=True)
class Scene:
    """A complete asperity contact scene (SI units throughout).

    Frozen: change a part with :func:`dataclasses.replace`. :func:`~asperity2d.make_scene` builds one
    from named parameters; this class is for changing one part of a built scene.

    Parameters
    ----------
    lower : LowerSurface
        The lower asperities on their tracks.
    slider : Slider
        The upper body and its asperities.
    drive : SpringDrive or ConstantForce
        What pulls the slider.
    contact : Contact
        Friction at the asperity contacts.
    gravity : float, default 0.0
        Downward acceleration (m/s^2), >= 0.
    name : str, default ""
        A label (``make_scene`` names it by its parameters).

    See Also
    --------
    asperity2d.make_scene, asperity2d.simulate

    Examples
    --------
    >>> import dataclasses
    >>> import asperity2d as a
    >>> scene = a.make_scene(lower_count=4, upper_count=2)
    >>> scene.name
    'regular-full-spring-fixed-seed0'
    >>> pushed = dataclasses.replace(scene, drive=a.ConstantForce(0.01))
    >>> pushed.drive
    ConstantForce(force=0.01)
    """

    lower: LowerSurface = field(default_factory=LowerSurface)
    slider: Slider = field(default_factory=Slider)
    drive: Drive = field(default_factory=SpringDrive)
    contact: Contact = field(default_factory=Contact)
    gravity: float = 0.0
    name: str = ""

    def __post_init__(self):
        object.__setattr__(self, "gravity", check_nonnegative("gravity", self.gravity))
        check_text("name", self.name)
        for attr, kind in (("lower", LowerSurface), ("slider", Slider), ("contact", Contact)):
            if not isinstance(getattr(self, attr), kind):
                raise SceneError(f"`{attr}` must be a {kind.__name__}, got {show(getattr(self, attr))}")
        if not isinstance(self.drive, (ConstantForce, SpringDrive)):
            raise SceneError(f"`drive` must be a SpringDrive or ConstantForce, got {show(self.drive)}")
        if self.slider.track == "free" and self.slider.normal_load == 0 and self.gravity == 0:
            raise SceneError("`normal_load` must be > 0 for a free slider when `gravity` is 0")
        if self.slider.track == "fixed":
            # Measured from the highest lower tip; it must not reach that asperity's base.
            if self.lower.shapes is None:
                height, what = self.lower.profile.height, "the lower asperity height"
            else:
                i = int(np.argmax(self.lower.shapes.summits))
                height, what = self.lower.shapes.heights[i], f"the height of the highest lower asperity ({i})"
            if self.slider.interference >= height:
                raise SceneError(
                    f"`interference` ({self.slider.interference:g} m) must be smaller than {what} "
                    f"({height:g} m): the tips would reach the base")
            if self.lower.substrate:
                level = self.lower.top - self.slider.interference
                highest = max(z for line in self.lower.substrate for _, z in line)
                if highest >= level:
                    raise SceneError(
                        f"`interference` ({self.slider.interference:g} m) puts the fixed track's tips at "
                        f"{level:g} m, at or below the profile's rigid valley floor ({highest:g} m): the "
                        "slider would jam; use a smaller `interference`")

    # -- display -------------------------------------------------------------
    def __repr__(self) -> str:
        """One readable line (``Scene('name', 16 lower full triangles 1 µm base, ...)``); the full
        parameters are in ``to_dict()``."""
        return f"Scene({self.name!r}, {describe(self)})" if self.name else f"Scene({describe(self)})"

    def _repr_svg_(self) -> str:
        """The scene at rest as an SVG drawing (Jupyter shows it)."""
        from ._display import represent

        return represent(self, "svg")

    # -- derived quantities --------------------------------------------------
    @property
    def base(self) -> float:
        return self.lower.profile.base

    @property
    def floor(self) -> float:
        """Height of the engine's guard floor (m): the lower surface's (``travel_down`` below its
        lowest base level), raised where needed so that a slider lying on it still reaches
        :data:`~asperity2d.scene.FLOOR_OVERLAP` of its tip depth above every lower asperity's base level.

        At ``travel_down`` = the asperity height a slider resting on the floor had its top
        exactly at the base level: it slid beneath the asperities untouched (one lower asperity
        and a free slider: the tip slid down the front flank and passed underneath at a
        quarter of the wedge law). Raised, such a slider meets the asperity flank to flank and
        must climb it. A profile's rigid valleys (``substrate``) are the surface between its
        asperities and keep the lower surface's floor.
        """
        floor = self.lower.floor
        if self.lower.substrate:
            return floor
        top_of_bases = max(self.lower.shape_set().levels)
        return max(floor, top_of_bases - (1.0 - FLOOR_OVERLAP) * self.slider.depth)

    def natural_frequencies(self) -> dict[str, float]:
        """Angular natural frequencies (rad/s) of the scene's spring-mass pairs (inf where a
        ratio overflows: ``Units`` refuses those scenes)."""
        k, m = np.asarray(self.lower.stiffness), np.asarray(self.lower.mass)
        with np.errstate(over="ignore", divide="ignore"):
            freqs = {"lower": float(np.max(np.sqrt(k / m)))}
        if self.lower.is_lattice:
            # Gershgorin bound on the lattice's highest horizontal mode, in O(n) memory
            row = gershgorin_rows(self.lower.lateral_stiffness if self.lower.is_lattice else ())
            freqs["lattice"] = float(np.max(np.sqrt(row / m)))
        if isinstance(self.drive, SpringDrive):
            freqs["drive"] = math.sqrt(self.drive.stiffness / self.slider.mass)
        return freqs

    def shortest_period(self) -> float:
        """Shortest natural period T = 2 pi / omega_max (s); dt defaults to T/50."""
        return 2.0 * math.pi / max(self.natural_frequencies().values())

    def slowest_period(self) -> float:
        """Longest spring-mass period in the scene (s), including the slider on one lower spring."""
        k, m = np.asarray(self.lower.stiffness), np.asarray(self.lower.mass)
        omegas = list(np.sqrt(k / m)) + [math.sqrt(float(np.min(k)) / self.slider.mass)]
        if isinstance(self.drive, SpringDrive):
            omegas.append(math.sqrt(self.drive.stiffness / self.slider.mass))
        return 2.0 * math.pi / min(omegas)

    def replace(self, **changes) -> "Scene":
        return dataclasses.replace(self, **changes)

    # -- serialisation -------------------------------------------------------
    def to_dict(self) -> dict:
        return _to_plain(self)

    @classmethod
    def from_dict(cls, data: dict) -> "Scene":
        """The scene ``to_dict()`` wrote; a record that is not a scene's raises SceneError."""
        if not isinstance(data, dict) or data.get("type") != cls.__name__:
            raise SceneError(f"`scene` must be a scene record (a table with type = {cls.__name__!r}), "
                             f"got {type(data).__name__}" + (f" of type {data.get('type')!r}"
                                                             if isinstance(data, dict) else ""))
        try:
            return _from_plain(data)
        except TypeError as exc:  # a missing or unknown field of a component
            raise SceneError(f"`scene` record does not fit: {exc}") from None

    def to_toml(self, path, *, run: dict | None = None):
        """Write the whole scene as a TOML scene file (``asperity2d run FILE`` runs it, bit for
        bit as :func:`~asperity2d.simulate` runs this scene); ``run`` is its ``[run]`` table
        (``duration`` in s). Every number is written exactly (shortest round-trip text); a
        field left at None is left out (it reads back as its default). Returns the path."""
        from ._io import atomic_write_text, toml_text

        tables = {"format": TOML_FORMAT, **({"run": dict(run)} if run else {}), "spec": _drop_none(self.to_dict())}
        return atomic_write_text(path, toml_text(tables, header="asperity2d scene, written by Scene.to_toml"))

    @classmethod
    def from_toml(cls, path) -> "Scene":
        """The scene of a TOML file written by :meth:`to_toml` (``SceneError`` if it is not one;
        a file of ``make_scene`` arguments is read by ``asperity2d.scene_io.read_scene``)."""
        from ._io import read_toml

        data = read_toml("path", path)
        return spec_from_toml(data, path)


#: The format tag of a whole-scene TOML file (:meth:`Scene.to_toml`).
TOML_FORMAT = "asperity2d.scene/1"


def spec_from_toml(data: dict, path) -> Scene:
    """The :class:`Scene` of a parsed whole-scene TOML document (``format``, ``spec``, ``run``)."""
    if data.get("format") != TOML_FORMAT or not isinstance(data.get("spec"), dict):
        raise SceneError(f"`path` {str(path)!r} is not a scene file written by Scene.to_toml (format "
                         f"{TOML_FORMAT!r} and a [spec] table)")
    extra = sorted(set(data) - {"format", "spec", "run"})
    if extra:
        raise SceneError(f"`{extra[0]}` in {str(path)!r} is not part of a scene file (format, [run], [spec])")
    try:
        scene = _from_plain(data["spec"])
    except TypeError as exc:  # a field the component does not have
        raise SceneError(f"`spec` in {str(path)!r} is invalid: {exc}") from None
    if not isinstance(scene, Scene):
        raise SceneError(f"`spec` in {str(path)!r} must describe a Scene, got {type(scene).__name__}")
    return scene


def _drop_none(data):
    """``data`` without the None fields (TOML has no null; each such field defaults to None)."""
    if isinstance(data, dict):
        return {k: _drop_none(v) for k, v in data.items() if v is not None}
    if isinstance(data, list):
        if any(v is None for v in data):
            raise SceneError("a scene with None inside a list cannot be written as TOML")
        return [_drop_none(v) for v in data]
    return data


_KINDS = {"full": "full triangles", "half": "half triangles", "flat": "flat blocks"}


def _si(value: float, unit: str) -> str:
    return si(value, unit, trim=True)


def _span(values, unit: str) -> str:
    lo, hi = float(np.min(values)), float(np.max(values))
    return _si(lo, unit) if math.isclose(lo, hi, rel_tol=1e-9) else f"{_si(lo, unit)}–{_si(hi, unit)}"


def describe(scene: Scene) -> str:
    """A one-line, plain-words summary of ``scene``: surfaces, slider, drive (SI prefixes)."""
    lower, slider, drive = scene.lower, scene.slider, scene.drive
    kind = _KINDS.get(lower.profile.kind, lower.profile.kind)
    text = f"{lower.count} lower {kind} {_si(lower.profile.base, 'm')} base"
    if lower.shapes is not None:
        text = (f"{lower.count} lower {kind}, bases {_span(lower.shape_set().bases, 'm')}, "
                f"heights {_span(lower.heights(), 'm')}")
    spacing = lower.spacing
    if isinstance(spacing, RegularSpacing):
        text += f", pitch {_si(spacing.pitch, 'm')} regular"
    elif isinstance(spacing, RandomSpacing):
        text += f", mean pitch {_si(spacing.mean_pitch, 'm')} random"
    else:
        text += f", mean pitch {_si(spacing.mean_pitch, 'm')}"
    if lower.substrate:
        text += " on a rigid substrate"
    if lower.is_lattice:
        text += ", joined by lateral springs"
    text += f"; slider {slider.count} tip{'s' if slider.count != 1 else ''}"
    if slider.track == "fixed":
        text += f" on a fixed track ({_si(slider.interference, 'm')} interference)"
    else:
        text += f", free under {_si(slider.normal_load, 'N')}"
    if isinstance(drive, SpringDrive):
        text += f"; spring drive {_si(drive.stiffness, 'N/m')} at {_si(drive.velocity, 'm/s')}"
    else:
        text += f"; constant force {_si(drive.force, 'N')}"
    return text


_TYPES = {c.__name__: c for c in (Scene, LowerSurface, Slider, ConstantForce, SpringDrive,
                                  Contact, Profile, RegularSpacing, RandomSpacing, ExplicitSpacing,
                                  Shapes)}


def _to_plain(obj):
    if dataclasses.is_dataclass(obj):
        out = {"type": type(obj).__name__}
        for f in dataclasses.fields(obj):
            if isinstance(obj, Contact) and f.name == "law" and obj.law == DEFAULT_CONTACT_LAW:
                continue  # the default law is left out: saved scenes read as they did before it was named
            if isinstance(obj, Contact) and f.name == "law_params":
                if obj.law_params:  # a TOML table of the law's parameters (none: left out, as above)
                    out[f.name] = dict(obj.law_params)
                continue
            out[f.name] = _to_plain(getattr(obj, f.name))
        return out
    if isinstance(obj, tuple):
        return [_to_plain(v) for v in obj]
    return obj


def _from_plain(data):
    if isinstance(data, dict) and "type" in data:
        cls = _TYPES.get(data["type"])
        if cls is None:
            raise SceneError(f"unknown scene component type `{data['type']}`")
        kwargs = {k: _from_plain(v) for k, v in data.items() if k != "type"}
        return cls(**kwargs)
    if isinstance(data, list):
        return tuple(_from_plain(v) for v in data)
    return data
