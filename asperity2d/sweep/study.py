"""Study descriptions: a run function, a parameter grid and seeds, expanded to runs.

A :class:`Study` names a picklable, importable *run function* by its dotted
path ``"module:function"``. Each run calls ``fn(**params, seed=seed)`` and gets
back a mapping of quantity name to float. ``params`` is the study's ``fixed``
parameters updated with one grid point (a *variant*).

Every run has a stable key: the first 16 hex digits of the SHA-256 of the
canonical JSON of ``{"run": path, "params": params, "seed": seed}``. Changing
a grid value therefore changes the keys of exactly the runs it affects, and a
results store re-runs only those. Note that ``1`` and ``1.0`` are different
parameter values (their JSON differs).

A study can be written as TOML::

    name = "spacing"
    run = "asperity2d.studies.ooten:critical_force_run"
    seeds = 20                      # range(20); or a list [0, 1, 5]; or {start = 0, stop = 20}
    quantities = ["critical_force"] # optional: names every run must return

    [grid]
    spacing = ["regular", "random"]
    profile = ["full"]

    [fixed]                         # optional: the same for every run
    normal_load = 1e-6

or as a Python script that defines ``STUDY = Study(...)``.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import re
import runpy
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Mapping

from .._inputs import MAX_SEEDS, count_seeds
from .._io import MAX_TOML_DEPTH, deep_key, too_deep
from ..errors import SceneError

_RUN_PATH = re.compile(r"^[A-Za-z_][\w.]*:[A-Za-z_]\w*$")
_NAME = re.compile(r"^[A-Za-z0-9][\w.\-]*$")
KEY_LENGTH = 16


def canonical_json(value: Any) -> str:
    """JSON with sorted keys and no whitespace: the form that keys and checksums hash."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def run_key(run: str, params: Mapping[str, Any], seed: int) -> str:
    """Stable key of one run: hex SHA-256 of canonical JSON of path, params and seed.

    Parameters
    ----------
    run : str
        ``"module:function"``.
    params : mapping
        The run's parameters.
    seed : int
        Its seed.

    Returns
    -------
    str
        16 hex digits.

    See Also
    --------
    asperity2d.sweep.RunSpec : carries it.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> sweep.run_key('asperity2d.studies.ooten:critical_force_run', {'lower_count': 4, 'upper_count': 2, 'spacing': 'regular'}, 0)
    'b0556b2bd3086a4e'
    """
    text = canonical_json({"run": run, "params": dict(params), "seed": int(seed)})
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:KEY_LENGTH]


def _check_value(name: str, value: Any) -> Any:
    """Return ``value`` if it is a JSON scalar (finite float); raise SceneError otherwise."""
    if isinstance(value, float) and not math.isfinite(value):
        raise SceneError(f"`{name}` must be finite, got {value!r}")
    if value is None or isinstance(value, (str, bool, int, float)):
        return value
    raise SceneError(
        f"`{name}` must be a str, int, float, bool or None, got {type(value).__name__}"
    )


@dataclass(frozen=True)
class RunSpec:
    """One run of a study: its key, full parameters, seed and grid point.

    See Also
    --------
    asperity2d.sweep.Study.runs : lists them.

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> study.runs()[0]
    RunSpec(key='b0556b2bd3086a4e', params={'lower_count': 4, 'upper_count': 2, 'spacing': 'regular'}, seed=0, variant=(('spacing', 'regular'),))
    """

    key: str
    params: Mapping[str, Any]
    seed: int
    variant: tuple[tuple[str, Any], ...]

    def __hash__(self) -> int:
        return hash(self.key)

    @property
    def variant_label(self) -> str:
        """Human-readable grid point, e.g. ``"spacing=regular, profile=full"``."""
        return variant_label(self.variant)


def variant_label(variant: Iterable[tuple[str, Any]]) -> str:
    """``"a=1, b=x"`` for a grid point given as ``(name, value)`` pairs."""
    return ", ".join(f"{k}={v}" for k, v in variant) or "(single variant)"


