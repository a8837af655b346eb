"""The analysis of a run: stick–slip events, force measures and contact states, pure functions of a Result.

Everything here reads a :class:`~asperity2d.result.Result` and returns plain
data (floats, dicts of arrays, lists of frozen :class:`Event` records); nothing
simulates. Each role lives in its own module, re-exported here so that
``asperity2d.analysis.X`` keeps working for every name it held:

* ``asperity2d.events``: the stick–slip events (:func:`stick_slip_events`, :class:`Event`,
  :func:`event_statistics`, :func:`events_table`, :func:`synthetic_stick_slip`) and how a run
  is segmented;
* ``asperity2d.forces``: the force measures (:func:`breakaway_force`,
  :func:`peak_stick_force`, :func:`mean_stick_force`, :func:`friction_traces`);
* ``asperity2d.contact_states``: separated, sliding, sticking (:func:`contact_states`);
* ``asperity2d.slip_thresholds``: the spring-driven block's cycle in closed form and the
  detector's default thresholds (:func:`spring_block_slip`, :func:`slip_speed_threshold`).
"""

from __future__ import annotations

from .contact_states import ContactStates, contact_states  # noqa: F401
from .events import (EVENT_COLUMNS, Event, _asperity_run, _drive_scales, _merge, _runs,  # noqa: F401
                     _thresholds, event_statistics, events_table, stick_slip_events, synthetic_stick_slip)
from .forces import (_spring_events, breakaway_force, friction_traces, mean_stick_force,  # noqa: F401
                     peak_stick_force)
from .slip_thresholds import (MIN_SLIP_FRACTION, MIN_SLIP_PERIODS, MIN_STICK_PERIODS,  # noqa: F401
                              NO_SLIP_PEAK_FRACTION, SLIP_MARGIN_FRACTION, SLIP_SPEED_FRACTION,
                              STICK_SPEED_FRACTION, SpringBlockSlip, _barrier_and_kinetic, _min_stick,
                              _nonnegative, _positive, scene_slip, slip_scale, slip_speed_threshold,
                              spring_block_slip)
