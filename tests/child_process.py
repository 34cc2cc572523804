"""What the tests' child processes need: SIGINT as Python expects it."""

import signal


def sigint_default():
    """In the child before exec: SIGINT to its default, so that Python turns it into KeyboardInterrupt even when the
    tests run in a background job of a shell without job control (which starts its children with SIGINT ignored)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
