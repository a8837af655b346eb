"""Building an asperity scene's pymunk space (part of the adapter, :mod:`asperity2d.engine`).

:func:`build` turns a :class:`~asperity2d.scene.Scene` into a :class:`Layout`: the
``pymunk.Space`` in internal units (:mod:`asperity2d.units`) and where everything
is in it. Bodies (Ooten's figures 5-8, DESIGN.md section 5):

* each lower asperity is ``Body(m, inf)`` (it cannot rotate) on a vertical
  ``GrooveJoint`` (its track, limited to the travel) with a vertical
  ``DampedSpring`` to ground; in the MATLAB lattice the groove is left out
  and horizontal ``DampedSpring`` links join the peaks. The body sits at its
  tip's x and at y = 0 at rest; its polygon is its own shape
  (:meth:`~asperity2d.scene.LowerSurface.outlines`), whose base line lies at
  the asperity's base level, so a body's y is always its displacement from rest;
* the slider is one ``Body(M, inf)`` carrying every upper triangle, on a
  horizontal groove (fixed track) or free vertically;
* a static floor at the bottom of the tracks stops upper tips from falling
  through wide gaps; it touches only the slider; so do the static segments
  of a profile's valleys between its asperities (``LowerSurface.substrate``);
* shape filters keep lower asperities from touching each other.

pymunk's ``DampedSpring`` applies its damping as an exact exponential decay
of the relative velocity, so the track and lattice dampers are stable at any
step; only the drive damper (applied as a force, :mod:`.core`) limits dt.
"""

from __future__ import annotations

import math
import pickle
from dataclasses import dataclass

import numpy as np
import pymunk
from pymunk import batch

from ..units import Units
from .native import free_fast

#: Shape categories (bit masks), also used as collision types.
LOWER, SLIDER, FLOOR = 1, 2, 4
#: Solver settings in internal units (DESIGN.md section 5).
COLLISION_SLOP = 1e-3  # base lengths of overlap left uncorrected
CORRECTION_PER_STEP = 0.1  # fraction of overlap / joint error removed per step
_SPRING_REST = 100.0  # rest length of the vertical track springs (internal units)


def per_step_bias(fraction: float, dt: float) -> float:
    """pymunk bias (error left after one time unit) that removes ``fraction`` per step of ``dt``."""
    return math.pow(1.0 - fraction, 1.0 / dt)


