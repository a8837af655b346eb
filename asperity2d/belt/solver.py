"""``simulate_chain``: masses on a moving belt with exact stick/slip switching.

The driver validates every parameter (:mod:`.spec`, :mod:`asperity2d._inputs`, :mod:`.limits`,
:class:`~.backend.RunOptions`) into one spec -- a :class:`~.spec.ChainSpec`, or a
:class:`~.normal.ContactSpec` when a normal contact is given -- picks the back-end from
``METHODS`` (the first entry of the method whose predicate accepts the spec; the contract:
:mod:`.backend`) and turns the back-end's raw run into a :class:`~.result.BeltResult` (a
:class:`~.contact.result.ContactResult` with a normal contact).
"""

from __future__ import annotations

import time as _time

from ..errors import SceneError
from .backend import MAX_WALL_TIME, Backend, ContactRun, RawRun, RunOptions
from .chain.hybrid import run_ode_phases, run_state_law
from .chain.linear import run_closed_form
from .result import BeltResult, assemble
from .chain.sign import run_sign
from .spec import ChainSpec, ContactSpec, contact_spec
from .._registry import Registry

__all__ = ["Backend", "METHODS", "simulate_chain", "register_method", "unregister_method", "backends_of"]


def _run_contact(spec, options):
    from .contact.loop import run_contact  # lazily: chains without a normal DOF never import it

    return run_contact(spec, options)


def _tangential(spec) -> bool:
    return isinstance(spec, ChainSpec)


def backends_of(obj, name: str = "method") -> tuple[Backend, ...]:
    """A method's back ends, from what a user or an installed package gives (the entry of
    :data:`METHODS`), as ``solve_ivp(method=...)`` takes a class:

    * a :class:`Backend`, or a tuple / list of them (in order of preference);
    * a back-end class, or an instance of one: an object with ``run(spec, options) -> RawRun``
      and, optionally, ``accepts(spec) -> bool`` (default: every tangential chain), ``name``
      (default: the class's name) and ``settings`` (default: none). A class is instantiated
      with no arguments.

    Anything else is one ``SceneError`` naming ``name``."""
    if isinstance(obj, Backend):
        return (obj,)
    if isinstance(obj, (tuple, list)):
        if obj and all(isinstance(b, Backend) for b in obj):
            return tuple(obj)
        raise SceneError(f"`{name}` must be a Backend, a tuple of them or a back-end class, got a "
                         f"{type(obj).__name__} of {', '.join(sorted({type(b).__name__ for b in obj})) or 'nothing'}")
    if isinstance(obj, type):
        try:
            obj = obj()
        except Exception as exc:  # noqa: BLE001 -- an outside class's error is one line
            raise SceneError(f"`{name}` {obj.__name__} cannot be made with no arguments "
                             f"({type(exc).__name__}: {exc})") from None
    run = getattr(obj, "run", None)
    if not callable(run):
        raise SceneError(f"`{name}` must be a method name, a Backend or a back-end class with "
                         f"run(spec, options), got {type(obj).__name__}")
    accepts = getattr(obj, "accepts", None)
    settings = getattr(obj, "settings", ())
    label = getattr(obj, "name", None)
    return (Backend(label if isinstance(label, str) and label else type(obj).__name__,
                    accepts if callable(accepts) else _tangential, run,
                    settings=tuple(settings) if isinstance(settings, (tuple, list)) else ()),)


def _check_method(entry) -> tuple[Backend, ...]:
    return backends_of(entry, "method")


