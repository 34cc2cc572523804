import os

import pytest
from build_guard import no_build  # noqa: F401 - a fixture for every test file

os.environ.setdefault("OMP_NUM_THREADS", "1")
#: gcc at -Os for the right-hand sides and stencils: half of -O3's time, where the suite's some 450 builds from a cold
#: cache took a third of it; the same bits (tests/discretization/test_opt_level.py), each evaluation 1.1-1.2x slower.
#: A value set outside (MOL_SHELL_OPT_LEVEL=3 python -m pytest ...) is kept.
os.environ.setdefault("MOL_SHELL_OPT_LEVEL", "s")

#: files whose tests are independent examples with nothing shared but a kernel cache on disk: under pytest-xdist
#: they spread over the workers one by one, and fill the gaps between the other files
#: (test_studies: each runs a studies/ script to its own folder; test_faults: 96 s of drills, each with its own
#: processes, which as one group could end the suite on one worker while the other idles)
SPREAD = {"test_fuzz.py", "test_studies.py", "test_faults.py", "test_performance_paths.py"}


@pytest.hookimpl(tryfirst=True)  # before pytest-xdist's own hook reads the groups
def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist (``-n 2``, ``--dist loadgroup`` from pyproject), the tests of one file run on one worker:
    a file's module-scoped fixtures and cached runs (a reference solution, a compiled system) are built once."""
    for item in items:
        if item.path.name not in SPREAD:
            item.add_marker(pytest.mark.xdist_group(str(item.path.relative_to(config.rootpath))))


@pytest.fixture(autouse=True)
def quiet_compiles(monkeypatch):
    """gcc's progress notice (``mol-shell: compiling ... (about N s expected)``, after 5 s of a build) is said only
    after an hour in tests: on a slow or busy machine it came between a command and its one line of refusal, which
    tests count (tests of the notice set their own threshold)."""
    from mol_shell.discretization import compiled

    monkeypatch.setattr(compiled, "COMPILE_PROGRESS_AFTER", 3600.0)


@pytest.fixture(scope="session")
def paper_scene():
    import mol_shell

    return mol_shell.TwistedCylinder()
