"""Fuzzed scene and chain files: the command line answers exit 0 or 2, never a traceback.

Two layers, both with Hypothesis:

* **arbitrary bytes** as a scene file and as a chain file, through the whole
  command line (``main(["run", f, "--duration", "1e-9"])`` and
  ``main(["belt", f, "--t-end", "1e-3"])``). Almost every byte string is
  refused while reading (not UTF-8, not TOML, missing keys); the few valid
  ones (empty, comments, ``seed = 3``) run a bounded 1 ns / 1 ms simulation.
* **arbitrary TOML documents** (keys drawn from the real parameter names
  and at random; values any TOML value: huge integers, inf, nan, strings,
  datetimes, arrays, tables) through the command line's file loaders only:
  ``scene_from_toml`` (reading, the ``[scene]``/``[run]`` structure and
  ``make_scene``'s validation) and ``load_chain``. Running what they build
  is left out on purpose: a valid document may ask for 10^6 asperities or a
  10^9-event chain, and bounding those runs is the simulators' job (issue 11,
  items 1-2), fuzzed in their own tests.

Each file either loads or raises ``SceneError``; any other exception fails the
test. Default run: 40 + 40 + 60 + 60 examples, ~6 s; ``-m slow`` runs 1,000 of each.
"""

from __future__ import annotations

import datetime as dt
import inspect
import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from asperity2d import SceneError
from asperity2d.cli.asperity import scene_from_toml
from asperity2d.cli.belt import ALLOWED as CHAIN_KEYS
from asperity2d.cli.belt import load_chain
from asperity2d.cli import main

FAST = settings(max_examples=40, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
SLOW = settings(max_examples=1000, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _scene_keys() -> list[str]:
    from asperity2d import builders

    names = set(inspect.signature(builders.make_scene).parameters) | set(getattr(builders, "DEFAULTS", {}))
    return sorted(n for n in names if n != "overrides")


# -- TOML documents -----------------------------------------------------------------
def _toml_string(text: str) -> str:
    # JSON escapes are TOML escapes, except that TOML also wants DEL escaped
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf") if math.isinf(value) else repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return _toml_string(value)
    if isinstance(value, dt.datetime):
        return value.isoformat()
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return "{" + ", ".join(f"{_toml_string(k)} = {_toml_value(v)}" for k, v in value.items()) + "}"


def to_toml(doc: dict) -> str:
    """A TOML document with ``doc``'s keys at top level (nested tables written inline)."""
    return "".join(f"{_toml_string(k)} = {_toml_value(v)}\n" for k, v in doc.items())


SCALARS = st.one_of(
    st.booleans(),
    st.integers(),
    st.integers(min_value=-(10 ** 400), max_value=10 ** 400),
    st.floats(),
    st.sampled_from([0.0, -0.0, 1e-300, 5e-324, 1e300, -1.0, 1.0, 0.5]),
    st.text(max_size=8),
    st.datetimes(min_value=dt.datetime(1000, 1, 1)),
)
VALUES = st.recursive(SCALARS, lambda inner: st.lists(inner, max_size=4)
                      | st.dictionaries(st.text(min_size=1, max_size=6), inner, max_size=3), max_leaves=8)


def documents(keys: list[str], tables: tuple[str, ...]):
    """TOML documents over ``keys`` (plus random ones), with optional sub-tables ``tables``."""
    key = st.one_of(st.sampled_from(keys), st.text(min_size=1, max_size=8))
    body = st.dictionaries(key, VALUES, max_size=6)
    return st.one_of(body, st.fixed_dictionaries({}, optional={t: st.one_of(body, VALUES) for t in tables})
                     .flatmap(lambda extra: body.map(lambda d: {**d, **extra})))


def _check_loader(load, path, text):
    path.write_text(text, encoding="utf-8")
    try:
        load(path)
    except SceneError:
        pass  # the one acceptable failure; anything else propagates and fails the test


def _scene_doc_case(tmp_path, doc):
    _check_loader(scene_from_toml, tmp_path / "scene.toml", to_toml(doc))


def _chain_doc_case(tmp_path, doc):
    _check_loader(load_chain, tmp_path / "chain.toml", to_toml(doc))


@FAST
@given(doc=documents(_scene_keys(), ("scene", "run")))
def test_any_toml_document_as_a_scene_file_loads_or_is_a_scene_error(tmp_path, doc):
    _scene_doc_case(tmp_path, doc)


@FAST
@given(doc=documents(sorted(CHAIN_KEYS), ("friction",)))
def test_any_toml_document_as_a_chain_file_loads_or_is_a_scene_error(tmp_path, doc):
    _chain_doc_case(tmp_path, doc)


# -- arbitrary bytes, through the whole command line -----------------------------------
BYTES = st.one_of(st.binary(max_size=64), st.text(max_size=64).map(lambda s: s.encode("utf-8")))


def _cli_case(tmp_path, capsys, data: bytes, argv):
    path = tmp_path / "input.toml"
    path.write_bytes(data)
    code = main([a.replace("{f}", str(path)) for a in argv])
    out, err = capsys.readouterr()
    assert code in (0, 2), (code, data, err)
    assert "Traceback" not in err
    if code == 2:
        assert len(err.splitlines()) == 1 and err.startswith("asperity2d: error: "), err


@settings(FAST, max_examples=60)
@given(data=BYTES)
def test_any_bytes_as_a_scene_file_exit_0_or_2(tmp_path, capsys, data):
    _cli_case(tmp_path, capsys, data, ["run", "{f}", "--duration", "1e-9", "--json"])


@settings(FAST, max_examples=60)
@given(data=BYTES)
def test_any_bytes_as_a_chain_file_exit_0_or_2(tmp_path, capsys, data):
    _cli_case(tmp_path, capsys, data, ["belt", "{f}", "--t-end", "1e-3", "--json"])


@pytest.mark.slow
@SLOW
@given(doc=documents(_scene_keys(), ("scene", "run")))
def test_many_toml_documents_as_scene_files(tmp_path, doc):
    _scene_doc_case(tmp_path, doc)


@pytest.mark.slow
@SLOW
@given(doc=documents(sorted(CHAIN_KEYS), ("friction",)))
def test_many_toml_documents_as_chain_files(tmp_path, doc):
    _chain_doc_case(tmp_path, doc)


@pytest.mark.slow
@SLOW
@given(data=BYTES)
def test_many_byte_strings_as_scene_and_chain_files(tmp_path, capsys, data):
    _cli_case(tmp_path, capsys, data, ["run", "{f}", "--duration", "1e-9", "--json"])
    _cli_case(tmp_path, capsys, data, ["belt", "{f}", "--t-end", "1e-3", "--json"])
