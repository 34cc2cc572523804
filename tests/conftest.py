import os

import pytest

os.environ.setdefault("OMP_NUM_THREADS", "1")


@pytest.fixture(scope="session")
def paper_scene():
    import mol_shell

    return mol_shell.TwistedCylinder()
