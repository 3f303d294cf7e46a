"""Every workaround of pythonfmu 0.7 behaviour that the FMUs need, in one place.

pythonfmu 0.7.0 runs a slave class inside its binary (``<modelIdentifier>_pythonfmu.so``,
``<modelIdentifier>.dll``). The behaviours below are measured on that version; each has a test
in ``tests/fmu/test_pythonfmu07.py`` that drives pythonfmu's own binary and fails when an upgrade
changes the behaviour, so that its workaround can be reviewed. Workarounds marked *loader* are
done by the FMUs' linux64 binary (``native/loader.c``) in front of pythonfmu's; pythonfmu's win64
binary is shipped unchanged and has none of them.

=====  ===================================================================  ==================
 id     pythonfmu 0.7 behaviour                                              workaround
=====  ===================================================================  ==================
 P1     An exception of the slave is reported as fmi2Fatal, logged with a    :class:`Refusal`;
        NULL category; there is no way to return fmi2Error.                 loader: fmi2Error
 P2     After a call raises, it releases its references to the instance,     :func:`outlive_
        its log queue and its class (and again at fmi2Reset/FreeInstance):   the_exception`
        the next call would reach freed objects.
 P3     With ``loggingOn = fmi2False`` (fmpy's ``simulate_fmu`` default) it  loader: pythonfmu's
        drops every line, its fatal one included; fmi2SetDebugLogging's      logging always on,
        categories filter error lines too.                                   the loader filters
 P4     A message reaches the host's logger as its printf format string.    :func:`escape_percent`
 P5     Lines queued by the slave in a call that raises are given to the     the base never
        host's logger while the exception is pending: a Python host's        queues a line in a
        logger runs with an error set, and the exception is lost ("unknown   call that raises
        error" instead of the refusal).
 P6     Value references reach the slave as C ``int``: 2**31 and above       :func:`value_
        arrive negative.                                                     reference`
 P7     fmi2SetString of bytes that are not UTF-8 leaves a NULL in the list  loader: such bytes
        it passes (fmi2Fatal, instance released); a NULL string arrives as   arrive as
        None.                                                                :data:`NOT_UTF8`
 P8     The resource URI is taken apart by deleting ``file://`` and          loader: one
        turning ``%20`` into a space; a folder without the slave's files     spelling, checked
        makes fmi2Instantiate call a NULL class (segfault); a NULL           folder; NULL name
        instanceName aborts the host (std::logic_error).                     refused
 P9     An FMU state is the Python object ``_get_fmu_state`` returned,       the base copies;
        handed back as is; a NULL, freed or foreign pointer is used as one;  loader: handles
        fmi2SerializeFMUstate copies exactly ``size`` bytes (a too small     checked, framed
        size truncates under fmi2OK, a larger one reads past the data).      and sized
 P10    The state (de)serialization methods are called on the class: an      :func:`never_
        exception there releases the instance of P2 without any refusal.   raising`
 P11    fmi2Instantiate executes the slave script once more with the        :data:`SCRIPT`
        module's namespace as globals and releases that namespace once
        after it (a reference it only borrowed).
 P12    pythonfmu enforces no FMI call order (fmi2SetupExperiment after      the base's state
        initialization rebases the slave's time).                            machine
=====  ===================================================================  ==================

Importing this module imports neither pythonfmu nor numpy.
"""
from __future__ import annotations

import ctypes
import functools

__all__ = ["Refusal", "escape_percent", "outlive_the_exception", "value_reference",
           "NOT_UTF8", "never_raising", "SCRIPT", "VR_RANGE"]

#: P6: fmi2ValueReference is unsigned 32-bit; pythonfmu passes it as a C int.
VR_RANGE = 2 ** 32

#: P7: how the loader hands over a string that is not UTF-8 (the bytes follow in hex). It
#: starts with ESC, which no FMI String of this project holds (loader.c: NOT_UTF8).
NOT_UTF8 = "\x1bnot UTF-8: "


class Refusal(RuntimeError):
    """The exception a slave raises to refuse a call with fmi2Error (P1).

    pythonfmu logs ``repr`` of it inside its fmi2Fatal line; the loader finds
    ``<modelIdentifier>Refusal: `` there and gives the host the refusal's own line with
    fmi2Error instead (loader.c: REFUSAL).

    Parameters
    ----------
    model_identifier : str
        The FMU's modelIdentifier.
    line : str
        The one log line, with ``%`` already escaped.
    """

    def __init__(self, model_identifier: str, line: str):
        super().__init__(line)
        self.model_identifier = model_identifier

    def __repr__(self) -> str:
        return f"{self.model_identifier}Refusal: {self}"


def escape_percent(text: str) -> str:
    """P4: ``text`` with ``%`` doubled, so that a host's printf-style logger prints it as is."""
    return text.replace("%", "%%")


def outlive_the_exception(instance) -> None:
    """P2: keep ``instance`` alive through pythonfmu's handling of the exception it raises next.

    One extra reference each to the instance, its log queue and its class balances the one
    pythonfmu releases, so the next call (or fmi2Reset, fmi2FreeInstance) reaches live objects.
    Call it right before raising, once per exception.
    """
    incref = ctypes.pythonapi.Py_IncRef
    incref.argtypes, incref.restype = [ctypes.py_object], None
    for obj in (instance, instance.log_queue, type(instance)):
        incref(obj)


def value_reference(vr: int) -> int:
    """P6: the value reference the host passed, from the C int pythonfmu made of it."""
    return vr % VR_RANGE


def never_raising(fallback):
    """P10: a decorator making a state (de)serialization method return ``fallback(exc)``
    instead of raising (the base refuses the result where it is used, with a line)."""
    def decorate(method):
        @functools.wraps(method)
        def wrapper(*args):
            try:
                return method(*args)
            except Exception as exc:          # anything: see P10
                return fallback(exc)
        return wrapper
    return decorate


# P11: pythonfmu 0.7's fmi2Instantiate imports the slave script's module, executes the file once
# more with the module's namespace as globals and a fresh dict as locals (to find the class),
# and then releases that namespace, which it had only borrowed. Each instantiation would leave
# the namespace one reference short, until it is freed under the module. The script takes the
# reference back in exactly that execution, the one whose locals are not its globals.
SCRIPT = '''"""The {cls} slave of build {tag} (see pipeplug_fmu.build)."""
import ctypes as _ctypes

from {prefix}_fmu_{tag}.{module} import {cls}

__all__ = ["{cls}"]

if locals() is not globals():   # pythonfmu's class search: it releases globals() once after
    _ctypes.pythonapi.Py_IncRef(_ctypes.py_object(globals()))
'''
