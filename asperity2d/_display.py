"""Notebook display of the model's objects, without the model depending on the renderers.

Jupyter asks an object for ``_repr_svg_`` / ``_repr_html_``. The model's objects (``Scene``,
``Result``, ``BeltResult``, ``Comparison``) answer through :func:`represent`, which hands the
object to the display back end named by :data:`BACKEND` -- the renderers'
:mod:`asperity2d.renderers.notebook` -- imported by name the first time a notebook asks. The
back end depends on the model, never the other way round (the dependency inversion of pandas'
plotting back ends), so ``import asperity2d`` stays light and the layer contract holds.
"""

from __future__ import annotations

import importlib

#: The module that draws the model's objects for a notebook: ``represent(obj, mime) -> str``.
BACKEND = "asperity2d.renderers.notebook"


def represent(obj, mime: str) -> str:
    """``obj`` drawn for a notebook as ``mime`` (``"svg"`` or ``"html"``) by the back end."""
    return importlib.import_module(BACKEND).represent(obj, mime)
