"""What both halves of the belt solver run on: phases in closed form and the switch finder.

``modal`` (the modal form of a linear phase: eigen-decomposition, exact propagation, work
integrals) -> ``segment`` (Taylor grids and mode caches of a segment of it) -> ``events``
(event functions of a phase as rows over its modes) and ``finder`` (locating the first zero of
those rows, the touch rule). The tangential chain (:mod:`asperity2d.belt.chain`) and the normal
contact (:mod:`asperity2d.belt.contact`) import these; nothing here imports either.
"""
