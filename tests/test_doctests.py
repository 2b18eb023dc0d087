"""Run the docstring examples of the package as tests (numpydoc ``Examples``)."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import coastmesh

MODULES = sorted(
    info.name
    for info in pkgutil.walk_packages(coastmesh.__path__, "coastmesh.")
    if not info.name.startswith("coastmesh.cli") and info.name != "coastmesh.__main__"
)


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module(name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0


def test_kernels_have_examples():
    finder = doctest.DocTestFinder()
    for name in (
        "coastmesh.pca.line",
        "coastmesh.pca.grid",
        "coastmesh.geometry.shoreline",
    ):
        tests = finder.find(importlib.import_module(name))
        assert sum(len(t.examples) for t in tests) >= 3, name
