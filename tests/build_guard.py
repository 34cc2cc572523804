"""A fixture for tests of the checks made before any graph is built: building raises :class:`Built`."""

import sys

import pytest


class Built(Exception):
    """Raised where a graph would be built: the work got past every check made before building."""


@pytest.fixture
def no_build(monkeypatch):
    """``ShellSystem`` raises :class:`Built`; the simulate module's cache of built systems is emptied around the test."""
    simulate_module = sys.modules["mol_shell.runs.simulate"]

    def fail(*args, **kwargs):
        raise Built

    monkeypatch.setattr(sys.modules["mol_shell.runs.building"], "ShellSystem", fail)
    simulate_module._built.cache_clear()
    yield
    simulate_module._built.cache_clear()
