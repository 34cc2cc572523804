"""What the docs say agrees with the code: their run and study commands parse and have what a run needs (a
``t_end``), the functions they name exist, ``help(mol_shell.path)`` names every parameter it takes, and the
compliance checker says what docs/netcdf.md quotes."""

import importlib
import re
import shlex
import subprocess
from pathlib import Path

import pytest

import mol_shell
from mol_shell.analysis.equilibria import PATH_PARAMETERS
from mol_shell.cli.main import make_parser

ROOT = Path(__file__).resolve().parents[2]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def commands(text):
    """``mol-shell run|study ...`` as written: in code spans (over line breaks) and fenced lines (``\\`` joined)."""
    found = [" ".join(m.split()) for m in re.findall(r"`(mol-shell (?:run|study) [^`]*)`", text)]
    joined = re.sub(r"\\\n\s*", " ", text)
    found += [m.strip() for m in re.findall(r"^\s*(?:\$ )?(mol-shell (?:run|study) [^\n#]*)", joined, flags=re.MULTILINE)]
    return [c for c in found if not any(mark in c for mark in ("[", "|", "...", "SCENE", " ARGS"))]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_run_and_study_commands_give_what_a_run_needs(page):
    """``mol-shell study twisted-cylinder --vary ... -o study.nc`` (README) failed with 't_end is missing'."""
    parser = make_parser()
    for command in commands(page.read_text()):
        try:  # a fragment in prose (without -o) is not a command to check
            args = parser.parse_args(shlex.split(command.split("&&")[0])[1:])
        except SystemExit:
            continue
        from_file = str(args.scene).endswith(".toml") or getattr(args, "from_path", None) is not None
        paths = getattr(args, "path", None) is not None
        assert from_file or paths or args.t_end is not None or args.times is not None, (page.name, command)


def test_the_cap_study_of_paths_sets_the_cap_s_wall():
    """The caps of docs/statics.md are those of the section above it: h = 0.005, nu = 0.3, plane stress."""
    text = re.sub(r"\\\n\s*", " ", (ROOT / "docs" / "statics.md").read_text())
    study = next(c for c in commands(text) if "--path" in c)
    for setting in ("h=0.005", "nu=0.3", "material=svk-plane-stress", "end2=clamped"):
        assert f"--set {setting}" in study, study
    assert "first critical pressure: -69.4898, -87.326" in text
    assert "steps=10" not in text.split("```")[1]  # the first example takes the CLI's default steps


def test_the_functions_the_docs_name_exist():
    """docs/reliability.md named mol_shell._core.ranges.scene_ranges (it is mol_shell.scenes.ranges's)."""
    missing = []
    for page in PAGES:
        for dotted in set(re.findall(r"`(mol_shell(?:\.[A-Za-z_]\w*)+)`", page.read_text())):
            parts = dotted.split(".")
            for cut in range(len(parts), 0, -1):
                try:
                    obj = importlib.import_module(".".join(parts[:cut]))
                except ImportError:
                    continue
                try:
                    for attr in parts[cut:]:
                        obj = getattr(obj, attr)
                except AttributeError:
                    missing.append((page.name, dotted))
                break
            else:
                missing.append((page.name, dotted))
    assert not missing


def test_help_of_path_names_every_parameter():
    doc = " ".join(mol_shell.path.__doc__.split())
    section = doc[doc.index("parameter : str"): doc.index("start, stop")]
    assert all(f"``{name}``" in section for name in PATH_PARAMETERS), section


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_the_compliance_checker_says_what_the_netcdf_page_quotes(tmp_path):
    """Besides the two calendar items the checker prints a warning about its own monotonicity check on the string
    coordinate ``end``: docs/netcdf.md quotes it."""
    pytest.importorskip("compliance_checker")
    ds = mol_shell.simulate(mol_shell.TwistedCylinder(), n=5, t_end=1e-5, progress=False, stresses=False)
    mol_shell.write_netcdf(ds, tmp_path / "run.nc")
    out = subprocess.run(["compliance-checker", "--test=cf:1.8", str(tmp_path / "run.nc")], capture_output=True, check=False,
                         text=True, timeout=300)
    printed = out.stdout + out.stderr
    page = (ROOT / "docs" / "netcdf.md").read_text()
    warning = [line for line in printed.splitlines() if line.startswith(("WARNING", "cf:1.8."))]
    assert warning and all(line in page for line in warning), warning
