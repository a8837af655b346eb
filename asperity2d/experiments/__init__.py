"""Experiments on the model: named measures and comparisons over seeds, the virtual
tribometer, and quasi-static (drive speed-up) convergence ladders.

* :mod:`.measures` -- the named measures, what each measures and how converged it is;
* :mod:`.compare` -- :func:`compare` (variants x seeds, statistics);
* :mod:`.tribometer` -- friction against velocity and at reversals;
* :mod:`.quasistatic` -- the drive speed-up and its convergence ladder.
"""
