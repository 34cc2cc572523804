"""The files a command reads and writes: its inputs (scene files and the files they name, path and run files),
the scene-file keys a refusal is said with, and its outputs checked against its inputs."""

from __future__ import annotations

import os
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from mol_shell._core.atomic import keep_inputs
from mol_shell._core.errors import ParameterError
from mol_shell._core.paths import check_lengths
from mol_shell._core.user_files import read_user_file
from mol_shell.scenes.files import FILE_KEYS


def input_files(args):
    """``{label: path}`` of the files a command reads, as its options name them: ``FILE`` (plot, export, animate),
    ``--from`` (run, modes), a scene file ``SCENE_OR_FILE`` and the files it names (:func:`scene_file_inputs`: a
    meridian's ``points``), and a meridian's ``--set points=FILE`` (a study's ``--vary points=FILE,...``)."""
    scene = getattr(args, "scene", None)
    toml = scene if scene is not None and str(scene).endswith(".toml") else None
    files = {"FILE": getattr(args, "file", None), "--from": getattr(args, "from_path", None), "SCENE_OR_FILE": toml}
    sets = [str(item).partition("=") for item in getattr(args, "set", None) or []]
    if toml is not None:  # a value --set replaces is not read
        files.update(scene_file_inputs(toml, skip={key.strip() for key, _, _ in sets}))
    for key, _, value in sets:
        if key.strip() == "points" and value.strip():
            files["--set points"] = value.strip()
    for key, _, value in (str(item).partition("=") for item in getattr(args, "vary", None) or []):
        if key.strip() == "points":  # a study's tables, each a case
            names = [name.strip() for name in value.split(",") if name.strip()]
            files.update({f"--vary points (value {i + 1})": name for i, name in enumerate(names)})
    return files


