"""Building an asperity scene's pymunk space (part of the adapter, :mod:`asperity2d.engine`).

Mixed into :class:`asperity2d.engine.asperity.Engine`, which sets ``scene``,
``units``, ``space`` and ``_error_bias`` first. Bodies, in internal units
(DESIGN.md section 5):

* each lower asperity is ``Body(m, inf)`` on a vertical ``GrooveJoint`` (its
  track) with a vertical ``DampedSpring`` to ground; in the MATLAB lattice the
  groove is left out and horizontal ``DampedSpring`` links join the peaks;
* the slider is one ``Body(M, inf)`` carrying every upper triangle, on a
  horizontal groove (fixed track) or free vertically;
* a static floor at the bottom of the tracks, touching only the slider.
"""

from __future__ import annotations

import math

import numpy as np
import pymunk
from pymunk import batch

from .contacts import _FLOOR, _LOWER, _SLIDER

_SPRING_REST = 100.0  # rest length of the vertical track springs (internal units)


class SpaceBuilder:
    """Adds the lower surface, the slider and the floor to ``self.space``."""

    def _build_lower(self):
        lower, u, space = self.scene.lower, self.units, self.space
        verts = [(x / u.length, y / u.length) for x, y in lower.profile.vertices(upper=False)]
        self.lower_x0 = lower.centers() / u.length
        self.lower_apex_x = self.lower_x0 + lower.profile.apex_offset(upper=False) / u.length
        self.lower_height = lower.profile.height / u.length
        down, up = lower.travel_down / u.length, lower.travel_up / u.length
        self.lower_bodies = []
        flt = pymunk.ShapeFilter(categories=_LOWER, mask=_SLIDER)
        self.tracked = not lower.is_lattice
        for x0, m, k, c in zip(self.lower_x0, lower.mass, lower.stiffness, lower.damping):
            body = pymunk.Body(m / u.mass, math.inf)
            body.position = (x0, 0.0)
            shape = pymunk.Poly(body, verts)
            shape.filter, shape.collision_type = flt, _LOWER
            # The vertical spring hangs from far below, so it stays vertical
            # (to 1e-2 rad per base of sideways motion in the lattice).
            joints = [pymunk.DampedSpring(space.static_body, body, (x0, -_SPRING_REST), (0.0, 0.0),
                                          _SPRING_REST, k / u.stiffness, c / u.damping)]
            if self.tracked:
                joints.append(pymunk.GrooveJoint(space.static_body, body, (x0, -down), (x0, up),
                                                 (0.0, 0.0)))
            for joint in joints:
                joint.error_bias = self._error_bias
            space.add(body, shape, *joints)
            self.lower_bodies.append(body)
        if lower.is_lattice:
            self._build_lattice()

    def _build_lattice(self):
        """Horizontal springs between neighbouring peaks and to the two walls.

        Each is a ``DampedSpring`` between body centres (rest length: their
        spacing); a wall link anchors to the static body one mean pitch
        outside the end peak. For small displacements they act along x with
        the stiffness matrix :meth:`LowerSurface.lateral_stiffness_matrix`;
        a height difference dy between linked peaks tilts a link by dy/pitch.
        """
        lower, u, space = self.scene.lower, self.units, self.space
        pitch = lower.spacing.mean_pitch / u.length
        x = self.lower_x0
        bodies = self.lower_bodies
        for j, (k, c) in enumerate(zip(lower.lateral_stiffness, lower.lateral_damping)):
            if k == 0 and c == 0:
                continue
            if j == 0:
                link = pymunk.DampedSpring(space.static_body, bodies[0], (x[0] - pitch, 0.0),
                                           (0.0, 0.0), pitch, k / u.stiffness, c / u.damping)
            elif j == len(bodies):
                link = pymunk.DampedSpring(bodies[-1], space.static_body, (0.0, 0.0),
                                           (x[-1] + pitch, 0.0), pitch, k / u.stiffness, c / u.damping)
            else:
                link = pymunk.DampedSpring(bodies[j - 1], bodies[j], (0.0, 0.0), (0.0, 0.0),
                                           x[j] - x[j - 1], k / u.stiffness, c / u.damping)
            space.add(link)

    def _build_slider(self):
        s, u, space = self.scene.slider, self.units, self.space
        lower = self.scene.lower
        h_up = s.profile.height / u.length
        centers = s.centers() / u.length
        self.upper_offsets = centers
        self.upper_apex = centers + s.profile.apex_offset(upper=True) / u.length
        body = pymunk.Body(s.mass / u.mass, math.inf)
        if s.track == "fixed":
            # Start left of the surface: the front asperity's base ends a tenth
            # of a base before the first lower asperity's base begins.
            x0 = (self.lower_x0[0] - lower.profile.base / u.length) - centers[-1] - 0.1
            y0 = self.lower_height - s.interference / u.length + h_up
        else:
            # Start at the beginning of the surface, just clear of the tips:
            # the first upper tip over the first valley (or, with a single lower
            # asperity, over the middle of its front flank); settle() lowers it.
            profile, apex = lower.profile, self.lower_apex_x
            if len(apex) > 1:
                x_tip = 0.5 * (apex[0] + apex[1])
            else:
                run = {"flat": 0.0, "full": 0.5, "half": 1.0}[profile.kind] * profile.base / u.length
                x_tip = apex[0] - 0.5 * run
            x0 = x_tip - self.upper_apex[0]
            y0 = self.lower_height + h_up + 1e-3
        body.position = (x0, y0)
        self.slider_y0 = y0
        flt = pymunk.ShapeFilter(categories=_SLIDER, mask=_LOWER | _FLOOR)
        base_verts = s.profile.vertices(upper=True)
        shapes = []
        for c in centers:
            shape = pymunk.Poly(body, [(c + x / u.length, y / u.length) for x, y in base_verts])
            shape.filter, shape.collision_type = flt, _SLIDER
            shapes.append(shape)
        space.add(body, *shapes)
        if s.track == "fixed":
            groove = pymunk.GrooveJoint(space.static_body, body, (-1e6, y0), (1e6, y0), (0.0, 0.0))
            groove.error_bias = self._error_bias
            space.add(groove)
        self.slider = body

    def _build_floor(self):
        # A guard at the bottom of the lower tracks: upper tips that sink into
        # wide gaps (or half triangles that would fall through) land on it. It
        # is deep enough never to carry load in ordinary contact.
        y = -self.scene.lower.travel_down / self.units.length
        x_lo = self.lower_x0[0] - 1e6
        floor = pymunk.Segment(self.space.static_body, (x_lo, y), (-x_lo, y), 0.0)
        floor.filter = pymunk.ShapeFilter(categories=_FLOOR, mask=_SLIDER)
        floor.collision_type = _FLOOR
        self.space.add(floor)

    def _prepare_batch(self):
        buf = batch.Buffer()
        batch.get_space_bodies(self.space, batch.BodyFields.BODY_ID, buf)
        ids = np.frombuffer(buf.int_buf(), dtype=np.uintp).copy()
        where = {int(i): k for k, i in enumerate(ids)}
        self._slider_row = where[self.slider.id]
        self._slider_id = self.slider.id
        self._lower_rows = np.array([where[b.id] for b in self.lower_bodies], dtype=np.intp)
        rows = self._lower_rows
        if len(rows) and np.array_equal(rows, np.arange(rows[0], rows[0] + len(rows))):
            self._lower_rows = slice(int(rows[0]), int(rows[0]) + len(rows))  # a view, not a copy
        self._lower_index = {b.id: i for i, b in enumerate(self.lower_bodies)}
        self._fric_buf = batch.Buffer()
        self._body_buf = batch.Buffer()
        self._arb_buf = batch.Buffer()
