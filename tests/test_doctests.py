"""The Examples sections of the public API run, and print what they say they print.

Every public callable and class of ``asperity2d`` (its ``__all__``), of ``asperity2d.belt``,
``surface``, ``sweep``, ``friction``, ``dynamics`` and ``asperity2d.renderers.render`` is
collected here; each docstring's examples run as a doctest (NumPy's legacy-free print options,
``ELLIPSIS`` and ``NORMALIZE_WHITESPACE``), in a temporary working directory so files an example
writes land there. The scenes the examples use are small (4 lower / 2 upper asperities), so the
whole module runs in well under a minute on two cores.

``test_public_names_have_examples`` is a ratchet: a public name without an Examples section must
be listed in ``WITHOUT_EXAMPLES``, and a listed name that has gained one must leave the list.
"""

from __future__ import annotations

import doctest
import importlib
import inspect

import pytest

#: Module -> the public names documented there (``__all__``, or the one name for ``render``).
PUBLIC = {
    "asperity2d": None,
    "asperity2d.belt": None,
    "asperity2d.surface": None,
    "asperity2d.sweep": None,
    "asperity2d.friction": None,
    "asperity2d.dynamics": None,
    "asperity2d.renderers": ("render",),
    "asperity2d.scripting": None,
}
#: Names that are not callables or classes (the version string, submodules, tables).
NOT_CALLABLE = {"asperity2d.__version__", "asperity2d.belt.presets", "asperity2d.belt.METHODS",
                "asperity2d.dynamics.ASPERITY_WINDOW", "asperity2d.dynamics.BASIN_LABELS"}

#: Public names still without an Examples section (shrinks; never grows).
WITHOUT_EXAMPLES: set[str] = set()

FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def public_names() -> list[str]:
    names = []
    for module_name, listed in PUBLIC.items():
        module = importlib.import_module(module_name)
        for name in listed or module.__all__:
            qualified = f"{module_name}.{name}"
            if qualified not in NOT_CALLABLE:
                names.append(qualified)
    return names


def resolve(qualified: str):
    module_name, name = qualified.rsplit(".", 1)
    return getattr(importlib.import_module(module_name), name)


NAMES = public_names()


def has_examples(obj) -> bool:
    doc = inspect.getdoc(obj) or ""
    return "\nExamples\n--------\n" in f"\n{doc}\n"


def test_public_names_have_examples():
    missing = {name for name in NAMES if not has_examples(resolve(name))}
    assert missing <= WITHOUT_EXAMPLES, f"public names without Examples: {sorted(missing - WITHOUT_EXAMPLES)}"
    gained = WITHOUT_EXAMPLES - missing
    assert not gained, f"these now have Examples: remove them from WITHOUT_EXAMPLES: {sorted(gained)}"


@pytest.fixture
def numpy_printing():
    import numpy as np

    with np.printoptions(precision=4, suppress=True, legacy=False):
        yield


@pytest.mark.parametrize("qualified", [n for n in NAMES])
def test_examples_run(qualified, tmp_path, monkeypatch, numpy_printing):
    obj = resolve(qualified)
    if not has_examples(obj):
        pytest.skip(f"{qualified} has no Examples section yet (listed in WITHOUT_EXAMPLES)")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("TQDM_DISABLE", "1")
    finder = doctest.DocTestFinder(recurse=False)
    module = inspect.getmodule(obj)
    tests = [t for t in finder.find(obj, qualified, module=module, globs={}) if t.examples]
    assert tests, f"{qualified}: an Examples section without a single >>> line"
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    for test in tests:
        runner.run(test, out=lambda text: pytest.fail(f"{qualified}:\n{text}", pytrace=False))
    assert runner.summarize(verbose=False).failed == 0
