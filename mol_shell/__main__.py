import sys

from mol_shell.cli.main import entry

sys.exit(entry())
