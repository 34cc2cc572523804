"""The studies/ scripts loaded as modules by the tests (each test file under names of its own, so that one file's
patches of a script's module never reach another's)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

STUDIES = Path(__file__).resolve().parents[1] / "studies"


def load_script(name, tag):
    """``studies/NAME.py`` as a new module named ``TAG_NAME``."""
    spec = importlib.util.spec_from_file_location(f"{tag}_{name}", STUDIES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
