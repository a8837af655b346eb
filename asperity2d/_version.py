"""The package version, from the installed distribution's metadata (one source of truth: pyproject.toml).

Reading it costs ~80 ms (``importlib.metadata`` scans the installed
distributions), so nothing imports this module at start-up:
``asperity2d.__version__``, ``asperity2d --version``, the run metadata and the
sweep manifest load it when they need it.
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version


def distribution_version(name: str) -> str:
    """The installed version of distribution ``name``; ``"0+unknown"`` for a never-installed source tree."""
    try:
        return version(name)
    except PackageNotFoundError:
        return "0+unknown"


__version__ = distribution_version("asperity2d")