#: method name -> back-ends in order of preference (the contract: :mod:`.backend`). A
#: ``Registry`` (``asperity2d._registry``): :func:`register_method` adds a method, an installed
#: package adds its own through the entry-point group ``asperity2d.belt_methods`` (a Backend, a
#: tuple of them or a back-end class), and ``"module:name"`` works wherever a method's name does.
#: Item assignment (``METHODS["frozen"] = (Backend(...),)``) still adds one.
METHODS: Registry = Registry("method", "asperity2d.belt_methods", check=_check_method, adapt=lambda o, n: o)
METHODS.register((
    Backend("closed-form contact phases", lambda spec: isinstance(spec, ContactSpec), _run_contact, settings=()),
    Backend("state-variable ODE (Dahl, LuGre)", lambda spec: _tangential(spec) and spec.law.has_state,
            run_state_law),
    Backend("closed-form phases",
            lambda spec: _tangential(spec) and spec.constant_belt and spec.law.piecewise_constant,
            run_closed_form),
    Backend("integrated phases", _tangential, run_ode_phases),
), name="exact")
METHODS.register((Backend("sign() friction through solve_ivp", _tangential, run_sign),), name="sign")


def register_method(name: str, backends, *, replace: bool = False) -> tuple[Backend, ...]:
    """Add the method ``name`` to :data:`METHODS`: its back ends (a :class:`Backend`, a tuple of
    them in order of preference, or a back-end class: ``backends_of``); a name already taken
    raises ``SceneError`` unless ``replace``. Returns the back ends as registered.

    Examples
    --------
    >>> from asperity2d.belt.solver import Backend, register_method, unregister_method
    >>> register_method("exact", Backend("mine", lambda spec: True, print))
    Traceback (most recent call last):
    ...
    asperity2d.errors.SceneError: `method` 'exact' is already registered (pass replace=True)
    """
    return METHODS.register(backends, name=name, replace=replace)


def unregister_method(name: str) -> tuple[Backend, ...]:
    """Remove the method ``name`` from :data:`METHODS` and return its back ends."""
    return METHODS.unregister(name)


