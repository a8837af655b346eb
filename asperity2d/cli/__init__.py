"""The command line, ``asperity2d`` (also ``python -m asperity2d``): the parser in
:mod:`.main`, one handler module per family of subcommands (:mod:`.asperity`, :mod:`.belt`,
:mod:`.basins`, :mod:`.sweep`). The scene scripts' harness is public: :mod:`asperity2d.scripting`."""

from .main import main

__all__ = ["main"]
