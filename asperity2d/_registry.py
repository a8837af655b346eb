"""The one registry helper every extension point of asperity2d is built on.

A :class:`Registry` is a mapping name -> entry (a measure, a contact law, an output format, a
result kind, a belt back end, an engine) that:

* adds an entry with ``Registry.register`` (checked by the registry's own ``check``; a name
  already taken is refused in one line unless ``replace=True``) and removes it with
  ``Registry.unregister``;
* looks a name up with :meth:`~Registry.lookup`: an unknown name is one ``SceneError`` naming
  the parameter and the nearest registered names ("did you mean ...?", :mod:`difflib`);
* accepts ``"package.module:attribute"`` wherever a registered name is (the attribute is
  imported, then made an entry by the registry's ``adapt``), as ``Study(run="pkg.mod:fn")`` does;
* loads its entry-point group (``asperity2d.measures``, ...; :data:`GROUPS`) on first use, so
  an installed package adds entries without anyone importing it. A broken entry point (it does
  not import, it is not an entry, its name is taken) is never a traceback: it is kept as one
  line naming the package and the entry (:attr:`Registry.failures`), given when that name is
  looked up and listed by the command line.

It behaves as a ``dict`` for reading (``name in R``, ``R[name]``, iteration in registration
order, ``len``), so ``MEASURES[name]`` and ``tuple(METHODS)`` read as they always did; item
assignment and ``del`` stay for the older way of adding (they run the same check, without the
collision rule). Light: no NumPy, and ``importlib.metadata`` only on first use.

Registry API (for the registries' modules; the lead wires a new one in the same way)::

    REGISTRY = Registry(
        "measure",                  # what an entry is, for messages: "`measure` 'x' ..."
        "asperity2d.measures",      # the entry-point group (a key of GROUPS)
        key=lambda entry: entry.name,      # the name an entry registers under (register(entry))
        check=check_entry,          # entry -> entry, raises SceneError (optional)
        adapt=adapt,                # (obj, name) -> entry: what an entry point or "mod:attr"
                                    # names, made an entry (default: obj itself, then check)
        param="measure",            # the parameter named in a lookup's message (default `what`)
    )
    REGISTRY.register(entry, replace=False) -> entry
    REGISTRY.unregister(name) -> entry
    REGISTRY.lookup(name, param=None) -> entry     # "did you mean", "mod:attr", entry points
    REGISTRY.failures -> {entry-point name: one-line reason}

Examples
--------
>>> from asperity2d._registry import Registry
>>> colours = Registry("colour", None, key=str.lower)
>>> colours.register("red")
'red'
>>> colours.register("red")
Traceback (most recent call last):
...
asperity2d.errors.SceneError: `colour` 'red' is already registered (pass replace=True)
>>> colours.lookup("rd")
Traceback (most recent call last):
...
asperity2d._registry.UnknownName: `colour` must be one of red, got 'rd' (did you mean 'red'?)
>>> colours.lookup("string:ascii_lowercase")  # "module:attribute" works wherever a name does
'abcdefghijklmnopqrstuvwxyz'
"""

from __future__ import annotations

import difflib
import importlib
import threading
from collections.abc import MutableMapping
from typing import Any, Callable

from .errors import SceneError

#: The entry-point groups an outside package fills (``[project.entry-points."asperity2d.measures"]``
#: in its ``pyproject.toml``), with the registry each one feeds and what an entry point names.
GROUPS = {
    "asperity2d.measures": "experiments.measures.MEASURES: a Measure",
    "asperity2d.contact_laws": "contact_laws.LAWS: a LawEntry, or a ContactLaw subclass",
    "asperity2d.formats": "renderers.FORMATS: an OutputFormat",
    "asperity2d.belt_methods": "belt.METHODS: a Backend, a tuple of them, or a back-end class",
    "asperity2d.result_kinds": "saved.RESULT_KINDS: a ResultKind",
    "asperity2d.engines": "engine.ENGINES: an EngineEntry",
}

#: Longest name a registry looks up (a name is a word; anything longer is refused, not searched).
MAX_NAME = 1000

_lock = threading.RLock()
_ALL_ENTRY_POINTS = None


def _entry_points(group: str):
    """The installed entry points of ``group`` (every distribution is scanned once per process)."""
    global _ALL_ENTRY_POINTS
    if _ALL_ENTRY_POINTS is None:
        from importlib.metadata import entry_points

        _ALL_ENTRY_POINTS = entry_points()
    return list(_ALL_ENTRY_POINTS.select(group=group))


def _package_of(ep) -> str:
    dist = getattr(ep, "dist", None)
    name = getattr(dist, "name", None) if dist is not None else None
    return f"package {name!r}" if name else f"module {ep.value.partition(':')[0]!r}"


