"""The command line, ``asperity2d`` (also ``python -m asperity2d``): the parser in
:mod:`.main`, one handler module per family of subcommands (:mod:`.asperity`, :mod:`.belt`,
:mod:`.basins`, :mod:`.sweep`) and the plumbing shared by the scene scripts (:mod:`.scripting`)."""

from .main import main

__all__ = ["main"]
