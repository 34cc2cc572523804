"""A Ctrl-C as C extensions report it when it lands inside their calls: the real errors, made by raising
KeyboardInterrupt where a signal's handler would have raised it (deterministic: no signal, no timing)."""

import ctypes

import casadi as ca


class _Interrupted:
    """A ctypes argument type whose conversion is interrupted (the handler ran inside ``from_param``, as in NumPy's
    ``ndpointer.from_param`` when SIGINT lands there)."""

    @classmethod
    def from_param(cls, obj):
        raise KeyboardInterrupt


def ctypes_argument_error():
    """``ctypes.ArgumentError('argument 1: KeyboardInterrupt: ')``, with no cause or context."""
    function = ctypes.CDLL(None).abs
    function.argtypes = [_Interrupted]
    try:
        function(1)
    except ctypes.ArgumentError as exc:
        return exc
    raise AssertionError("ctypes converted the argument")


class _InterruptedCallback(ca.Callback):
    def __init__(self):
        ca.Callback.__init__(self)
        self.construct("interrupted", {})

    def get_n_in(self):
        return 1

    def get_n_out(self):
        return 1

    def eval(self, arg):
        raise KeyboardInterrupt


def casadi_runtime_error():
    """CasADi's ``RuntimeError("Error in Function::call for ... :\\nKeyboardInterrupt")`` of a call interrupted
    inside."""
    callback = _InterruptedCallback()
    try:
        callback(1.0)
    except RuntimeError as exc:
        return exc
    raise AssertionError("CasADi's call returned")


def systemerror_from_casadi():
    """CPython's ``SystemError`` of a C function that returned with the interrupt set (CasADi's ``DM.__array__``)."""
    try:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as interrupt:
            raise SystemError("<function DM.__array__> returned a result with an exception set") from interrupt
    except SystemError as exc:
        return exc


#: every kind, by name (for ``pytest.mark.parametrize``)
WRAPPED = {"ctypes": ctypes_argument_error, "casadi": casadi_runtime_error, "systemerror": systemerror_from_casadi}
