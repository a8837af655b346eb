"""Seed 001 mass study on the 3-DOF chain (see belt_parameters.py). Run: ``python scenes/belt_mass.py [--quick]``."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import belt_parameters  # noqa: E402


def main(argv=None) -> int:
    return belt_parameters.main(argv, only="mass")


if __name__ == "__main__":
    raise SystemExit(main())