@dataclass(frozen=True, kw_only=True)
class Study:
    """A parameter study: ``run`` called for every grid point and every seed.

    Parameters
    ----------
    name : str
        Short identifier (letters, digits, ``_ . -``); recorded in the store.
    run : str
        Dotted path ``"package.module:function"`` of a top-level function
        ``fn(**params, seed=int) -> Mapping[str, float]``.
    grid : dict[str, list]
        Parameter name -> values; the study runs the Cartesian product.
        Values are JSON scalars (str, int, float, bool, None).
    seeds : iterable of int
        Seeds (>= 0, distinct) run at every grid point, e.g. ``range(20)``.
    fixed : dict
        Parameters passed unchanged to every run.
    quantities : tuple[str, ...] or None
        Names every run must return (a run missing one is recorded as
        failed); ``None`` accepts whatever the function returns.

    See Also
    --------
    asperity2d.sweep.run_study, asperity2d.sweep.load_study

    Examples
    --------
    >>> from asperity2d import sweep
    >>> study = sweep.Study(name='spacing', run='asperity2d.studies.ooten:critical_force_run',
    ...                     grid={'spacing': ('regular', 'random')}, seeds=(0,),
    ...                     fixed={'lower_count': 4, 'upper_count': 2}, quantities=('critical_force_N',))
    >>> len(study.runs())  # 2 grid points x 1 seed
    2
    """

    name: str
    run: str
    grid: Mapping[str, tuple] = field(default_factory=dict)
    seeds: tuple[int, ...] = (0,)
    fixed: Mapping[str, Any] = field(default_factory=dict)
    quantities: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not _NAME.match(self.name):
            raise SceneError(
                f"`name` must be letters, digits, '_', '.' or '-', got {self.name!r}"
            )
        if not isinstance(self.run, str) or not _RUN_PATH.match(self.run):
            raise SceneError(f"`run` must be a dotted path 'module:function', got {self.run!r}")
        object.__setattr__(self, "grid", self._checked_grid(self.grid))
        object.__setattr__(self, "seeds", self._checked_seeds(self.seeds))
        if not isinstance(self.fixed, Mapping):
            raise SceneError(f"`fixed` must be a mapping, got {type(self.fixed).__name__}")
        fixed = {}
        for key, value in self.fixed.items():
            if not isinstance(key, str) or not key.isidentifier() or key == "seed":
                raise SceneError(f"`fixed` keys must be identifiers other than 'seed', got {key!r}")
            if key in self.grid:
                raise SceneError(f"`fixed` and `grid` both set {key!r}")
            fixed[key] = _check_value(f"fixed.{key}", value)
        object.__setattr__(self, "fixed", fixed)
        if self.quantities is not None:
            names = tuple(self.quantities) if not isinstance(self.quantities, str) else None
            if not names or not all(isinstance(q, str) and q for q in names):
                raise SceneError(
                    f"`quantities` must be a non-empty list of names or None, got {self.quantities!r}"
                )
            if len(set(names)) != len(names):
                raise SceneError(f"`quantities` must be distinct, got {names!r}")
            object.__setattr__(self, "quantities", names)

    @staticmethod
    def _checked_grid(grid: Any) -> dict[str, tuple]:
        if not isinstance(grid, Mapping):
            raise SceneError(f"`grid` must be a mapping of name to values, got {type(grid).__name__}")
        checked = {}
        for key, values in grid.items():
            if not isinstance(key, str) or not key.isidentifier() or key == "seed":
                raise SceneError(f"`grid` keys must be identifiers other than 'seed', got {key!r}")
            if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
                raise SceneError(f"`grid.{key}` must be a list of values, got {values!r}")
            values = tuple(_check_value(f"grid.{key}", v) for v in values)
            if not values:
                raise SceneError(f"`grid.{key}` must have at least one value")
            if len({canonical_json(v) for v in values}) != len(values):
                raise SceneError(f"`grid.{key}` values must be distinct, got {list(values)!r}")
            checked[key] = values
        return checked

    @staticmethod
    def _checked_seeds(seeds: Any) -> tuple[int, ...]:
        if isinstance(seeds, (int, str, bytes)) or not isinstance(seeds, Iterable):
            raise SceneError(f"`seeds` must be an iterable of ints such as range(n), got {seeds!r}")
        count_seeds("seeds", seeds)  # before a tuple of 10**12 seeds is attempted
        seeds = tuple(itertools.islice(seeds, MAX_SEEDS + 1))
        if len(seeds) > MAX_SEEDS:
            count_seeds("seeds", seeds)
        for s in seeds:
            if isinstance(s, bool) or not isinstance(s, int) or s < 0:
                raise SceneError(f"`seeds` must be ints >= 0, got {s!r}")
        if not seeds:
            raise SceneError("`seeds` must not be empty")
        if len(set(seeds)) != len(seeds):
            raise SceneError("`seeds` must be distinct")
        return tuple(int(s) for s in seeds)

    def __hash__(self) -> int:
        return hash(canonical_json(self.to_dict()))

    # -- expansion ---------------------------------------------------------
    def variants(self) -> list[tuple[tuple[str, Any], ...]]:
        """Grid points in order (first grid parameter varies slowest)."""
        names = list(self.grid)
        return [tuple(zip(names, combo)) for combo in itertools.product(*self.grid.values())]

    def runs(self) -> list[RunSpec]:
        """Every run of the study: variants in grid order, seeds in the given order."""
        specs = []
        for variant in self.variants():
            params = {**self.fixed, **dict(variant)}
            for seed in self.seeds:
                specs.append(RunSpec(run_key(self.run, params, seed), params, seed, variant))
        return specs

    def __len__(self) -> int:
        return math.prod(len(v) for v in self.grid.values()) * len(self.seeds)

    # -- serialisation -----------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """Plain JSON-able dict; :meth:`from_dict` inverts it."""
        return {
            "name": self.name,
            "run": self.run,
            "grid": {k: list(v) for k, v in self.grid.items()},
            "seeds": list(self.seeds),
            "fixed": dict(self.fixed),
            "quantities": None if self.quantities is None else list(self.quantities),
        }

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> "Study":
        """Build a study from a dict (as in TOML); ``seeds`` may be an int count
        or ``{"start": a, "stop": b}``."""
        if not isinstance(data, Mapping):
            raise SceneError(f"`study` must be a table/mapping, got {type(data).__name__}")
        allowed = {"name", "run", "grid", "seeds", "fixed", "quantities"}
        unknown = sorted(set(data) - allowed)
        if unknown:
            raise SceneError(f"`study` has unknown field(s) {unknown}; allowed: {sorted(allowed)}")
        for required in ("name", "run", "seeds"):
            if required not in data:
                raise SceneError(f"`{required}` is required in a study")
        seeds = data["seeds"]
        if isinstance(seeds, int) and not isinstance(seeds, bool):
            if seeds < 1:
                raise SceneError(f"`seeds` count must be >= 1, got {seeds}")
            seeds = range(seeds)
        elif isinstance(seeds, Mapping):
            try:
                seeds = range(int(seeds.get("start", 0)), int(seeds["stop"]))
            except (KeyError, TypeError, ValueError):
                raise SceneError(f"`seeds` table needs integer `start` and `stop`, got {seeds!r}") from None
        return cls(
            name=data["name"],
            run=data["run"],
            grid=data.get("grid", {}),
            seeds=seeds,
            fixed=data.get("fixed", {}),
            quantities=data.get("quantities"),
        )