def simulate_chain(
    masses,
    springs,
    dampers,
    *,
    mu_s=None,
    mu_k=None,
    v_belt,
    x0,
    v0,
    t_end,
    g=9.81,
    normal_load=None,
    friction=None,
    method="exact",
    n_samples=2001,
    t_eval=None,
    include_events=True,
    rtol=1e-8,
    atol=None,
    integrator="LSODA",
    max_events=1_000_000,
    max_steps=1_000_000,
    max_wall_time=MAX_WALL_TIME,
    normal=None,
    y0=None,
    vy0=None,
) -> BeltResult:
    """Simulate n masses (kg) on a belt at ``v_belt`` (m/s, or a callable of t) for ``t_end`` s.

    ``springs`` (N/m) and ``dampers`` (N·s/m) have n+1 entries: wall-m1,
    m1-m2, ..., mn-wall (0 removes a link). ``mu_s`` / ``mu_k`` are the static
    and kinetic coefficients (``mu_k`` defaults to ``mu_s``); ``friction``, a
    law from :mod:`asperity2d.friction`, replaces them. The normal load per
    mass is ``normal_load`` (N) or m·g.

    ``method="exact"``: event-driven non-smooth integration -- closed-form
    phases for a constant belt speed with Coulomb / static-kinetic friction,
    ``solve_ivp`` (``integrator``, ``rtol``, ``atol``) phases with the same
    stick logic otherwise, a smooth stiff ODE for Dahl / LuGre.
    ``method="sign"``: the multi-DOF belt thesis' raw sign() friction through an adaptive
    solver (chatter included).

    Output is sampled at ``t_eval`` (s) or ``n_samples`` uniform times, plus
    every event time when ``include_events``. Budgets: ``max_events``
    switches; ``max_steps`` scan steps (1/16 of the fastest period each) or
    right-hand-side evaluations; ``max_wall_time`` seconds of wall-clock time (default 30 s), watched
    inside long phases too. Memory: at most 2,000 masses, and the run's peak memory is estimated up
    front (~1 kB per mass², four times that with ``normal``, plus ~200 B per mass and sample;
    ``belt.limits.memory_estimate``) and refused beyond 4 GiB -- about 1,800 masses with 2,001
    samples. Bad input raises ``SceneError`` naming the parameter; a run that fails or exceeds a
    budget raises ``SimulationError``.

    ``normal``, a :class:`~.normal.NormalContact`, gives every mass a normal
    degree of freedom and a unilateral contact (separated, sliding or sticking;
    ``asperity2d.belt.normal``); ``y0`` / ``vy0`` (m, m/s) are then the initial gaps and
    normal velocities (default: at rest on the contact) and the result is a
    :class:`~.contact.result.ContactResult`.

    Parameters
    ----------
    masses : sequence of float
        The n masses (kg), > 0.
    springs, dampers : sequence of float
        n + 1 stiffnesses (N/m) and damping coefficients (N·s/m), >= 0: wall-m1, m1-m2, ...,
        mn-wall.
    mu_s, mu_k : float, optional
        Static and kinetic friction coefficients (``mu_k`` defaults to ``mu_s``); give these
        or ``friction``.
    v_belt : float or callable
        Belt speed (m/s), or ``v_belt(t)``.
    x0, v0 : sequence of float
        Initial positions (m, from the unstretched chain) and velocities (m/s).
    t_end : float
        Simulated time (s), > 0.
    g : float, default 9.81
        Gravity (m/s²) for the default normal load m·g.
    normal_load : float or sequence of float, optional
        Normal load per mass (N), instead of m·g.
    friction : FrictionLaw, optional
        A law from :mod:`asperity2d.friction` (Stribeck, LuGre, ...).
    method : str, Backend or back-end class, default "exact"
        ``"exact"`` (event-driven stick/slip), ``"sign"`` (the thesis' sign() friction), another
        name of :data:`METHODS` (an installed package's too) or ``"module:name"``; or, as
        ``solve_ivp`` takes one, a :class:`Backend`, a tuple of them or a back-end class or
        instance (``backends_of``).
    n_samples : int, default 2001
        Uniform output samples (ignored with ``t_eval``).
    t_eval : array_like, optional
        Output times (s).
    include_events : bool, default True
        Add every event time to the samples.
    rtol, atol : float, optional
        Tolerances of the integrated phases (default ``rtol=1e-8``).
    integrator : str, default "LSODA"
        The :func:`scipy.integrate.solve_ivp` method of the integrated phases.
    max_events, max_steps : int, default 1_000_000
        Budgets (above).
    max_wall_time : float, default 30
        Wall-clock budget (s).
    normal : NormalContact, optional
        A normal degree of freedom per mass (above).
    y0, vy0 : sequence of float, optional
        Initial gaps (m) and normal velocities (m/s), with ``normal``.

    Returns
    -------
    BeltResult or ContactResult
        The time series, the events and the stick intervals (a ``ContactResult`` with
        ``normal``).

    Raises
    ------
    SceneError
        A bad parameter, named.
    SimulationError
        A run that fails or exceeds a budget.

    See Also
    --------
    asperity2d.belt.presets : the thesis' tables as keyword arguments.
    asperity2d.dynamics : spectra, Poincaré sections, limit cycles, Lyapunov exponents.

    Examples
    --------
    One mass on a spring to the wall, carried by the belt from rest relative to it: it sticks
    until the spring pulls mu_s·m·g, at t = mu_s·m·g / (k·V) = 0.3924 s:

    >>> from asperity2d import belt
    >>> r = belt.simulate_chain([1.0], [100.0, 0.0], [0.0, 0.0], mu_s=0.4, mu_k=0.3,
    ...                         v_belt=0.1, x0=[0.0], v0=[0.1], t_end=2.0)
    >>> r
    BeltResult(n=1, 2006 samples, t_end=2 s, events=5)
    >>> first = r.events[0]
    >>> first.kind, round(first.t, 6), round(first.x, 6)
    ('slip', 0.3924, 0.03924)
    >>> [(round(a, 4), round(b, 4)) for a, b in r.stick_intervals[0]]
    [(0.0, 0.3924), (0.8656, 1.0618), (1.5349, 1.7311)]
    """
    method, backends = _method(method)
    if normal is None and y0 is None and vy0 is None:
        spec = ChainSpec(masses, springs, dampers, mu_s, mu_k, v_belt, x0, v0, t_end, g, normal_load, friction)
    else:
        spec = contact_spec(masses, springs, dampers, mu_s=mu_s, mu_k=mu_k, v_belt=v_belt, x0=x0, v0=v0,
                            t_end=t_end, g=g, normal_load=normal_load, friction=friction, normal=normal, y0=y0,
                            vy0=vy0)
    options = RunOptions.build(spec, n_samples=n_samples, t_eval=t_eval, include_events=include_events,
                               rtol=rtol, atol=atol, integrator=integrator, max_events=max_events,
                               max_steps=max_steps, max_wall_time=max_wall_time)
    return run_spec(spec, options, method, backends=backends)


