"""The tangential chain: masses sliding or stuck on the belt, without a normal degree of freedom.

The back ends of ``METHODS`` for a :class:`~asperity2d.belt.spec.ChainSpec`: ``linear``
(closed-form phases, with ``energy``'s exact work integrals), ``hybrid`` (integrated phases and
state-variable laws) and ``sign`` (the multi-DOF belt thesis' sign() friction), sharing ``loop``
(the event loop) and ``modes`` (stick or slip at a switch). They run on
:mod:`asperity2d.belt.phases` and return the contract's ``RawRun`` (:mod:`asperity2d.belt.backend`).
"""
