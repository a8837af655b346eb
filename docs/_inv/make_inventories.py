"""Write the intersphinx inventories of Python, NumPy, SciPy, matplotlib and pymunk (``docs/_inv/``).

The documentation links to those projects' sites, but neither CI nor a developer's machine can
fetch their ``objects.inv`` while building (no network beyond the package registries). So the
inventories are made here, offline, from the installed packages: each module's public names,
introspected, mapped to the URL pattern of its project's site (the pattern each site's own
autosummary set-up produces). ``conf.py`` points ``intersphinx_mapping`` at these files; the
links in the built pages go to the real sites.

Run after upgrading one of those packages (``pip install -e ".[docs]"`` installs sphobjinv)::

    python docs/_inv/make_inventories.py

A name not listed here (a private helper, a rarely used module) stays unlinked; the nitpicky
build then says so, and the module belongs in the lists below.
"""

from __future__ import annotations

import builtins
import importlib
import inspect
from pathlib import Path

import sphobjinv as soi

HERE = Path(__file__).resolve().parent

#: standard-library modules whose public names the pages and docstrings may mention
STDLIB = ("abc", "argparse", "collections", "collections.abc", "concurrent.futures", "contextlib",
          "dataclasses", "datetime", "enum", "functools", "hashlib", "io", "itertools", "json", "logging",
          "math", "multiprocessing", "numbers", "os", "os.path", "pathlib", "pickle", "random", "shutil",
          "subprocess", "tempfile", "threading", "time", "tomllib", "typing", "warnings", "zipfile")
#: builtin types documented on stdtypes.html (the others are on functions.html)
STDTYPES = {"str", "list", "tuple", "dict", "set", "frozenset", "bytes", "bytearray", "memoryview", "range"}

SCIPY = ("fft", "integrate", "interpolate", "io", "linalg", "ndimage", "optimize", "signal", "sparse",
         "spatial", "special", "stats")
MATPLOTLIB = ("pyplot", "figure", "axes", "animation", "colors", "cm", "patches", "lines", "collections",
              "ticker", "gridspec", "colorbar")


class Inventory:
    def __init__(self, project: str, version: str):
        self.inv = soi.Inventory()
        self.inv.project, self.inv.version = project, version
        self.seen: set[tuple[str, str]] = set()

    def add(self, name: str, role: str, uri: str, domain: str = "py") -> None:
        if (name, role) in self.seen:
            return
        self.seen.add((name, role))
        self.inv.objects.append(soi.DataObjStr(name=name, domain=domain, role=role, priority="1", uri=uri,
                                               dispname="-"))

    def write(self, filename: str) -> int:
        text = self.inv.data_file(contract=True)
        soi.writebytes(HERE / filename, soi.compress(text))
        return len(self.inv.objects)


def public(module) -> list[str]:
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in dir(module) if not n.startswith("_")]
    return [n for n in names if not n.startswith("_") and hasattr(module, n)]


def role_of(obj) -> str | None:
    if inspect.ismodule(obj):
        return None
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    if callable(obj):
        return "function"
    return "data"


def members(cls) -> list[tuple[str, str]]:
    """A class's public methods and attributes as (name, role)."""
    out = []
    for name, value in vars(cls).items():
        if name.startswith("_"):
            continue
        if isinstance(value, property) or type(value).__name__ in ("getset_descriptor", "member_descriptor"):
            out.append((name, "attribute"))
        elif callable(value) or isinstance(value, (classmethod, staticmethod)):
            out.append((name, "method"))
    return out


