"""What the tests' child processes need: SIGINT as Python expects it."""

import signal


def sigint_default():
    """In the child before exec: SIGINT to its default, so that Python turns it into KeyboardInterrupt even when the
    tests run in a background job of a shell without job control (which starts its children with SIGINT ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def wait_until_busy(proc, cpu_seconds, timeout=120.0):
    """Wait until child ``proc`` has used ``cpu_seconds`` of processor time itself (user + system, from Linux's
    ``/proc/PID/stat``; a compiler it runs is not counted): past its imports and set-up and into its work, however
    fast or loaded the machine. ``False`` if it exited or ``timeout`` (wall seconds) passed first."""
    import os
    import time

    tick = os.sysconf("SC_CLK_TCK")
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and proc.poll() is None:
        try:
            with open(f"/proc/{proc.pid}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:  # gone between poll() and open()
            return False
        if (int(fields[11]) + int(fields[12])) / tick >= cpu_seconds:
            return True
        time.sleep(0.05)
    return False
