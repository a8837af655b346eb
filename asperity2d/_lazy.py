"""Packages whose public names are imported on first use (PEP 562).

``asperity2d`` and ``asperity2d.belt`` use it so that ``import asperity2d``, the command line's
``--help`` and its bad-input errors start without NumPy, pymunk, SciPy or matplotlib.
"""

from __future__ import annotations

import importlib


def exports(package: str, namespace: dict, names: dict[str, str], submodules=()):
    """``(__getattr__, __dir__)`` for ``package``: each of ``names`` (public name -> module in
    the package) is imported on first use and kept in ``namespace`` (the package's globals),
    each of ``submodules`` is imported when first asked for."""

    def __getattr__(name):
        if name in names:
            value = getattr(importlib.import_module(f".{names[name]}", package), name)
            namespace[name] = value
            return value
        if name in submodules:
            return importlib.import_module(f".{name}", package)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(namespace) | set(names) | set(submodules))

    return __getattr__, __dir__
