"""The engine's step loop in C (``_kernel.c``), loaded with cffi (part of the adapter).

:meth:`asperity2d.engine.core.Engine.step` spends most of a step's Python time
between its calls into Chipmunk: the drive force, the track projection, the
contact read and the stick/slip switch (measured on Ooten's 16/4 fixed track:
~10 us of Python around a ~20 us ``cpSpaceStep``). :class:`Kernel` runs ``n``
such steps in one C call (and :meth:`Engine.settle`'s simpler steps): the
same Chipmunk and pymunk batch functions (their addresses are taken from
pymunk's cffi module, so nothing is linked against pymunk) and the same arithmetic, operation for operation, with no fused
multiply-adds. Results are bit-identical to the Python loop
(``tests/test_engine_kernel.py``). Steps with hooks (an energy meter) run in
Python.

The C file is an optional extension (``setup.py``): where it was not compiled,
or pymunk's fast path is not usable (:data:`.native.NATIVE`), or its structs
are not laid out as the C file expects, or with the environment variable
``ASPERITY2D_KERNEL=0``, :data:`KERNEL` is False and :data:`KERNEL_REASON`
says why; the engine then steps in Python.
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np

from . import native

#: The environment variable that turns the C step loop off ("0").
SWITCH = "ASPERITY2D_KERNEL"

_CDEF = """
typedef struct {
    uintptr_t space, body;
    uintptr_t space_step, set_force, each_body, each_arbiter, set_friction;
    uintptr_t get_body, set_body, get_arbiter;
    uintptr_t body_data, arbiter_data;
    uintptr_t bodies, arbiter_ints, arbiter_floats;
    double *rows;
    int spring;
    double dt, k, c, v, origin, force, load;
    int64_t step_count;
    int slider_row, lower_row0, n_lower, tracked, fixed_slider;
    double y_track, track_tolerance, max_drift;
    double *lower_x0;
    int switch_active;
    double switch_dt, stick_speed, slip_distance, mu_static, mu_kinetic, mu_idle;
    int law_kind;
    double v_s, viscosity;
    double rs_a, rs_b, rs_d_c, rs_v_0, rs_mu_0, rs_dt;
    uint8_t *stuck, *present;
    double *slid, *mu;
    double *theta;
    uintptr_t *shapes;
    uintptr_t slider_id;
    uintptr_t *ids;
    int32_t *id_index;
    double *slips;
    uint8_t *has;
} asp_ctx;
void asp_steps(asp_ctx *c, int64_t n);
void asp_settle_steps(asp_ctx *c, int64_t n, double push);
size_t asp_layout(int which);
double asp_rate_state_step(const asp_ctx *c, int is_new, double v, double *theta);
"""

ffi = lib = None
#: Why the engine steps in Python (None: the C loop is used), decided once at import.
KERNEL_REASON: str | None = None
#: The contact laws the C loop implements, by their ``kernel`` name
#: (:attr:`asperity2d.contact_laws.ContactLaw.kernel`) -> ``law_kind`` in ``_kernel.c``, whose
#: ``stick_slip`` is held to each one's Python reference ``step``.
C_LAWS = {"static-kinetic": 0, "velocity-weakening": 1, "viscous": 2, "rate-state": 3}
#: True when :class:`Kernel` is usable.
KERNEL = False


def _address(cdata) -> int:
    """A pymunk cffi pointer as an integer (the two cffi modules do not share types)."""
    return int(native.ffi.cast("uintptr_t", cdata))


class Kernel:
    """The C step loop bound to one engine's space, rows and stick/slip switch (``track_tolerance``:
    the drift, in base lengths, above which the projection puts the tracked bodies back).

    Holds the arrays the C code reads and writes; the engine's drive, step
    count and drift books are copied in before each :meth:`steps` and back
    after it. The engine is passed to each call rather than kept, so an engine
    and its kernel form no reference cycle: a finished fork is freed at once,
    its pymunk space with it, not at the next cycle collection. The switch's state moves between its Python lists and these
    arrays only when the other loop needs it (:meth:`StickSlip.hand_to`).
    """

    def __init__(self, engine, stepper: native.Native, track_tolerance: float):
        layout, switch = engine.layout, engine.switch
        c = self.ctx = ffi.new("asp_ctx *")
        lib_p = native.lib
        c.space, c.body = _address(stepper._space), _address(stepper._body)
        c.space_step = _address(native.ffi.addressof(lib_p, "cpSpaceStep"))
        c.set_force = _address(native.ffi.addressof(lib_p, "cpBodySetForce"))
        c.each_body = _address(native.ffi.addressof(lib_p, "cpSpaceEachBody"))
        c.each_arbiter = _address(native.ffi.addressof(lib_p, "cpSpaceEachCachedArbiter"))
        c.set_friction = _address(native.ffi.addressof(lib_p, "cpShapeSetFriction"))
        c.get_body, c.set_body = _address(native._GET_BODY), _address(native._SET_BODY)
        c.get_arbiter = _address(native._GET_ARBITER)
        c.body_data, c.arbiter_data = _address(stepper._body_data), _address(stepper._arb_data)
        c.bodies = _address(stepper._bodies._float_arr)
        c.arbiter_ints = _address(stepper._arbiters._int_arr)
        c.arbiter_floats = _address(stepper._arbiters._float_arr)
        self._rows = engine._row_store  # kept alive with the pointer into it
        c.rows = ffi.cast("double *", self._rows.ctypes.data)
        c.dt = engine.dt_internal
        c.load = engine.load_internal
        c.spring = engine.drive.spring
        rows = layout.lower_rows
        n = len(layout.lower_bodies)
        c.slider_row, c.n_lower = layout.slider_row, n
        c.lower_row0 = rows.start if n else 0
        c.tracked, c.fixed_slider = bool(layout.tracked), bool(layout.fixed_slider)
        c.track_tolerance = track_tolerance
        self._x0 = np.ascontiguousarray(layout.lower_x0, dtype=float)
        c.lower_x0 = ffi.cast("double *", self._x0.ctypes.data)
        c.switch_active = bool(switch.active)
        c.switch_dt, c.stick_speed, c.slip_distance = switch.dt, switch.stick_speed, switch.slip_distance
        law = switch.law
        c.law_kind = C_LAWS[law.kernel]
        # each C law's parameters, internal units, as its Python reference holds them (a field
        # the law lacks is never read by its branch)
        c.mu_idle = law.idle
        c.mu_kinetic = getattr(law, "mu_kinetic", law.idle)
        c.mu_static = getattr(law, "mu_static", c.mu_kinetic)
        c.v_s, c.viscosity = getattr(law, "v_s", 1.0), getattr(law, "viscosity", 0.0)
        if law.kernel == "rate-state":
            c.rs_a, c.rs_b, c.rs_d_c, c.rs_v_0, c.rs_mu_0, c.rs_dt = law.a, law.b, law.d_c, law.v_0, law.mu_0, law.dt
        # the law's state (handed over from the switch's lists when the C loop first steps)
        self.stuck, self.present = np.zeros(n, np.uint8), np.zeros(n, np.uint8)
        self.slid, self.mu, self.theta = np.zeros(n), np.zeros(n), np.full(n, np.nan)
        self._shapes = np.array([_address(s._shape) for s in layout.lower_shapes], dtype=np.uintp)
        order = sorted(range(n), key=lambda i: layout.lower_bodies[i].id)
        self._ids = np.array([layout.lower_bodies[i].id for i in order], dtype=np.uintp)
        self._id_index = np.array(order, dtype=np.int32)
        self._slips, self._has = np.zeros(n), np.zeros(n, np.uint8)
        c.slider_id = layout.slider_id
        for name in ("stuck", "present", "slid", "mu", "theta", "_shapes", "_ids", "_id_index", "_slips", "_has"):
            arr = getattr(self, name)
            ctype = {np.uint8: "uint8_t *", np.float64: "double *", np.uintp: "uintptr_t *",
                     np.int32: "int32_t *"}[arr.dtype.type]
            setattr(c, name.lstrip("_"), ffi.cast(ctype, arr.ctypes.data))

    def steps(self, e, n: int) -> None:
        """``n`` steps of the engine ``e`` (the one it was made for; no hooks): as
        :meth:`Engine.step`'s loop."""
        c = self.ctx
        d, layout = e.drive, e.layout
        c.k, c.c, c.v, c.origin, c.force = d.k, d.c, d.v, d.origin, d.force
        c.step_count, c.max_drift = e.step_count, e.max_solver_drift
        c.y_track = layout.slider_y_track
        e.switch.hand_to(self)
        lib.asp_steps(c, n)
        e.step_count, e.max_solver_drift = c.step_count, c.max_drift

    def settle_steps(self, e, n: int, push: float) -> None:
        """``n`` of the engine ``e``'s :meth:`Engine.settle` steps with the extra force ``push``
        (internal units)."""
        c = self.ctx
        d = e.drive
        c.k, c.origin = d.k, d.origin
        c.max_drift, c.y_track = e.max_solver_drift, e.layout.slider_y_track
        lib.asp_settle_steps(c, n, push)
        e.max_solver_drift = c.max_drift