def load_study(path: str | os.PathLike) -> Study:
    """Read a study from a ``.toml`` file or a ``.py`` script that defines ``STUDY``.

    Parameters
    ----------
    path : str or os.PathLike
        A ``.toml`` file, or a ``.py`` script defining ``STUDY``.

    Returns
    -------
    Study

    Raises
    ------
    FileError
        A missing or malformed file, naming ``path``.

    See Also
    --------
    asperity2d.sweep.Study : what it returns.
    asperity2d.sweep.run_study : takes the path too.

    Examples
    --------
    >>> from pathlib import Path
    >>> from asperity2d import sweep
    >>> _ = Path("study.toml").write_text(
    ...     'name = "spacing"\\n'
    ...     'run = "asperity2d.studies.ooten:critical_force_run"\\n'
    ...     'seeds = 2\\n'
    ...     '[grid]\\n'
    ...     'spacing = ["regular", "random"]\\n')
    >>> study = sweep.load_study('study.toml')
    >>> study.seeds, study.grid
    ((0, 1), {'spacing': ('regular', 'random')})
    """
    path = Path(path)
    if not path.is_file():
        raise SceneError(f"`study` file does not exist: {str(path)!r}")
    suffix = path.suffix.lower()
    if suffix == ".toml":
        try:
            text = path.read_bytes().decode("utf-8")
            deep = deep_key(text)  # first: tomllib spends quadratic time on a dotted key's parts
            data = tomllib.loads(text) if deep is None else {}
        except (tomllib.TOMLDecodeError, UnicodeDecodeError, RecursionError) as exc:
            raise SceneError(f"`study` file {str(path)!r} is not valid TOML: {exc}") from None
        deep = deep or too_deep(data)  # dotted keys nest without limit; a message about them must not recurse
        if deep is not None:
            raise SceneError(f"`study` file {str(path)!r} is nested too deeply: `{deep}` nests tables more "
                             f"than {MAX_TOML_DEPTH} levels deep")
        return Study.from_dict(data)
    if suffix == ".py":
        namespace = runpy.run_path(str(path), run_name="__asperity2d_study__")
        study = namespace.get("STUDY")
        if not isinstance(study, Study):
            raise SceneError(f"`study` script {str(path)!r} must define STUDY = Study(...)")
        return study
    raise SceneError(f"`study` file must end in .toml or .py, got {str(path)!r}")
