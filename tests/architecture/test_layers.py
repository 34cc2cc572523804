"""The package's architecture, checked on its import graph: layers, no cycles, no imports of the root, lazy imports.

The layers are declared once, in ``pyproject.toml`` (``[tool.importlinter]``, lowest last); these tests read them
from there. import-linter and grimp parse every ``import`` statement of every module, those inside functions
included (checked below against an independent walk of each module's syntax tree), so a function-level import
cannot hide an upward edge or a cycle.
"""

import ast
import os
import subprocess
import sys
from pathlib import Path

import grimp
import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[2]
PACKAGE = ROOT / "mol_shell"
CONFIG = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]
CONTRACTS = CONFIG["contracts"]
LAYERS = next(c["layers"] for c in CONTRACTS if c["type"] == "layers")

#: External packages a function may import, each for a reason: optional (an extra) or heavy to import and needed by
#: few commands, so ``import mol_shell`` and the CLI's start stay fast. Import times measured on a 2-core machine.
LAZY_EXTERNAL = {
    "distributed": "the dask extra, optional: only studies run on a dask cluster need it",
    "cloudpickle": "the dask extra's, optional: only a study of a law of one's own made in a script pickles it",
    "sksundae": "SUNDIALS (about 1 s to import): only the CVODE/IDA integrators and the DAE route need it",
    "scipy": "its integrate/interpolate/sparse submodules (0.4-1 s each): only some integrators, statics, modes, meridians",
    "matplotlib": "pyplot (0.7 s, and it picks a backend): only figures; the CLI chooses the backend first",
    "mpl_toolkits": "matplotlib's 3-D toolkit (shipped with it): only animations draw in 3-D",
    "meshio": "only the 3-D export",
    "h5py": "only the 3-D export's HDF5 file (meshio's XDMF writer, given a file of its own; 0.07 s)",
    "imageio_ffmpeg": "only animations written as video",
    "PIL": "only animation frames and GIFs",
    "tqdm": "only runs that show a progress bar",
    "fcntl": "POSIX only: the compiled-kernel cache locks with it where it exists",
}

#: Function-level imports that have no such reason (the standard library, and packages every run imports anyway):
#: reported to be moved to module level. Each entry must still exist, so a fixed one is removed from here.
NOT_YET_AT_MODULE_LEVEL: set = set()


def module_files():
    """``{module name: path}`` of every module of the package."""
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


def imports(module, path):
    """``[(line, imported module, inside a function)]`` of every import statement of a module, by its syntax tree.

    Relative imports are resolved against the module's package; ``from X import name`` yields ``X`` (and
    ``X.name``, which may be a submodule).
    """
    package = module if path.name == "__init__.py" else module.rpartition(".")[0]
    found = []

    def visit(node, in_function):
        for child in ast.iter_child_nodes(node):
            inner = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda))
            if isinstance(child, ast.Import):
                found.extend((child.lineno, alias.name, in_function) for alias in child.names)
            elif isinstance(child, ast.ImportFrom):
                base = child.module or ""
                if child.level:
                    anchor = package.split(".")[: len(package.split(".")) - (child.level - 1)]
                    base = ".".join(anchor + ([base] if base else []))
                found.append((child.lineno, base, in_function))
                found.extend((child.lineno, f"{base}.{alias.name}", in_function) for alias in child.names)
            visit(child, inner)

    visit(ast.parse(path.read_text(), str(path)), False)
    return found


MODULES = module_files()
IMPORTS = {module: imports(module, path) for module, path in MODULES.items()}


@pytest.fixture(scope="module")
def graph():
    return grimp.build_graph("mol_shell", include_external_packages=True, cache_dir=None)


