"""The Examples of the public entry points run, and give what they show."""

from __future__ import annotations

import doctest
import importlib

import pytest

import rocking

#: Modules whose docstrings carry examples of the public interface.
MODULES = [
    "rocking",
    "rocking.model.loading",
    "rocking.model.params",
    "rocking.model.pulse",
    "rocking.sim.run",
    "rocking.study.api",
    "rocking.study.overturning_map",
    "rocking.study.spectrum",
    "rocking.study.optimize",
    "rocking.study.design",
    "rocking.study.threshold",
]


@pytest.mark.parametrize("name", MODULES)
def test_examples(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.NORMALIZE_WHITESPACE)
    assert result.failed == 0


def test_every_main_entry_point_has_examples():
    for name in (
        "simulate",
        "overturning_map",
        "minimum_overturning_spectrum",
        "optimal_damper",
        "design",
        "threshold_map",
        "load_model",
    ):
        assert "Examples\n    --------\n" in getattr(rocking, name).__doc__, name


def test_public_names_are_exported_and_shadow_no_module():
    import pkgutil

    subpackages = {m.name for m in pkgutil.iter_modules(rocking.__path__)}
    assert not set(rocking.__all__) & subpackages
    for name in rocking.__all__:
        assert getattr(rocking, name) is not None
