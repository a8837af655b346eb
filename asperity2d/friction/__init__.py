"""Friction laws and their fits.

* :mod:`.laws` -- the laws a belt chain (or any model) can use: Coulomb, static/kinetic,
  Coulomb + viscous, Stribeck, and the state-variable Dahl and LuGre laws;
* the fits -- fitting those laws to the virtual tribometer's data (:func:`fit_coulomb_viscous`,
  :func:`fit_stribeck`, :func:`fit_dahl`, :func:`fit_lugre`) and to the stick-slip cycles of
  asperity runs (:func:`fit_stick_slip`, :func:`stick_slip_cycles`), by SciPy least squares.
"""

from .fits import (Fit, fit_coulomb_viscous, fit_dahl, fit_lugre, fit_stick_slip, fit_stribeck, steady_mask,
                   stick_slip_cycles)
from .laws import (Coulomb, CoulombViscous, Dahl, FrictionLaw, LuGre, StaticKinetic, Stribeck,
                   law_from_dict)

__all__ = ["FrictionLaw", "Coulomb", "StaticKinetic", "CoulombViscous", "Stribeck", "Dahl", "LuGre",
           "law_from_dict", "Fit", "fit_coulomb_viscous", "fit_stribeck", "fit_dahl", "fit_lugre", "fit_stick_slip",
           "stick_slip_cycles", "steady_mask"]