@dataclass
class Layout:
    """A built space and where everything is in it (internal units).

    ``rows`` index the ``n_rows`` rows of ``pymunk.batch.get_space_bodies``
    (the static body has one):
    ``slider_row`` and ``lower_rows`` (a slice when contiguous);
    ``lower_index`` maps a body id (a pointer value) to its lower asperity index.
    ``lower_x0`` / ``lower_apex_x``
    are the rest x of each lower body / apex (the same: bodies sit at their
    tips), ``lower_height`` the rest height of the highest lower tip,
    ``upper_apex`` the apexes' x relative to the slider, ``slider_y0`` its
    starting height.
    """

    space: pymunk.Space
    slider: pymunk.Body
    lower_bodies: list
    lower_shapes: list
    lower_x0: np.ndarray
    lower_apex_x: np.ndarray
    lower_height: float
    upper_apex: np.ndarray
    slider_y0: float
    tracked: bool  # lower asperities on vertical grooves (False: MATLAB lattice)
    fixed_slider: bool
    slider_groove: pymunk.GrooveJoint | None = None  # the fixed track
    slider_y_start: float = 0.0  # where the slider starts (above slider_y0 when lowered onto the surface)
    slider_y_track: float = 0.0  # the fixed track's height now (projection target)
    slider_row: int = 0
    lower_rows: slice | np.ndarray | None = None
    lower_index: dict | None = None
    lower_row_of: list | None = None
    slider_id: int = 0
    masses: np.ndarray | None = None  # per batch row (internal units; 0 for the static body)
    n_rows: int = 0

    def index(self) -> None:
        """Find the batch rows and ids of the bodies (after building or copying)."""
        buf = batch.Buffer()
        batch.get_space_bodies(self.space, batch.BodyFields.BODY_ID, buf)
        ids = np.frombuffer(buf.int_buf(), dtype=np.uintp).copy()
        self.n_rows = len(ids)  # the static body has a row too
        where = {int(i): k for k, i in enumerate(ids)}
        self.slider_row = where[self.slider.id]
        self.slider_id = self.slider.id
        rows = np.array([where[b.id] for b in self.lower_bodies], dtype=np.intp)
        if len(rows) and np.array_equal(rows, np.arange(rows[0], rows[0] + len(rows))):
            self.lower_rows = slice(int(rows[0]), int(rows[0]) + len(rows))  # a view, not a copy
        else:
            self.lower_rows = rows
        self.lower_index = {b.id: i for i, b in enumerate(self.lower_bodies)}
        self.lower_row_of = rows.tolist()  # batch row of each lower asperity
        by_id = {b.id: b for b in self.space.bodies}
        self.masses = np.array([by_id[int(i)].mass if int(i) in by_id else 0.0 for i in ids])

    def snapshot(self) -> bytes:
        """The space pickled (bodies, joints and the contact cache): :meth:`copy` restores it."""
        return pickle.dumps(self.space, protocol=pickle.HIGHEST_PROTOCOL)

    def copy(self, snapshot: bytes | None = None) -> "Layout":
        """An independent copy of the space from ``snapshot`` (default: taken now), with every
        reference re-pointed. Copies of one layout step bit-identically to each other.
        (Unpickling a snapshot is 3.5x cheaper than ``pymunk.Space.copy``'s deep copy.)"""
        space = pickle.loads(self.snapshot() if snapshot is None else snapshot)
        free_fast(space)
        # pymunk copies bodies and shapes in order (new ids): match them by position
        body_at = {id(b): k for k, b in enumerate(self.space.bodies)}
        shape_at = {id(s): k for k, s in enumerate(self.space.shapes)}
        bodies, shapes = list(space.bodies), list(space.shapes)
        groove = None
        if self.slider_groove is not None:
            at = [id(c) for c in self.space.constraints].index(id(self.slider_groove))
            groove = list(space.constraints)[at]
        out = Layout(space=space, slider=bodies[body_at[id(self.slider)]], slider_groove=groove,
                     slider_y_start=self.slider_y_start, slider_y_track=self.slider_y_track,
                     lower_bodies=[bodies[body_at[id(b)]] for b in self.lower_bodies],
                     lower_shapes=[shapes[shape_at[id(s)]] for s in self.lower_shapes],
                     lower_x0=self.lower_x0, lower_apex_x=self.lower_apex_x,
                     lower_height=self.lower_height, upper_apex=self.upper_apex,
                     slider_y0=self.slider_y0, tracked=self.tracked, fixed_slider=self.fixed_slider)
        out.index()
        return out


#: Lower shapes are added to the space's bounding-box tree in runs of this many, in x order
#: within a run (see :func:`insertion_order`).
INSERTION_RUN = 256


def insertion_order(n: int) -> list[int]:
    """The order in which ``n`` lower shapes (in x order) enter the space: runs of
    :data:`INSERTION_RUN` in x order, the runs themselves middle first (the middle run, then
    the middles of the two halves, ...).

    Chipmunk's bounding-box tree places each new leaf by an area heuristic that, for boxes
    added in x order along a line, hangs every new one below the last: the tree becomes a
    chain, and adding (and, while stepping, walking up from a moving leaf) costs its depth.
    A surface added in x order built in O(n^2) (measured: 10,000 asperities 2.2 s, 20,000
    9.3 s, 100,000 about 20 min). Runs added middle first keep the chain within one run
    (depth <= 256 plus the runs' balanced levels): O(n) (100,000 in ~10 s, mostly pymunk's
    own object creation). Up to 256 asperities the order, hence the tree and every result,
    is exactly what it was (the pinned golden scenes are bit-identical)."""
    runs = [(start, min(n, start + INSERTION_RUN)) for start in range(0, n, INSERTION_RUN)]
    order, queue = [], [(0, len(runs))]
    while queue:  # breadth first over the runs, middle first
        lo, hi = queue.pop(0)
        if lo < hi:
            mid = (lo + hi) // 2
            order.append(mid)
            queue += [(lo, mid), (mid + 1, hi)]
    return [i for run in order for i in range(*runs[run])]