def scene_file_inputs(path, skip=()):
    """``{"FILE.toml: [table] key": file}``: the files scene file ``path`` names, the values of its keys that name
    files (:data:`~mol_shell.scenes.files.FILE_KEYS`: a meridian's ``points``, in whatever table it stands) where they
    name an existing file, relative to the scene file's folder as :func:`~mol_shell.scenes.files.load_scene` reads
    them, but those of the keys ``skip`` (replaced by ``--set``). Other strings (a history's table, a law's name) are
    no paths: a long one was taken as one and raised ``File name too long``. A scene file that cannot be read or
    parsed, or a path that cannot be (``~nosuchuser/p.txt``), names none here: the command refuses it by name when it
    loads it."""
    try:
        path = Path(os.fspath(path)).expanduser()
        data = tomllib.loads(read_user_file(path).decode("utf-8-sig"))
    except (OSError, TypeError, ValueError, RuntimeError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return {}
    pending = [(name, table) for name, table in data.items() if isinstance(table, dict)]
    pending += [(f"[{name}]", table) for name, tables in data.items() if isinstance(tables, list)
                for table in tables if isinstance(table, dict)]
    pending.append(("", data))
    files = {}
    for name, table in pending:
        for key in FILE_KEYS:
            value = table.get(key)
            if key in skip or not isinstance(value, str) or not value.strip():
                continue
            try:
                named = Path(value.strip()).expanduser()
                named = named if named.is_absolute() else path.parent / named
                if named.is_file():
                    files[f"{path}: " + (f"[{name}] {key}" if name else key)] = str(named)
            except (OSError, ValueError, RuntimeError):  # no path the scene can read either: refused as it loads it
                continue
    return files


#: the ``[run]`` keys of a scene file each command reads (``None``: all of them); a command not listed reads no value
#: of the file as given (stability runs cases of its own)
FILE_VALUES_READ = {"run": None, "study": None, "path": ("n",), "modes": ("n",), "compare": ("n", "t_end", "times")}
#: the command line's options that replace a ``[run]`` key of a scene file (``--t-end`` and ``--times`` both)
RUN_FLAGS = {"n": ("n",), "dt": ("dt",), "rtol": ("rtol",), "atol": ("atol",), "max_step": ("max_step",),
             "integrator": ("integrator",), "t_end": ("t_end", "times"), "times": ("t_end", "times")}


def _file_keys(path):
    """``{key: table}`` of the keys scene file ``path`` sets in its tables (``{}`` where it cannot be read)."""
    try:
        data = tomllib.loads(read_user_file(path).decode("utf-8-sig"))
    except (OSError, ValueError, UnicodeDecodeError):
        return {}
    return {key: name for name, table in data.items() if isinstance(table, dict) for key in table}


def _replaced(args):
    """The scene parameters and ``[run]`` keys the command line gives in place of a scene file's: ``--set``,
    ``--vary``, ``--param``/``--path`` (the continued load), ``--option`` and the run's flags."""
    names = {item.partition("=")[0].strip() for option in ("set", "vary", "option")
             for item in getattr(args, option, None) or []}
    names |= {str(getattr(args, option)).partition("=")[0].strip() for option in ("param", "path")
              if isinstance(getattr(args, option, None), str)}
    names |= {"material_parameters"} if any(name.startswith("material.") for name in names) else set()
    return names | {key for key, flags in RUN_FLAGS.items() if any(getattr(args, f, None) is not None for f in flags)}


def said_with_the_file(args, exc):
    """``exc`` said with the scene file, table and key where it refuses a value the command's scene file set (a step
    ``[run] dt`` beyond the stability bound, ``[edges] end1 = 'clamped'`` on a closed shell, a ``[loads]`` pressure
    without an equilibrium: found as it runs, they named the key alone), as the file's own refusals are said; else
    ``exc`` as it is (a value the command line set, a refusal that names the file already). A ``[run]`` key the command
    needs and neither the file nor the command line gives (``t_end``) is said missing from the file's ``[run]``."""
    scene, command = getattr(args, "scene", None), getattr(args, "command", None)
    if not (isinstance(scene, str) and scene.endswith(".toml") and command in FILE_VALUES_READ
            and isinstance(exc.name, str)):
        return exc
    try:
        shown = str(Path(scene).expanduser())
    except RuntimeError:
        return exc
    text, table = str(exc), _file_keys(shown).get(exc.name)
    read = FILE_VALUES_READ[command]
    if (table is None and exc.value is None and exc.name in RUN_FLAGS and text.startswith(f"{exc.name} is missing")
            and (read is None or exc.name in read)):
        table = "run"  # a [run] key the command needs and the file leaves out (t_end): said where it goes
    if (table is None or text.startswith(f"{shown}: ") or exc.name in _replaced(args)
            or (table == "run" and read is not None and exc.name not in read)):
        return exc
    said = text if text.startswith(f"{exc.name} ") else f"{exc.name}: {text}"
    return ParameterError(exc.name, exc.value, exc.range or exc.allowed, message=f"{shown}: [{table}] {said}")


def reason_with_the_file(args, reason):
    """A refusal recorded as text (a study's refused case, whose ``message`` the file keeps) said with the scene file,
    table and key as :func:`said_with_the_file` says a raised one: the parameter is the refusal's first word, as
    every :class:`ParameterError` begins (``dt = 0.0001 is outside ...``)."""
    name = str(reason).split(" ", 1)[0]
    return str(said_with_the_file(args, ParameterError(name, None, "", message=str(reason))))


def check_outputs(args, paths=(), name="-o", value=None):
    """Refuse, naming ``-o`` (or ``name = value``), an output or a file written beside it (``paths``) that is one of
    the command's input files (:func:`input_files`): ``export run.h5 -o run.xdmf`` replaced the run by the export's
    HDF5 data. Every command checks its ``-o`` so before anything is computed; the files beside it where it knows
    them."""
    keep_inputs(input_files(args), [args.output if value is None else value, *paths], name,
                args.output if value is None else value)


def check_companions(args, paths):
    """Refuse, naming ``-o``, a file a command writes beside its output (``.png``, ``.md``, ``.h5``,
    ``_NNNN.vtu``) with a name too long for its file system (``run.pvd``'s ``run_0000.vtu``: 5 bytes longer), or where
    a directory stands (found only after the work, it was an internal error), or that is one
    of the command's input files (:func:`check_outputs`)."""
    output = args.output
    for path in paths:
        check_lengths(path, "-o", output, what=f"writes {Path(path).name!r} beside it")
        if os.path.isdir(path):
            raise ParameterError.invalid("-o", str(output), f"writes {path} beside it, where a directory stands",
                                         "an output whose companion files can be written (move that directory away)")
    check_outputs(args, paths)