def _method(method) -> tuple[str, tuple[Backend, ...]]:
    """``(name, back ends)`` of a ``method=`` argument: a name of :data:`METHODS` (or
    ``"module:name"``), or back ends given directly (named by the first one)."""
    if isinstance(method, str):
        return method, METHODS.lookup(method, "method")
    backends = backends_of(method, "method")
    return backends[0].name, backends


def run_spec(spec, options: RunOptions, method: str = "exact", *, backends=None) -> BeltResult:
    """Run a validated spec (a ChainSpec, or a ContactSpec with its normal contact) with ``options``
    by the first back end of ``METHODS[method]`` (or of ``backends``) that accepts it; the result
    with its meta."""
    backends = METHODS.lookup(method, "method") if backends is None else backends
    backend = next((b for b in backends if b.accepts(spec)), None)
    if backend is None:  # a method whose back ends all refuse this chain (a normal contact with "sign")
        others = [name for name, entries in METHODS.items() if any(b.accepts(spec) for b in entries)]
        raise SceneError(f"`method` {method!r} has no back end that accepts this chain"
                         f"{'' if isinstance(spec, ChainSpec) else ' with a normal contact'} "
                         f"(its back ends: {'; '.join(b.name for b in backends)}); "
                         f"methods that do: {', '.join(map(repr, others)) or 'none'}")
    clock = _time.perf_counter()
    raw = backend.run(spec, options)
    _check_raw(raw, spec, backend.name)
    meta = {**raw.meta, "method": method, "backend": backend.name, "wall_time": _time.perf_counter() - clock,
            **{name: getattr(options, name) for name in backend.settings}}
    if isinstance(spec, ContactSpec):
        from .contact.result import assemble_contact

        return assemble_contact(spec, raw, meta)
    return assemble(spec, raw, meta)


def _check_raw(raw, spec, backend: str) -> None:
    """One line naming the back end and the array when what it returned does not fit the chain
    (instead of a NumPy broadcast error deep in the assembly)."""
    import numpy as np

    contact = isinstance(spec, ContactSpec)
    expected = ContactRun if contact else RawRun
    if not isinstance(raw, expected):
        raise SceneError(f"back end {backend!r} must return a {expected.__name__}, got {type(raw).__name__}")
    n = len(spec.chain.masses) if contact else len(spec.masses)
    t = np.asarray(raw.t)
    if t.ndim != 1 or t.size < 1:
        raise SceneError(f"back end {backend!r} returned `t` of shape {t.shape}, expected (T,) with T >= 1")
    T = t.size
    shapes = ({"Z": (4 * n, T), "modes": (n, T), "friction_force": (n, T), "normal_force": (n, T),
               "work": (4, T)} if contact else
              {"x": (n, T), "v": (n, T), "state": (n, T), "friction_force": (n, T), "work": (3, T)})
    for array, shape in shapes.items():
        got = np.shape(getattr(raw, array))
        if got != shape:
            raise SceneError(f"back end {backend!r} returned `{array}` of shape {got}, expected {shape} "
                             f"({n} masses, {T} samples of `t`)")
    if len(raw.stick_intervals) != n:
        raise SceneError(f"back end {backend!r} returned `stick_intervals` for {len(raw.stick_intervals)} "
                         f"masses, expected {n}")