def build(scene, units: Units, dt: float, *, iterations: int, friction: float,
          engaged: bool = False) -> Layout:
    """Build ``scene`` in a new space stepped with ``dt`` (internal units).

    ``friction`` is the lower shapes' initial coefficient (the slider's shapes
    have 1.0, so a contact's coefficient is the lower shape's); their
    elasticity is the scene's contact ``restitution`` (the slider's is 1.0).
    A fixed-track slider starts before the surface, or with ``engaged`` over
    it (its rear tip above the first lower valley, like a free slider) with
    its track raised clear of the tips, to be lowered onto the surface by
    ``Engine.settle``.
    """
    space = pymunk.Space(threaded=False)  # threaded stepping is not reproducible
    free_fast(space)  # freed in O(n), not pymunk's O(n^2)
    space.iterations = iterations
    space.gravity = (0.0, -scene.gravity / units.acceleration)
    space.collision_slop = COLLISION_SLOP
    space.collision_bias = per_step_bias(CORRECTION_PER_STEP, dt)
    # Contacts are remembered for one step only: with pymunk's default (3) a contact that
    # touches again within 3 steps of separating reports the impulse remembered from before,
    # which was never applied (with restitution 1, up to ~700 load impulses in the recorded
    # normal force), while its warm start brings nothing a fixed small dt needs.
    space.collision_persistence = 1
    bias = per_step_bias(CORRECTION_PER_STEP, dt)
    lower = _build_lower(space, scene, units, bias, friction)
    slider = _build_slider(space, scene, units, bias, lower, engaged)
    _build_floor(space, scene, units, lower["x0"], friction, slider["extent"])
    layout = Layout(space=space, slider=slider["body"], lower_bodies=lower["bodies"],
                    lower_shapes=lower["shapes"], lower_x0=lower["x0"], lower_apex_x=lower["apex"],
                    lower_height=lower["height"], upper_apex=slider["apex"], slider_y0=slider["y0"],
                    tracked=not scene.lower.is_lattice, fixed_slider=scene.slider.track == "fixed",
                    slider_groove=slider["groove"], slider_y_start=slider["y_start"],
                    slider_y_track=slider["y_start"])
    layout.index()
    return layout


def _build_lower(space, scene, u: Units, bias: float, friction: float) -> dict:
    lower = scene.lower
    x0 = lower.tips() / u.length
    down, up = lower.travel_down / u.length, lower.travel_up / u.length
    flt = pymunk.ShapeFilter(categories=LOWER, mask=SLIDER)
    bodies, shapes = [], []
    for x, outline, m, k, c in zip(x0, lower.outlines(), lower.mass, lower.stiffness, lower.damping):
        body = pymunk.Body(m / u.mass, math.inf)
        body.position = (x, 0.0)
        shape = pymunk.Poly(body, [(vx / u.length, vy / u.length) for vx, vy in outline])
        shape.filter, shape.collision_type, shape.friction = flt, LOWER, friction
        shape.elasticity = scene.contact.restitution  # x the slider's 1.0
        # The vertical spring hangs from far below, so it stays vertical
        # (to 1e-2 rad per base of sideways motion in the lattice).
        joints = [pymunk.DampedSpring(space.static_body, body, (x, -_SPRING_REST), (0.0, 0.0),
                                      _SPRING_REST, k / u.stiffness, c / u.damping)]
        if not lower.is_lattice:
            joints.append(pymunk.GrooveJoint(space.static_body, body, (x, -down), (x, up), (0.0, 0.0)))
        for joint in joints:
            joint.error_bias = bias
        space.add(body, *joints)
        bodies.append(body)
        shapes.append(shape)
    space.add(*(shapes[i] for i in insertion_order(len(shapes))))
    if lower.is_lattice:
        _build_lattice(space, lower, u, x0, bodies)
    left = lower.runs()[0]
    return {"bodies": bodies, "shapes": shapes, "x0": x0, "height": lower.top / u.length,
            "apex": x0, "left": float(np.ravel(left)[0]) / u.length}


def _build_lattice(space, lower, u: Units, x, bodies) -> None:
    """Horizontal springs between neighbouring peaks and to the two walls.

    Each is a ``DampedSpring`` between body centres (rest length: their
    spacing); a wall link anchors to the static body one mean pitch outside
    the end peak. For small displacements they act along x with the stiffness
    matrix :meth:`LowerSurface.lateral_stiffness_matrix`; a height difference
    dy between linked peaks tilts a link by dy/pitch.
    """
    pitch = lower.spacing.mean_pitch / u.length
    for j, (k, c) in enumerate(zip(lower.lateral_stiffness, lower.lateral_damping)):
        if k == 0 and c == 0:
            continue
        k, c = k / u.stiffness, c / u.damping
        if j == 0:
            link = pymunk.DampedSpring(space.static_body, bodies[0], (x[0] - pitch, 0.0), (0.0, 0.0),
                                       pitch, k, c)
        elif j == len(bodies):
            link = pymunk.DampedSpring(bodies[-1], space.static_body, (0.0, 0.0), (x[-1] + pitch, 0.0),
                                       pitch, k, c)
        else:
            link = pymunk.DampedSpring(bodies[j - 1], bodies[j], (0.0, 0.0), (0.0, 0.0),
                                       x[j] - x[j - 1], k, c)
        space.add(link)


