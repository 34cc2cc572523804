"""The documentation site builds with ``mkdocs build --strict``: every page in ``nav`` exists, every link
between pages and every image resolves, and every API page's ``::: module`` is found (griffe reads the source) and
rendered from its docstrings without a warning (warnings are errors in strict mode)."""

import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _installed(name):
    try:
        return importlib.util.find_spec(name) is not None
    except ModuleNotFoundError:  # a parent package is missing
        return False


missing = [name for name in ("mkdocs", "mkdocstrings", "mkdocstrings_handlers.python") if not _installed(name)]


@pytest.mark.slow  # mkdocs builds the whole site with its API pages: 10-20 s
@pytest.mark.skipif(bool(missing), reason=f"the docs extra is not installed (pip install -e \".[docs]\"): "
                                          f"{', '.join(missing)} missing")
@pytest.mark.timeout(300)
def test_the_site_builds_strictly(tmp_path):
    out = tmp_path / "site"
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-d", str(out)], cwd=ROOT,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    assert (out / "index.html").is_file() and (out / "api" / "runs" / "index.html").is_file()
    # the API pages were rendered from the docstrings, not left as the ::: directives
    runs = (out / "api" / "runs" / "index.html").read_text()
    assert 'id="mol_shell.runs.simulate.simulate"' in runs and ":::" not in runs
    # the docstrings' Sphinx roles as links or code (docs/_hooks/sphinx_roles.py), none left as text: ~1,160 were
    pages = [p.read_text() for p in (out / "api").rglob("index.html")]
    assert not any(re.search(r":(?:func|meth|class|attr|data|mod):", page) for page in pages)
    public = (out / "api" / "index.html").read_text()
    assert 'id="mol_shell.SCENES"' in public and 'id="mol_shell.INTEGRATORS"' in public  # simulate's docstring
    assert 'href="../#mol_shell.SCENES"' in runs  # sends readers to them: a link


def test_every_page_in_docs_is_in_the_nav():
    """A page left out of ``nav`` is built but cannot be reached from the site's menu."""
    import re

    nav = set(re.findall(r":\s*([\w/.-]+\.md)\s*$", (ROOT / "mkdocs.yml").read_text(), flags=re.M))
    pages = {p.relative_to(ROOT / "docs").as_posix() for p in (ROOT / "docs").rglob("*.md")}
    assert pages == nav, (pages - nav, nav - pages)
