"""Every public name has a numpydoc docstring with a runnable example, once in
``mechdyn.__all__`` and listed in the API reference (docs/api.rst).

The examples themselves run in pytest's doctest pass over mechdyn/ (``--doctest-modules``);
a public name that is data (``md.t``, loaded on first use) is documented by the string
after its annotation in mechdyn/__init__.py (where Sphinx reads it), whose example runs
here.
"""
import ast
import doctest
import importlib
import inspect
import re
from pathlib import Path

import pytest

import mechdyn as md

ROOT = Path(__file__).resolve().parents[1]
API = ROOT / "docs" / "api.rst"


def _is_data(obj) -> bool:
    return not (inspect.ismodule(obj) or inspect.isclass(obj) or callable(obj))


def attribute_doc(module_name: str, name: str) -> str | None:
    """The string literal after ``name = ...`` or ``name: ...`` at the top level of a
    module, or None."""
    path = Path(importlib.import_module(module_name).__file__)
    body = ast.parse(path.read_text()).body
    for statement, following in zip(body, body[1:]):
        targets = getattr(statement, "targets", [getattr(statement, "target", None)])
        if any(isinstance(t, ast.Name) and t.id == name for t in targets) \
                and isinstance(following, ast.Expr) \
                and isinstance(following.value, ast.Constant) \
                and isinstance(following.value.value, str):
            return inspect.cleandoc(following.value.value)
    return None


def docstring(name: str) -> str:
    obj = getattr(md, name)
    if _is_data(obj):
        return attribute_doc("mechdyn", name) or ""
    return inspect.getdoc(obj) or ""


def api_names() -> set:
    """The names docs/api.rst lists: autosummary entries and data/module directives."""
    names, in_table = set(), False
    for line in API.read_text().splitlines():
        if re.match(r"\s*\.\. autosummary::", line):
            in_table = True
            continue
        directive = re.match(r"\s*\.\. (?:auto)?(?:data|module|function|class)::\s*(\S+)", line)
        if directive:
            names.add(directive.group(1).removeprefix("mechdyn."))
            in_table = False
            continue
        if in_table:
            entry = line.strip()
            if not entry or entry.startswith(":"):
                continue
            if not line.startswith((" ", "\t")):
                in_table = False
                continue
            names.add(entry.lstrip("~").removeprefix("mechdyn."))
    return names


def test_all_has_no_duplicates():
    repeated = sorted({n for n in md.__all__ if md.__all__.count(n) > 1})
    assert repeated == []


def test_all_holds_every_lazy_name_and_each_resolves():
    assert set(md._LAZY) | set(md._LAZY_MODULES) <= set(md.__all__)
    for name in md.__all__:
        getattr(md, name)


@pytest.mark.parametrize("name", md.__all__)
def test_public_name_has_numpydoc_example(name):
    text = docstring(name)
    assert text, f"md.{name} has no docstring"
    assert re.search(r"^Examples\n-{8}$", text, re.M), f"md.{name}: no Examples section"
    assert re.search(r"^\s*>>> ", text, re.M), f"md.{name}: no >>> example"


def test_the_data_docstring_of_t_runs():
    """md.t's example lives in a string doctest does not collect: run it here."""
    text = attribute_doc("mechdyn", "t")
    test = doctest.DocTestParser().get_doctest(text, {}, "mechdyn.t", "symbols.py", 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert test.examples and runner.failures == 0


def test_api_reference_lists_every_public_name():
    missing = [name for name in md.__all__ if name not in api_names()]
    assert missing == []


def test_api_reference_lists_only_public_names():
    assert sorted(api_names() - set(md.__all__)) == []


def test_a_docstring_without_example_is_caught(monkeypatch):
    """The check can fail: a public function whose docstring lost its example."""
    def bare():
        """A function.

        Examples
        --------
        Nothing runnable here.
        """
    monkeypatch.setattr(md, "coordinate", bare)
    with pytest.raises(AssertionError, match="no >>> example"):
        test_public_name_has_numpydoc_example("coordinate")