def _build_slider(space, scene, u: Units, bias: float, lower: dict, engaged: bool) -> dict:
    s = scene.slider
    h_up = s.depth / u.length  # the deepest tip below the slider's datum
    apex = s.tips() / u.length  # relative to the slider's reference point, the rear tip
    body = pymunk.Body(s.mass / u.mass, math.inf)
    x_lower, apex_lower = lower["x0"], lower["apex"]
    clear = lower["height"] + h_up + 1e-3  # the tips just clear of the lower tips
    if s.track == "fixed" and not engaged:
        # Start left of the surface: the front asperity's base ends a tenth
        # of a base before the first lower asperity's base begins. The deepest
        # upper tip runs `interference` below the highest lower tip.
        right = float(np.ravel(s.runs()[1])[-1]) / u.length
        x0 = x_lower[0] - lower["left"] - right - apex[-1] - 0.1
        y0 = y_start = lower["height"] - s.interference / u.length + h_up
    else:
        # Start at the beginning of the surface, just clear of the tips: the
        # first upper tip over the first valley (or, with a single lower
        # asperity, over the middle of its front flank); settling lowers it.
        if len(apex_lower) > 1:
            x_tip = 0.5 * (apex_lower[0] + apex_lower[1])
        else:
            flat = scene.lower.profile.kind == "flat"
            x_tip = apex_lower[0] - (0.0 if flat else 0.5 * lower["left"])
        x0 = x_tip - apex[0]
        y0 = y_start = clear
        if s.track == "fixed":  # the track's height; the slider starts above it
            y0 = lower["height"] - s.interference / u.length + h_up
    if s.start is not None and not engaged:  # the scene's own start: its rear tip there, at the same height
        x0 = s.start / u.length - float(apex[0])
    body.position = (x0, y_start)
    flt = pymunk.ShapeFilter(categories=SLIDER, mask=LOWER | FLOOR)
    shapes = []
    for c, outline in zip(apex, s.outlines()):
        shape = pymunk.Poly(body, [(c + x / u.length, y / u.length) for x, y in outline])
        shape.filter, shape.collision_type, shape.friction = flt, SLIDER, 1.0
        shape.elasticity = 1.0
        shapes.append(shape)
    space.add(body, *shapes)
    # from the slider's start to its rear tip past the last lower asperity
    extent = (x0, float(x_lower[-1]) + float(apex[-1] - apex[0]) + 1.0)
    groove = None
    if s.track == "fixed":
        lo, hi = _reach(-1e6, 1e6, *extent)
        groove = pymunk.GrooveJoint(space.static_body, body, (lo, y_start), (hi, y_start), (0.0, 0.0))
        groove.error_bias = bias
        space.add(groove)
    return {"body": body, "apex": apex, "y0": y0, "y_start": y_start, "groove": groove, "extent": extent}


#: How far (in bases) the slider's track and the floor reach beyond the scene, at least.
_MARGIN = 1e5


def _reach(lo: float, hi: float, *xs: float) -> tuple[float, float]:
    """The x range (internal units) of the slider's track or the floor: [lo, hi] (the range
    every ordinary scene fits in, kept as it was so those scenes stay bit-identical), widened
    to cover every x in ``xs`` with a margin. (With a pitch 1e6 times the base, a fixed
    [-1e6, 1e6] track snapped a slider that started outside it onto its end at 4e6 bases per
    time unit.)"""
    return min(lo, min(xs) - _MARGIN), max(hi, max(xs) + _MARGIN)


def _build_floor(space, scene, u: Units, x_lower, friction: float, extent: tuple[float, float]) -> None:
    # A guard at the bottom of the lower tracks: upper tips that sink into
    # wide gaps (or half triangles that would fall through) land on it. It
    # is deep enough never to carry load in ordinary contact, and high enough
    # that a slider on it cannot pass beneath a lower asperity (Scene.floor).
    y = scene.floor / u.length
    lo, hi = _reach(float(x_lower[0]) - 1e6, 1e6 - float(x_lower[0]), *extent)
    floor = pymunk.Segment(space.static_body, (lo, y), (hi, y), 0.0)
    segments = [floor]
    # A profile's valleys between lower asperities (rigid substrate, touched by the slider only).
    for line in scene.lower.substrate or ():
        pts = [(vx / u.length, vz / u.length) for vx, vz in line]
        segments += [pymunk.Segment(space.static_body, a, b, 0.0) for a, b in zip(pts[:-1], pts[1:])]
    for segment in segments:
        segment.filter = pymunk.ShapeFilter(categories=FLOOR, mask=SLIDER)
        segment.collision_type, segment.friction = FLOOR, friction
        segment.elasticity = scene.contact.restitution
    space.add(*segments)
