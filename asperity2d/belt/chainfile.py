"""Chain files: a belt chain (and its normal contact) as TOML, read and written by the model.

A chain file holds ``simulate_chain``'s keyword arguments at top level:

* required: ``masses``, ``springs``, ``dampers``, ``v_belt``, ``x0``, ``v0``, ``t_end``, and
  ``mu_s`` unless a ``[friction]`` table gives the law (``law = "Stribeck"`` plus its
  parameters, as ``FrictionLaw.to_dict`` writes it);
* optional: ``mu_k``, ``g``, ``normal_load``;
* a normal contact: a ``[normal]`` table of :class:`~asperity2d.belt.NormalContact`'s
  parameters (``stiffness``, ``damping``, ``preload``, ``contact_stiffness``,
  ``restitution``, ``inclined``), with the initial gaps ``y0`` and normal velocities ``vy0``;
* run settings: ``method``, ``n_samples``, ``rtol``, ``atol``, ``integrator``.

:func:`read_chain` gives the keyword arguments (laws and the normal contact built),
:func:`arguments` the keyword arguments that rebuild a spec, :func:`write_chain` the file of a
spec (every number exactly: ``simulate_chain`` runs it bit for bit as it ran the spec).
``ChainSpec.to_toml`` / ``ChainSpec.from_toml`` (:mod:`.spec`, which builds the spec of a
file's arguments: :func:`~.spec.spec_of`) call these.

Nothing here imports NumPy until a spec is built: the command line reads (and refuses) a file
before it loads the solver.
"""

from __future__ import annotations

from ..errors import SceneError

REQUIRED = ("masses", "springs", "dampers", "v_belt", "x0", "v0", "t_end")
#: The chain's and its normal contact's optional keys.
OPTIONAL = ("mu_s", "mu_k", "g", "normal_load", "friction", "normal", "y0", "vy0")
#: Run settings a chain file may carry (``simulate_chain``'s, not the spec's).
SETTINGS = ("method", "n_samples", "rtol", "atol", "integrator")
ALLOWED = frozenset(REQUIRED + OPTIONAL + SETTINGS)
#: Settings that the solver uses without checking their type first.
_TYPES = {"method": (str,), "integrator": (str,), "n_samples": (int,), "rtol": (int, float)}


def read_chain(path) -> dict:
    """Keyword arguments for ``simulate_chain`` from the TOML chain file ``path``.

    Parameters
    ----------
    path : str or os.PathLike
        A TOML chain file: ``simulate_chain``'s arguments as keys, with optional ``[friction]``
        and ``[normal]`` tables.

    Returns
    -------
    dict
        Keyword arguments for :func:`asperity2d.belt.simulate_chain` (``normal`` a
        :class:`NormalContact`, ``friction`` a friction law, when the file has those tables).

    Raises
    ------
    SceneError
        An unknown key, a missing one, a setting of the wrong type or a bad ``[friction]`` /
        ``[normal]`` table, naming the key and the file.
    FileError
        A file that cannot be read or parsed.

    Examples
    --------
    >>> from asperity2d.belt import chainfile
    >>> _ = open("chain.toml", "w").write('''
    ... masses = [1.0]
    ... springs = [100.0, 0.0]
    ... dampers = [0.0, 0.0]
    ... mu_s = 0.4
    ... v_belt = 0.1
    ... x0 = [0.0]
    ... v0 = [0.1]
    ... t_end = 2.0
    ... [normal]
    ... stiffness = 1e4
    ... contact_stiffness = 1e5
    ... ''')
    >>> chainfile.read_chain("chain.toml")["normal"]
    NormalContact(stiffness=10000.0, damping=0.0, preload=0.0, contact_stiffness=100000.0, restitution=0.0, inclined=())
    """
    from .. import _io

    return from_document(_io.read_toml("chain", path), f"in {str(path)!r}")


