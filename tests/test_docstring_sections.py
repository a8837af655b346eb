"""Public functions describe their arguments in a Parameters section, and the renderers' names run examples.

numpydoc's own validator (``numpydoc.validate``) checks every public function of the package's
public modules: PR01 (a parameter not documented) and PR02 (one documented that does not exist)
must not occur. Prose that names the arguments is not a Parameters section: numpydoc renders
neither a table nor a type for it. The public callables of ``asperity2d.renderers`` each carry an
Examples section, run here as doctests (``tests/test_doctests.py`` runs the others).
"""

from __future__ import annotations

import doctest
import importlib
import inspect

import pytest

validate = pytest.importorskip("numpydoc.validate").validate

MODULES = ("asperity2d", "asperity2d.belt", "asperity2d.surface", "asperity2d.sweep", "asperity2d.friction",
           "asperity2d.dynamics", "asperity2d.renderers", "asperity2d.scripting")
CHECKS = ("PR01", "PR02")


def public_functions():
    seen = {}
    for module_name in MODULES:
        module = importlib.import_module(module_name)
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj):
                seen.setdefault(f"{obj.__module__}.{obj.__qualname__}", f"{module_name}.{name}")
    return seen


def test_every_public_function_documents_its_parameters():
    functions = public_functions()
    assert len(functions) > 80  # the check reaches the whole public API
    missing = {}
    for qualified, public in sorted(functions.items()):
        errors = [f"{code}: {message}" for code, message in validate(qualified)["errors"] if code in CHECKS]
        if errors:
            missing[public] = errors
    assert not missing, "\n".join(f"{name}: {'; '.join(errs)}" for name, errs in missing.items())


RENDERERS = ("OutputFormat", "register_format", "unregister_format", "suffixes", "describe",
             "register_kind_drawers")


def test_the_renderers_public_callables_all_have_examples():
    import asperity2d.renderers as renderers

    callables = {name for name in renderers.__all__ if callable(getattr(renderers, name))
                 and (inspect.isfunction(getattr(renderers, name)) or inspect.isclass(getattr(renderers, name)))}
    assert set(RENDERERS) | {"render"} == callables


@pytest.mark.parametrize("name", RENDERERS)
def test_the_renderers_examples_run(name, tmp_path, monkeypatch):
    import asperity2d.renderers as renderers

    monkeypatch.chdir(tmp_path)
    obj = getattr(renderers, name)
    tests = [t for t in doctest.DocTestFinder(recurse=False).find(obj, name, module=renderers, globs={}) if t.examples]
    assert tests, f"{name} has no Examples"
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in tests:
        runner.run(test, out=lambda text: pytest.fail(f"{name}:\n{text}", pytrace=False))
    assert runner.summarize(verbose=False).failed == 0
    assert ".txt" not in renderers.FORMATS  # an example that registers a format removes it again
