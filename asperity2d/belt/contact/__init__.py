"""The normal contact: chains whose masses can separate from the belt, land and stick again.

The back end of ``METHODS["exact"]`` for a :class:`~asperity2d.belt.spec.ContactSpec`:
``loop`` (the event loop, :func:`~asperity2d.belt.contact.loop.run_contact`) over ``phase``
(phases in closed form from ``affine``, the non-symmetric first-order solution) and ``modes``
(impacts, opening, closing, stick or slip at a switch) -> ``result`` (``ContactResult``, a
``BeltResult`` with the gap, the normal force and the separations). ``steady`` linearises a
chain about steady sliding (flutter); ``minimal`` holds Hoffmann's minimal model and its closed
forms. The contact's parameters (``NormalContact``) and spec are shared with the rest of the
belt (:mod:`asperity2d.belt.normal`, :mod:`asperity2d.belt.spec`).
"""
