"""The command line: argument parsing and commands only (`mol-shell`, `python -m mol_shell`)."""

from mol_shell.cli.main import main

__all__ = ["main"]
