import sys

from mol_shell.cli.main import main

sys.exit(main())