# -- Python --------------------------------------------------------------------------------------
def python() -> Inventory:
    import sys

    inv = Inventory("Python", f"{sys.version_info.major}.{sys.version_info.minor}")
    for name in dir(builtins):
        obj = getattr(builtins, name)
        if name.startswith("_"):
            continue
        if name in ("None", "True", "False", "Ellipsis", "NotImplemented"):
            inv.add(name, "data", f"library/constants.html#{name}")
        elif inspect.isclass(obj) and issubclass(obj, BaseException):
            inv.add(name, "exception", f"library/exceptions.html#{name}")
        elif inspect.isclass(obj):
            page = "stdtypes" if name in STDTYPES else "functions"
            inv.add(name, "class", f"library/{page}.html#{name}")
            for member, role in members(obj):
                inv.add(f"{name}.{member}", role, f"library/stdtypes.html#{name}.{member}")
        elif callable(obj):
            inv.add(name, "function", f"library/functions.html#{name}")
    for modname in STDLIB:
        module = importlib.import_module(modname)
        page = f"library/{modname}.html"
        inv.add(modname, "module", f"{page}#module-{modname}")
        for name in public(module):
            obj = getattr(module, name)
            role = role_of(obj)
            if role is None or (getattr(obj, "__module__", modname) or modname).split(".")[0] not in (
                    modname.split(".")[0], "_" + modname.split(".")[0], "posixpath", "genericpath", "builtins",
                    "_collections_abc", "_abc", "abc", "_functools", "_operator", "_io", "_pickle", "_json",
                    "_thread", "_datetime", "_random", "_warnings", "_hashlib", "_sha2", "posix"):
                continue
            full = f"{modname}.{name}"
            inv.add(full, role, f"{page}#{full}")
            if inspect.isclass(obj):
                for member, mrole in members(obj):
                    inv.add(f"{full}.{member}", mrole, f"{page}#{full}.{member}")
    # the glossary terms and labels numpydoc's default type links use
    for term in ("iterable", "sequence", "generator", "mapping", "file object", "path-like object", "hashable"):
        inv.add(term, "term", f"glossary.html#term-{term.replace(' ', '-')}", domain="std")
    inv.add("bltin-boolean-values", "label", "library/stdtypes.html#bltin-boolean-values", domain="std")
    return inv


# -- NumPy ---------------------------------------------------------------------------------------
def numpy_inventory() -> Inventory:
    import numpy as np

    inv = Inventory("NumPy", np.__version__)
    inv.add("numpy", "module", "reference/index.html#module-numpy")

    def generated(full: str, role: str) -> None:
        inv.add(full, role, f"reference/generated/{full}.html#{full}")

    for name in public(np):
        obj = getattr(np, name)
        role = role_of(obj)
        if role is None:
            continue
        generated(f"numpy.{name}", role)
    for member, role in members(np.ndarray):
        generated(f"numpy.ndarray.{member}", role)
    for sub in ("linalg", "fft"):
        module = importlib.import_module(f"numpy.{sub}")
        inv.add(f"numpy.{sub}", "module", f"reference/routines.{sub}.html#module-numpy.{sub}")
        for name in public(module):
            role = role_of(getattr(module, name))
            if role:
                generated(f"numpy.{sub}.{name}", role)
    inv.add("numpy.random", "module", "reference/random/index.html#module-numpy.random")
    inv.add("numpy.random.Generator", "class", "reference/random/generator.html#numpy.random.Generator")
    inv.add("numpy.random.default_rng", "function", "reference/random/generator.html#numpy.random.default_rng")
    inv.add("numpy.random.RandomState", "class",
            "reference/random/legacy.html#numpy.random.RandomState")
    inv.add("numpy.random.SeedSequence", "class",
            "reference/random/bit_generators/generated/numpy.random.SeedSequence.html#numpy.random.SeedSequence")
    for member, role in members(np.random.Generator):
        full = f"numpy.random.Generator.{member}"
        inv.add(full, role, f"reference/random/generated/{full}.html#{full}")
    inv.add("array_like", "term", "glossary.html#term-array_like", domain="std")
    inv.add("arrays.scalars", "label", "reference/arrays.scalars.html#arrays-scalars", domain="std")
    inv.add("numpy.typing", "module", "reference/typing.html#module-numpy.typing")
    for name in ("ArrayLike", "DTypeLike", "NDArray"):
        inv.add(f"numpy.typing.{name}", "data", f"reference/typing.html#numpy.typing.{name}")
    return inv


