"""Experiments on the model: named measures and comparisons over seeds, the virtual
tribometer, and quasi-static (drive speed-up) convergence ladders.

* :mod:`.compare` -- the named measures and :func:`compare` (variants x seeds, statistics);
* :mod:`.tribometer` -- friction against velocity and at reversals;
* :mod:`.quasistatic` -- the drive speed-up and its convergence ladder.
"""
