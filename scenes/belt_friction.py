"""Friction coefficient of the three-mass chain (Table 7)
======================================================

From the thesis *Vibration Analysis of Multi Degree of Freedom Self-excited
Systems* (no author named in the copy used here), called the multi-DOF belt
thesis below.

The Table 2 chain (three 1 kg masses, 10 N/m springs, mu0 = 0.2, belt at 0.1
m/s) with its friction varied (mu0 = 0.2, 0.4; Figure 14): each of the thesis'
statements about friction is a claim, judged as stated. One of the parameter
studies of ``belt_parameters.py``, which runs them all.

Run::

    python scenes/belt_friction.py [--quick] [--plots] [-o DIR] [--json]
"""

# %%
# This table's runs, measures and claims are ``belt_parameters.py``'s (its lesson shows each
# step); this script runs the friction table alone: ``belt_parameters.main`` with ``only="friction"``,
# its outputs in this script's own folder. The script sits beside ``belt_parameters.py`` in
# ``scenes/``, so that folder goes on the import path.

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import belt_parameters  # noqa: E402
from asperity2d import scripting  # noqa: E402


# %%
# The command line
# ----------------
#
# The options are ``belt_parameters.py``'s but ``--only``: ``--quick``, ``--plots``, ``-o``,
# ``--json``.

def main(argv=None) -> int:
    return belt_parameters.main(argv, only="friction", script=__file__)


if __name__ == "__main__":
    scripting.run(main)