def test_import_linter_keeps_every_contract():
    """``lint-imports`` (the contracts of pyproject.toml) reports every contract kept and none broken."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))
    lint = Path(sys.executable).with_name("lint-imports")
    command = [str(lint)] if lint.exists() else ["lint-imports"]
    done = subprocess.run([*command, "--no-logo", "--no-cache", str(ROOT / "pyproject.toml")], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout + done.stderr
    assert f"Contracts: {len(CONTRACTS)} kept, 0 broken." in done.stdout, done.stdout
    for contract in CONTRACTS:
        assert f"{contract['name']} KEPT" in done.stdout, (contract["name"], done.stdout)


def test_the_graph_counts_imports_inside_functions(graph):
    """Every import statement inside a function (found by walking the syntax trees) is an edge of the graph the
    contracts are checked on, with its line: imports inside functions are held to the layers too."""
    lazy = [(module, line, name) for module, found in IMPORTS.items() for line, name, inner in found if inner]
    assert lazy, "no function-level imports found: the syntax-tree walk is broken"
    for module, line, name in lazy:
        target = name.split(".")[0] if name.split(".")[0] != "mol_shell" else name
        if target not in graph.modules:  # a name imported from a module, not a module
            continue
        details = graph.get_import_details(importer=module, imported=target)
        assert line in {d["line_number"] for d in details}, (module, line, name, details)


def test_the_layers_are_the_folders_of_the_package():
    """The top of the package holds ``__init__.py``, ``__main__.py`` and one folder per declared layer, no more."""
    entries = [p for p in PACKAGE.iterdir() if p.name != "__pycache__" and not p.name.startswith(".")]
    assert {p.name for p in entries if p.is_file()} == {"__init__.py", "__main__.py"}
    folders = {p.name for p in entries if p.is_dir()}
    assert {f"mol_shell.{name}" for name in folders} == set(LAYERS)
    for name in folders:
        assert (PACKAGE / name / "__init__.py").is_file(), name
    assert len(LAYERS) == len(set(LAYERS))


def test_no_import_cycles_between_modules(graph):
    """No module reaches itself through the imports of others (module by module, not only between layers)."""
    internal = sorted(m for m in graph.modules if m == "mol_shell" or m.startswith("mol_shell."))
    assert set(internal) == set(MODULES)
    cycles = []
    for importer in internal:
        for imported in graph.find_modules_directly_imported_by(importer):
            if imported.startswith("mol_shell") and graph.chain_exists(importer=imported, imported=importer):
                cycles.append((importer, *graph.find_shortest_chain(importer=imported, imported=importer)))
    assert not cycles, "\n".join(" -> ".join(c) for c in cycles)


def test_no_module_inside_the_package_imports_the_root():
    """Only ``mol_shell.<layer>...`` inside the package: the root's ``__init__`` is the public face, imported by
    users, never by the package itself (``from mol_shell import X`` or ``import mol_shell`` in a module)."""
    offenders = [(module, line) for module, found in IMPORTS.items() if module != "mol_shell"
                 for line, name, _ in found if name == "mol_shell"]
    assert not offenders, offenders


def test_imports_inside_functions_are_only_of_optional_heavy_dependencies():
    """A function imports only external packages of :data:`LAZY_EXTERNAL` (never a mol_shell module: such an
    import hides an upward edge or a cycle from a reader of the module's head)."""
    found = set()
    for module, items in IMPORTS.items():
        for line, name, inner in items:
            if inner:
                found.add((module, name.split(".")[0], line))
    internal = [f for f in found if f[1] == "mol_shell"]
    assert not internal, internal
    others = {(module, top) for module, top, _ in found if top not in LAZY_EXTERNAL}
    assert others == NOT_YET_AT_MODULE_LEVEL, (
        f"new: {sorted(others - NOT_YET_AT_MODULE_LEVEL)}; moved to module level (remove from the list): "
        f"{sorted(NOT_YET_AT_MODULE_LEVEL - others)}")
    unused = set(LAZY_EXTERNAL) - {top for _, top, _ in found}
    assert not unused, f"allowed but imported by no function (remove from LAZY_EXTERNAL): {sorted(unused)}"
