"""``python -m asperity2d`` runs the command line."""

import sys

from .cli.main import main

if __name__ == "__main__":  # a spawned worker process imports this module: it must not run the CLI
    sys.exit(main())
