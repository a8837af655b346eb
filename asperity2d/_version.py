"""The package version: read from the installed distribution's metadata, whose one source is
``pyproject.toml``. Reading it costs ~80 ms (``importlib.metadata`` scans the installed
distributions), so nothing imports this module at start-up: ``asperity2d.__version__``,
``asperity2d --version`` and the run metadata load it when they need it.
"""

from __future__ import annotations

from importlib import metadata


def distribution_version(name: str) -> str:
    """The installed version of distribution ``name``; ``"0+unknown"`` for an uninstalled checkout."""
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "0+unknown"


__version__ = distribution_version("asperity2d")
