"""Seed 001 stiffness study on the 3-DOF chain (see belt_parameters.py). Run: ``python scenes/belt_stiffness.py [--quick]``."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import belt_parameters  # noqa: E402


def main(argv=None) -> int:
    return belt_parameters.main(argv, only="stiffness")


if __name__ == "__main__":
    raise SystemExit(main())