# -- SciPy ---------------------------------------------------------------------------------------
def scipy_inventory() -> Inventory:
    import scipy

    inv = Inventory("SciPy", scipy.__version__)
    inv.add("scipy", "module", "reference/index.html#module-scipy")
    for sub in SCIPY:
        module = importlib.import_module(f"scipy.{sub}")
        inv.add(f"scipy.{sub}", "module", f"reference/{sub}.html#module-scipy.{sub}")
        for name in public(module):
            obj = getattr(module, name)
            role = role_of(obj)
            if role is None:
                continue
            full = f"scipy.{sub}.{name}"
            inv.add(full, role, f"reference/generated/{full}.html#{full}")
            if inspect.isclass(obj) and obj.__module__.startswith("scipy"):
                for member, mrole in members(obj):
                    inv.add(f"{full}.{member}", mrole, f"reference/generated/{full}.{member}.html#{full}.{member}")
    return inv


# -- matplotlib ----------------------------------------------------------------------------------
def matplotlib_inventory() -> Inventory:
    import matplotlib

    inv = Inventory("Matplotlib", matplotlib.__version__)
    inv.add("matplotlib", "module", "api/matplotlib_configuration_api.html#module-matplotlib")
    for sub in MATPLOTLIB:
        module = importlib.import_module(f"matplotlib.{sub}")
        inv.add(f"matplotlib.{sub}", "module", f"api/{sub}_api.html#module-matplotlib.{sub}")
        for name in public(module):
            obj = getattr(module, name)
            role = role_of(obj)
            if role is None or getattr(obj, "__module__", None) != f"matplotlib.{sub}" and sub != "pyplot":
                continue
            if sub == "pyplot" and not (inspect.isfunction(obj) and obj.__module__ == "matplotlib.pyplot"):
                continue
            full = f"matplotlib.{sub}.{name}"
            if sub == "axes" and name == "Axes":
                inv.add(full, "class", f"api/axes_api.html#{full}")
            else:
                inv.add(full, role, f"api/_as_gen/{full}.html#{full}")
            if inspect.isclass(obj) and sub in ("figure", "axes", "animation"):
                for member, mrole in members(obj):
                    inv.add(f"{full}.{member}", mrole, f"api/_as_gen/{full}.{member}.html#{full}.{member}")
    # the Axes methods are inherited from _AxesBase and defined on Axes: both lists
    from matplotlib.axes import Axes

    for cls in Axes.__mro__:
        if cls.__module__.startswith("matplotlib.axes"):
            for member, mrole in members(cls):
                full = f"matplotlib.axes.Axes.{member}"
                inv.add(full, mrole, f"api/_as_gen/{full}.html#{full}")
    return inv


# -- pymunk --------------------------------------------------------------------------------------
def pymunk_inventory() -> Inventory:
    import pymunk

    inv = Inventory("pymunk", pymunk.version)
    inv.add("pymunk", "module", "pymunk.html#module-pymunk")
    for name in public(pymunk):
        obj = getattr(pymunk, name)
        role = role_of(obj)
        if role is None:
            continue
        home = getattr(obj, "__module__", "pymunk") if inspect.isclass(obj) or inspect.isfunction(obj) else "pymunk"
        # pymunk's site documents each class on its defining module's page only when that module
        # is public (pymunk.vec2d, ...); the rest (Space, Body, shapes, constraints) on pymunk.html
        page, target = "pymunk.html", f"pymunk.{name}"
        if home.count(".") == 1 and not home.split(".")[1].startswith("_") and home != "pymunk":
            page, target = f"{home}.html", f"{home}.{name}"
        inv.add(f"pymunk.{name}", role, f"{page}#{target}")
        if inspect.isclass(obj):
            for member, mrole in members(obj):
                inv.add(f"pymunk.{name}.{member}", mrole, f"{page}#{target}.{member}")
    return inv


def main() -> None:
    for filename, make in (("python.inv", python), ("numpy.inv", numpy_inventory), ("scipy.inv", scipy_inventory),
                           ("matplotlib.inv", matplotlib_inventory), ("pymunk.inv", pymunk_inventory)):
        count = make().write(filename)
        print(f"{filename}: {count} names, {(HERE / filename).stat().st_size} bytes")


if __name__ == "__main__":
    main()