def resolve(spec: str, *, what: str = "name") -> Any:
    """Import ``"package.module:attribute"`` (the attribute may be dotted) and return it; one
    ``SceneError`` naming ``what`` if it cannot.

    Examples
    --------
    >>> from asperity2d._registry import resolve
    >>> resolve("math:pi")
    3.141592653589793
    """
    module_name, _, attr = spec.partition(":")
    if not module_name or not attr:
        raise SceneError(f"`{what}` {spec!r} must be 'package.module:attribute'")
    try:
        obj = importlib.import_module(module_name)
    except Exception as exc:  # noqa: BLE001 -- an outside module's error is one line, never a traceback
        raise SceneError(f"`{what}` {spec!r}: module {module_name!r} cannot be imported "
                         f"({type(exc).__name__}: {exc})") from None
    for part in attr.split("."):
        if not hasattr(obj, part):
            raise SceneError(f"`{what}` {spec!r}: {module_name!r} has no attribute {attr!r}")
        obj = getattr(obj, part)
    return obj


def _show(value, limit: int = 60) -> str:
    """A value for a message, shortened; never raises."""
    try:
        text = repr(value)[: limit + 1] if not isinstance(value, str) else repr(value[: limit + 1])
    except Exception:  # noqa: BLE001 -- a message must never fail to format
        text = f"<{type(value).__name__} object>"
    return text if len(text) <= limit else text[: limit - 3] + "..."


