"""The command line: argument parsing and commands only (`mol-shell`, `python -m mol_shell`)."""

from mol_shell._core.interrupts import exit_if_command

try:
    from mol_shell.cli.main import main
except KeyboardInterrupt:  # Ctrl-C while the command line's own modules load: as the package's (mol_shell/__init__)
    exit_if_command()
    raise

__all__ = ["main"]
