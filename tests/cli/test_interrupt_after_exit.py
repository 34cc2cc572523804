"""A Ctrl-C or SIGTERM after a command wrote its output and said so, until its process has ended: one line saying what
it kept and exit 130 (143), for ``python -m mol_shell`` and the ``mol-shell`` program alike. The interpreter's
teardown after Python's exit functions (0.5 s after a run) first put the signals' default actions back: one that
landed there killed the process (-2, -15) with nothing said. The program now ends as the exit functions have run.

Each command runs in a process of its own, which a ``sitecustomize`` module (run by Python before the command) makes
signal itself at a fixed point of its end, so the point does not depend on the machine's speed: in its last exit
function (where both the old and the new program say it), or as the interpreter's teardown frees the modules (where
the old program was killed; the new one has no teardown to signal in: it ends 0, as where the signal came too late).
A study on local processes sends it the moment its ``wrote`` line is read: its pool's threads then still ran, and an
interrupt left the pool's semaphores to the resource tracker, which warned of them.
"""

import os
import signal
import subprocess
import sys
import textwrap

import pytest

#: ``SIGNAL_AT`` (``exit`` or ``teardown``) and ``SIGNAL_NUMBER``: where and which signal the process sends itself
HOOK = textwrap.dedent("""
    import atexit, os

    def _send():
        os.kill(os.getpid(), int(os.environ["SIGNAL_NUMBER"]))

    class _AtTeardown:
        def __del__(self):  # as the interpreter frees this module, after Python's exit functions
            _send()

    if os.environ.get("SIGNAL_AT") == "teardown":
        _held = _AtTeardown()
    elif os.environ.get("SIGNAL_AT") == "exit":
        atexit.register(_send)  # registered first: called last
""")

#: the ``mol-shell`` program as pip writes it (``mol_shell.cli.main:entry``)
PROGRAM = "import sys; from mol_shell.cli.main import entry; sys.argv[0] = 'mol-shell'; sys.exit(entry())"
RUN = ["run", "twisted-cylinder", "--n", "9", "--t-end", "1e-5", "--no-stresses"]
SAID = {signal.SIGINT: (130, "interrupted"), signal.SIGTERM: (143, "terminated (SIGTERM)")}


def _env(tmp_path, **hook):
    (tmp_path / "sitecustomize.py").write_text(HOOK)
    env = {**os.environ, **hook,
           "PYTHONPATH": os.pathsep.join([str(tmp_path), *filter(None, [os.environ.get("PYTHONPATH")])])}
    env.pop("PYTHONSTARTUP", None)
    return env


def _launch(program):
    return [sys.executable, "-m", "mol_shell"] if program == "python -m" else [sys.executable, "-c", PROGRAM]


def _errors(stderr):
    return [line for line in stderr.splitlines() if not line.startswith("mol-shell: warning:")]


@pytest.mark.parametrize(("program", "signum", "at"), [("python -m", signal.SIGINT, "teardown"),
                                                       ("mol-shell", signal.SIGTERM, "teardown"),
                                                       ("mol-shell", signal.SIGINT, "exit")])
def test_a_signal_after_the_command_said_wrote_is_said_with_its_file(tmp_path, program, signum, at):
    """In the teardown: killed by the signal, -2 (-15), nothing said. In the exit functions: said, as before."""
    out = tmp_path / "run.nc"
    done = subprocess.run([*_launch(program), *RUN, "-o", str(out)], capture_output=True, text=True, timeout=120,
                          env=_env(tmp_path, SIGNAL_AT=at, SIGNAL_NUMBER=str(int(signum))), check=False)
    code, said = SAID[signum]
    assert done.stdout.startswith(f"wrote {out}: 11 times x 9 nodes"), (done.returncode, done.stdout, done.stderr)
    if at == "exit":
        assert (done.returncode, _errors(done.stderr)) == (code, [f"mol-shell: {said} after writing {out}"])
    else:  # the process ended before the point of its teardown where it was killed: nothing to say
        assert (done.returncode, _errors(done.stderr)) == (0, [])
    with open(out, "rb") as handle:  # whole: written before the signal, as the line said
        assert handle.read(8) == b"\x89HDF\r\n\x1a\n"


def test_a_ctrl_c_as_a_study_on_local_processes_said_wrote_leaves_no_semaphores(tmp_path):
    """``resource_tracker: There appear to be 5 leaked semaphore objects to clean up at shutdown`` and a line of
    source followed ``mol-shell: interrupted after writing ...``: the pool's threads were let go on as the study
    wrote its file, and the Ctrl-C ended the process before they released the pool's queues."""
    out = tmp_path / "st.nc"
    env = {**_env(tmp_path), "MOL_SHELL_START_METHOD": "spawn"}  # a forked worker ends at once: the pool too
    process = subprocess.Popen([sys.executable, "-m", "mol_shell", "study", "twisted-cylinder", "--n", "9", "--vary",
                                "gamma=0.1,0.2", "--t-end", "1e-5", "--workers", "2", "-o", str(out)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    for line in process.stdout:
        if line.startswith("wrote"):
            process.send_signal(signal.SIGINT)
            break
    _, stderr = process.communicate(timeout=120)
    assert "semaphore" not in stderr and "resource_tracker" not in stderr, stderr
    said = _errors(stderr)
    assert (process.returncode, said) == (0, []) or (
        process.returncode == 130 and len(said) == 1 and said[0].startswith("mol-shell: interrupted after writing ")
        and said[0].endswith(f" {out}")), (process.returncode, stderr)  # its cases' files, then its own
    assert out.is_file()


@pytest.mark.parametrize(("at", "ended"), [("teardown", (2, [])), ("exit", (130, ["ring_vs_pde.py: interrupted"]))])
def test_a_study_script_ends_as_the_program_does(tmp_path, at, ended):
    """``studies/*.py`` end through ``run_script``: a Ctrl-C in the teardown killed the script (-2, nothing said after
    its refusal); in its exit functions it raised there (Python's "Exception ignored" and a traceback). Now, as
    ``mol-shell``: no teardown to signal in (its own exit code), or one line and 130."""
    script = os.path.join(os.path.dirname(__file__), "..", "..", "studies", "ring_vs_pde.py")
    done = subprocess.run([sys.executable, script, "--quick", "--n", "0"], capture_output=True, text=True,
                          timeout=60, env=_env(tmp_path, SIGNAL_AT=at, SIGNAL_NUMBER=str(int(signal.SIGINT))),
                          check=False)
    refused = "ring_vs_pde.py: error: --n = 0 is outside integers >= 3"
    assert (done.returncode, done.stderr.splitlines()) == (ended[0], [refused, *ended[1]]), done.stderr
