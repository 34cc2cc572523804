"""A Ctrl-C (or SIGTERM) that arrives after a command has returned, in the interpreter's teardown (about a second
after a large run, as modules and arrays are freed), ended the process 130 with nothing said (or 0): the program now
says what the command kept, in one line, and exits 130 (143) at once."""

import signal
import subprocess
import sys
from pathlib import Path

import pytest
import tomllib

SCRIPT = """
import os, signal, sys, time
from mol_shell.cli import outcome
from mol_shell.cli.main import main
code = outcome.said_in_teardown(main(sys.argv[2:]))
os.kill(os.getpid(), int(sys.argv[1]))  # as a signal arriving in the teardown would
time.sleep(5)
sys.exit(code)
"""


@pytest.mark.parametrize(("signum", "code", "said"), [(signal.SIGINT, 130, "interrupted"),
                                                      (signal.SIGTERM, 143, "terminated (SIGTERM)")])
def test_a_signal_after_the_command_returned_is_said_with_what_it_kept(signum, code, said, tmp_path):
    out = tmp_path / "run.nc"
    done = subprocess.run([sys.executable, "-c", SCRIPT, str(int(signum)), "run", "twisted-cylinder", "--n", "9",
                           "--t-end", "1e-5", "-o", str(out)], capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == code, (done.returncode, done.stderr)
    lines = [line for line in done.stderr.strip().splitlines() if not line.startswith("mol-shell: warning:")]
    assert lines == [f"mol-shell: {said} after writing {out}"], lines
    assert done.stdout.startswith(f"wrote {out}"), done.stdout
    assert out.is_file()


def test_the_program_is_the_entry_that_says_it():
    """``python -m mol_shell`` and the ``mol-shell`` script run :func:`mol_shell.cli.main.entry`."""
    root = Path(__file__).resolve().parents[2]
    assert tomllib.loads((root / "pyproject.toml").read_text())["project"]["scripts"]["mol-shell"] == \
        "mol_shell.cli.main:entry"
    assert "sys.exit(entry())" in (root / "mol_shell" / "__main__.py").read_text()
