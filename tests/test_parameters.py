"""make_scene's parameter records: the single source of its defaults, units and meanings.

The documentation's parameter table is generated from these records (docs/_ext/asperity_docs.py),
so a parameter without a unit or a meaning would be a hole in the reference.
"""

import inspect

import asperity2d as a
from asperity2d import builders, scene

#: The units a record may carry: SI units (and the degree for angles), "1" for a pure number,
#: "-" for a choice, text, flag or file.
UNITS = {"m", "kg", "N", "N/m", "N s/m", "s/m", "m/s", "m/s²", "°", "Pa", "kg/m³", "1", "-"}


def test_every_default_has_a_unit_and_a_meaning():
    records = {p.name: p for p in builders.PARAMETERS}
    assert list(records) == list(builders.DEFAULTS)  # one record per key, in the same order
    for name in builders.DEFAULTS:
        record = records[name]
        assert record.unit in UNITS, (name, record.unit)
        assert len(record.meaning.split()) >= 3, (name, record.meaning)
        assert builders.DEFAULTS[name] is record.default


def test_named_keywords_match_the_signature():
    signature = inspect.signature(a.make_scene).parameters
    for record in builders.KEYWORDS:
        assert signature[record.name].default == record.default
        assert record.unit in UNITS and record.meaning
    assert not set(p.name for p in builders.KEYWORDS) & set(builders.DEFAULTS)


def test_ooten_defaults_are_the_records_and_the_dataclass_defaults():
    assert scene.OOTEN_DEFAULTS == {p.name: p.default for p in scene.OOTEN_PARAMETERS}
    assert a.make_scene().replace(name="") == a.Scene()
    assert a.Scene().lower.stiffness == (scene.OOTEN_DEFAULTS["stiffness"],) * 16