def _load() -> str | None:
    """None if the C loop is usable here; else why not."""
    global ffi, lib
    if os.environ.get(SWITCH, "").strip() == "0":
        return f"{SWITCH}=0"
    if not native.NATIVE:
        return f"it needs pymunk's fast path, which is off: {native.NATIVE_REASON}"
    spec = importlib.util.find_spec(f"{__package__}._kernel")
    if spec is None or spec.origin is None:
        return "the C extension asperity2d.engine._kernel was not built (no C compiler at install?)"
    try:
        import cffi

        ffi = cffi.FFI()
        ffi.cdef(_CDEF)
        lib = ffi.dlopen(spec.origin)
        if [lib.asp_layout(i) for i in (0, 1)] != [ffi.sizeof("asp_ctx"), ffi.offsetof("asp_ctx", "has")]:
            return "the compiled loop's struct layout differs from kernel.py's"
        pffi = native.ffi
        pymunks = [pffi.offsetof("pmFloatArray", "arr"), pffi.offsetof("pmIntArray", "arr"),
                   pffi.sizeof("cpVect"), pffi.sizeof("uintptr_t")]
        if [lib.asp_layout(i) for i in (2, 3, 4, 5)] != pymunks or \
                [pffi.offsetof(t, "num") for t in ("pmFloatArray", "pmIntArray")] != [0, 0]:
            return "pymunk's structs are not laid out as the compiled loop expects"
    except Exception as exc:  # noqa: BLE001 - anything missing or different means: step in Python
        return f"the compiled loop could not be loaded ({type(exc).__name__}: {exc})"
    return None


def _choose() -> None:
    global KERNEL, KERNEL_REASON
    KERNEL_REASON = _load()
    KERNEL = KERNEL_REASON is None


_choose()