def from_document(data: dict, where: str = "in the chain") -> dict:
    """``simulate_chain`` keyword arguments of a parsed chain document (``where`` names its source in
    errors, e.g. ``"in 'chain.toml'"``); see :func:`read_chain`."""
    if not isinstance(data, dict):
        raise SceneError(f"the chain {where} must be a table of simulate_chain arguments, got {type(data).__name__}")
    data = dict(data)
    unknown = sorted(set(data) - ALLOWED, key=str)
    if unknown:
        raise SceneError(f"`{unknown[0]}` {where} is not a chain parameter (allowed: {', '.join(sorted(ALLOWED))})")
    missing = [key for key in REQUIRED if key not in data]
    if "mu_s" not in data and "friction" not in data:
        missing.append("mu_s")
    if missing:
        raise SceneError(f"`{missing[0]}` is missing {where} (required: {', '.join(REQUIRED)}, and mu_s or a "
                         "[friction] table)")
    for key, types in _TYPES.items():
        if key in data and (isinstance(data[key], bool) or not isinstance(data[key], types)):
            raise SceneError(f"`{key}` {where} must be of type {' or '.join(t.__name__ for t in types)}, "
                             f"got {data[key]!r}")
    if "friction" in data:
        from ..friction.laws import law_from_dict

        if not isinstance(data["friction"], dict):
            raise SceneError(f"`friction` {where} must be a [friction] table with a `law`, got {data['friction']!r}")
        try:
            data["friction"] = law_from_dict(data["friction"])
        except TypeError as exc:  # a parameter the law does not take
            raise SceneError(f"`friction` table {where} is invalid: {exc}") from None
    if "normal" in data:
        from .normal import NormalContact

        try:
            data["normal"] = NormalContact.from_dict(data["normal"])
        except SceneError as exc:
            raise SceneError(f"{exc} ({where.removeprefix('in ')})") from None
    return data


def arguments(spec) -> dict:
    """``simulate_chain`` keyword arguments that rebuild ``spec`` (a ChainSpec or a ContactSpec): the
    same spec, run bit for bit the same."""
    contact = getattr(spec, "chain", None)
    chain = spec if contact is None else contact
    out = {"masses": list(chain.masses), "springs": list(chain.springs), "dampers": list(chain.dampers)}
    if chain.friction is None:
        out.update(mu_s=chain.mu_s, mu_k=chain.mu_k)
    else:
        out["friction"] = chain.friction
    out.update(v_belt=chain.v_belt, x0=list(chain.x0), v0=list(chain.v0), t_end=chain.t_end, g=chain.g)
    if contact is None:
        if chain.normal_load is not None:
            out["normal_load"] = list(chain.normal_load)
    else:  # the chain's normal_load is the contact's static load, derived again from `normal`
        out.update(normal=spec.normal, y0=list(spec.y0), vy0=list(spec.vy0))
    return out


def document(spec, settings: dict | None = None) -> dict:
    """The chain file's document of ``spec`` (plain numbers, lists and tables; no None) plus the run
    ``settings``."""
    out = arguments(spec)
    if callable(out["v_belt"]):
        raise SceneError(f"`v_belt` is a function ({out['v_belt']!r}): a chain file holds a constant belt speed")
    if "friction" in out:
        out["friction"] = out["friction"].to_dict()
    if "normal" in out:
        out["normal"] = {k: v for k, v in out["normal"].to_dict().items() if v is not None}
    for key, value in (settings or {}).items():
        if key not in SETTINGS:
            raise SceneError(f"`{key}` is not a run setting of a chain file (allowed: {', '.join(SETTINGS)})")
        if value is not None:
            out[key] = value
    return out


def write_chain(spec, path, settings: dict | None = None):
    """Write ``spec`` (and the run ``settings``) as the TOML chain file ``path``; return the path."""
    from .._io import atomic_write_text, output_path, toml_text

    path = output_path("path", path, suffixes=(".toml",))
    text = toml_text(document(spec, settings), header="asperity2d belt chain (asperity2d belt FILE runs it)")
    return atomic_write_text(path, text)