class Registry(MutableMapping):
    """A named registry of entries (see the module doc for the API and the rules).

    Parameters
    ----------
    what : str
        What an entry is, in messages (``"measure"``).
    group : str or None
        The entry-point group loaded on first use (None: no outside entries).
    key : callable, optional
        ``entry -> name`` for ``register`` (None: entries carry no name; ``register(entry,
        name=...)`` and entry points give it).
    check : callable, optional
        ``entry -> entry``; raises ``SceneError`` naming what is wrong with an entry.
    adapt : callable, optional
        ``(obj, name) -> entry``: what an entry point or ``"module:attr"`` names, made an
        entry (default: the object itself).
    param : str, optional
        The parameter a lookup's message names (default ``what``).
    modules : bool, default True
        Whether ``"module:attr"`` names an entry (False where a key is no name a user types:
        a file extension).
    """

    def __init__(self, what: str, group: str | None, *, key: Callable[[Any], str] | None = None,
                 check: Callable[[Any], Any] | None = None, adapt: Callable[[Any, str], Any] | None = None,
                 param: str | None = None, modules: bool = True):
        self.what = what
        self.modules = modules
        self.group = group
        self.param = param or what
        self._key = key
        self._check = check
        self._adapt = adapt
        self._data: dict[str, Any] = {}
        self._resolved: dict[str, Any] = {}  # "module:attr" -> its entry, made once
        self._loaded = group is None
        #: entry-point name -> one line saying why it could not be loaded
        self.failures: dict[str, str] = {}

    # -- adding and removing ----------------------------------------------------------------------
    def register(self, entry, *, name: str | None = None, replace: bool = False):
        """Add ``entry`` under its name (``key(entry)``, or ``name`` for a registry whose entries
        carry none), checked; a name already taken is one ``SceneError`` unless ``replace``.
        Returns the entry as registered."""
        if self._check is not None:
            entry = self._check(entry)
        name = self._key(entry) if name is None else name
        if not isinstance(name, str) or not name or len(name) > MAX_NAME or ":" in name:
            raise SceneError(f"`{self.param}` name must be a non-empty string without ':' of at most "
                             f"{MAX_NAME:,} characters, got {_show(name)}")
        with _lock:
            if name in self._data and not replace:
                raise SceneError(f"`{self.param}` {name!r} is already registered (pass replace=True)")
            self._data[name] = entry
        return entry

    def unregister(self, name: str):
        """Remove the entry ``name`` and return it (an unknown name: one ``SceneError``)."""
        self._ensure_loaded()
        if name not in self._data:
            raise self._unknown(name, self.param)
        with _lock:
            return self._data.pop(name)

    # -- looking up -------------------------------------------------------------------------------
    def lookup(self, name, param: str | None = None):
        """The entry registered as ``name``, or the one ``"package.module:attribute"`` names.

        An unknown name is one ``SceneError`` naming ``param`` (default the registry's) with the
        nearest names; an entry point that failed to load gives its one line."""
        param = param or self.param
        if not isinstance(name, str):
            raise SceneError(f"`{param}` must be a name, got {type(name).__name__}")
        if len(name) > MAX_NAME:
            raise SceneError(f"`{param}` must be at most {MAX_NAME:,} characters, got {len(name):,}")
        self._ensure_loaded()
        if name in self._data:
            return self._data[name]
        if name in self.failures:
            raise SceneError(f"`{param}` {name!r}: {self.failures[name]}")
        if ":" in name and self.modules:
            if name not in self._resolved:
                self._resolved[name] = self.adapt(resolve(name, what=param), name, param=param)
            return self._resolved[name]
        raise self._unknown(name, param)

    def adapt(self, obj, name: str, *, param: str | None = None):
        """``obj`` made an entry of this registry (its ``adapt``, then its ``check``)."""
        entry = self._adapt(obj, name) if self._adapt is not None else obj
        try:
            return self._check(entry) if self._check is not None else entry
        except SceneError as exc:
            raise SceneError(f"`{param or self.param}` {name!r} is not a {self.what}: {exc}") from None

    def loaded(self) -> dict:
        """The entries registered so far, without loading the entry points (a module's own
        tables, built at import time, must not import outside packages)."""
        return dict(self._data)

    def suggest(self, name: str) -> list[str]:
        """The registered names closest to ``name`` (at most three, nearest first)."""
        return difflib.get_close_matches(name, list(self), n=3, cutoff=0.6)

    def _unknown(self, name, param: str) -> "UnknownName":
        close = self.suggest(name) if isinstance(name, str) and len(name) <= MAX_NAME else []
        hint = f" (did you mean {' or '.join(map(repr, close))}?)" if close else ""
        return UnknownName(f"`{param}` must be one of {', '.join(self) or 'nothing yet'}, "
                           f"got {_show(name)}{hint}")

    # -- entry points -----------------------------------------------------------------------------
    def _ensure_loaded(self) -> None:
        if self._loaded:
            return
        with _lock:
            if self._loaded:
                return
            self._loaded = True  # before loading: an entry point's module may use this registry
            for ep in _entry_points(self.group):
                self._load_entry_point(ep)

    def _load_entry_point(self, ep) -> None:
        where = f"entry point {ep.name!r} of {_package_of(ep)} (group {self.group})"
        try:
            obj = ep.load()
        except Exception as exc:  # noqa: BLE001 -- an outside package's bug is one line
            self.failures[ep.name] = f"{where} cannot be loaded ({type(exc).__name__}: {exc})"
            return
        try:
            entry = self.adapt(obj, ep.name)
            name = self._key(entry) if self._key is not None else ep.name
        except SceneError as exc:
            self.failures[ep.name] = f"{where} is not a {self.what}: {str(exc)}"
            return
        if name in self._data:
            self.failures[ep.name] = f"{where}: {self.what} {name!r} is already registered"
            return
        self._data[name] = entry

    def reload(self) -> None:
        """Forget which entry points were loaded and the failures; the next use loads them again
        (after installing a package in a running process)."""
        global _ALL_ENTRY_POINTS
        with _lock:
            _ALL_ENTRY_POINTS = None
            self.failures.clear()
            self._loaded = self.group is None

    # -- the mapping protocol ---------------------------------------------------------------------
    def __getitem__(self, name):
        self._ensure_loaded()
        try:
            return self._data[name]
        except (KeyError, TypeError):
            pass
        if self.modules and isinstance(name, str) and ":" in name and len(name) <= MAX_NAME:
            return self.lookup(name)
        raise self._unknown(name, self.param)

    def __setitem__(self, name, entry):
        if self._check is not None:
            entry = self._check(entry)
        with _lock:
            self._data[name] = entry

    def __delitem__(self, name):
        self._ensure_loaded()
        with _lock:
            del self._data[name]

    def __iter__(self):
        self._ensure_loaded()
        return iter(list(self._data))

    def __len__(self):
        self._ensure_loaded()
        return len(self._data)

    def __contains__(self, name):
        """A registered name, or a ``"module:attr"`` that imports to an entry (one that does not
        is one ``SceneError`` saying why: clearer than "not one of")."""
        self._ensure_loaded()
        try:
            if name in self._data:
                return True
        except TypeError:  # an unhashable value is no name
            return False
        if (self.modules and isinstance(name, str) and ":" in name and len(name) <= MAX_NAME
                and name not in self.failures):
            self.lookup(name)
            return True
        return False

    def __repr__(self):
        return f"Registry({self.what!r}: {', '.join(map(repr, self)) or 'empty'})"


class UnknownName(SceneError, KeyError):
    """A name no entry has: a ``SceneError`` (one line for the user) that is also the
    ``KeyError`` the mapping protocol expects (``registry.get(name)``)."""

    def __str__(self):
        return str(self.args[0]) if self.args else ""
