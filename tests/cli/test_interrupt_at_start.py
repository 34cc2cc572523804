"""Ctrl-C while the command line is still importing its modules (about a second from the shell)."""

import os
import signal
import subprocess
import sys
import textwrap

import pytest

#: a real SIGINT in the middle of the package's imports: sitecustomize (run by Python before the command) puts a finder
#: first on sys.meta_path that signals the process once, when it is asked for the named module
HOOK = textwrap.dedent("""
    import os, signal, sys

    class _Interrupt:
        fired = False

        def find_spec(self, name, path=None, target=None):
            if name == os.environ["INTERRUPT_AT"] and not self.fired:
                self.fired = True
                os.kill(os.getpid(), signal.SIGINT)
            return None

    sys.meta_path.insert(0, _Interrupt())
""")


def _run(tmp_path, module, args):
    (tmp_path / "sitecustomize.py").write_text(HOOK)
    env = {**os.environ, "INTERRUPT_AT": module,
           "PYTHONPATH": os.pathsep.join([str(tmp_path), *filter(None, [os.environ.get("PYTHONPATH")])])}
    env.pop("PYTHONSTARTUP", None)
    return subprocess.run([sys.executable, *args], env=env, capture_output=True, text=True, timeout=120, check=False)


@pytest.mark.parametrize("module", ["mol_shell.scenes.segments", "mol_shell.cli.path"])
def test_ctrl_c_while_the_command_line_imports_exits_130_in_one_line(tmp_path, module):
    """A SIGINT while ``python -m mol_shell`` loaded the package (or the command line's own modules) ended in a
    KeyboardInterrupt traceback through the imports. It is the command's Ctrl-C now: one line, exit 130."""
    done = _run(tmp_path, module, ["-m", "mol_shell", "scenes"])
    assert done.returncode == 130, done.stderr
    assert done.stderr.strip() == "mol-shell: interrupted"


def test_a_script_that_imports_the_package_keeps_its_keyboard_interrupt(tmp_path):
    """Only the command line turns the interrupt into its exit: a script importing ``mol_shell`` gets the
    ``KeyboardInterrupt`` to handle as it likes."""
    done = _run(tmp_path, "mol_shell.scenes.segments", ["-c", "import mol_shell"])
    assert done.stderr.rstrip().endswith("KeyboardInterrupt") and "mol-shell: interrupted" not in done.stderr
    assert done.returncode in (1, -signal.SIGINT, 128 + signal.SIGINT)  # Python's own ending of an interrupt
