"""Physical and numerical parameters of PipePlug: names, SI units, defaults, ranges.

This is the one place where defaults live. The FMU's start values, the harness and the
tests all read them from :data:`PARAMETERS`.

Derived quantities (paper, section 1, with docs/corrections.md A6: P1 outer, P2 inner)::

    P1 = 2 pi (R1 + h1)            outer perimeter of the pipe        [m]
    P2 = 2 pi R1                   inner perimeter of the pipe        [m]
    S1 = pi ((R1 + h1)^2 - R1^2)   wall cross-section                 [m^2]
    S2 = pi R1^2                   plug cross-section                 [m^2]
    M1 = rho1 S1 L1                pipe mass                          [kg]
    M2 = rho2 S2 L2                plug mass                          [kg]
    F_face = q_face S1             end resistance on the steel annulus [N]
    F_plug_face = q_plug_face S2   end resistance on the plug's face  [N]
    C_shaft = J_shaft F1           damping of the outer shaft friction [N s/m]
    C_inner = J_shaft F2           damping of the plug's inner friction [N s/m]
    C_face = J_face F_face         damping of the annulus' end resistance [N s/m]
    C_plug_face = J_face F_plug_face   damping of the plug face's     [N s/m]

Smith damping (docs/physics.md, "Smith damping"): a sliding resistance R grows to R (1 + J v)
with the sliding speed v; ``J_shaft`` multiplies the shaft friction (outer and the plug's
inner), ``J_face`` the end resistances.
"""
from __future__ import annotations

import contextlib
import math
import threading
from dataclasses import dataclass, fields, make_dataclass, replace
from functools import cache

import numpy as np

__all__ = ["ParameterError", "Parameter", "PARAMETERS", "Params", "ParamArrays", "Limit",
           "LIMITS", "LARGEST", "DERIVED", "RECORD_DTYPE", "values_record", "check_rules",
           "first_refused", "limit_values"]


class ParameterError(ValueError):
    """A parameter or option has a value outside its allowed set.

    Parameters
    ----------
    name : str
        The variable's name, as in the FMU contract.
    value : object
        The offending value.
    allowed : str
        The allowed range or set, in words (e.g. ``"> 0"``).
    """

    def __init__(self, name: str, value: object, allowed: str):
        self.name, self.value, self.allowed = name, value, allowed
        super().__init__(f"{name} = {value!r} is not allowed; allowed: {allowed}")


@dataclass(frozen=True)
class Parameter:
    """One row of the parameter table.

    ``lower``/``upper`` are inclusive unless ``strict_lower`` is set; ``upper_of`` names another
    parameter bounding this one from above (``L2 <= L1``).
    """

    name: str
    unit: str
    default: float
    description: str
    lower: float | None = None
    strict_lower: bool = False
    upper: float | None = None
    upper_of: str | None = None
    active_with: str | None = None

    def allowed(self) -> str:
        """The allowed range in words, as logged on a refusal."""
        parts = []
        if self.lower is not None:
            parts.append(f"{'>' if self.strict_lower else '>='} {self.lower:g}")
        if self.upper is not None:
            parts.append(f"<= {self.upper:g}")
        if self.upper_of is not None:
            parts.append(f"<= {self.upper_of}")
        return "finite, " + " and ".join(parts) if parts else "finite"


PARAMETERS: tuple[Parameter, ...] = (
    Parameter("L1", "m", 1.0, "pipe length (friction length of model I)", 0.0, True),
    Parameter("L2", "m", 1.0, "plug length; 0 = no plug; the plug fills the pipe's front part", 0.0,
              upper_of="L1"),
    Parameter("R1", "m", 0.035, "pipe inner radius", 0.0, True),
    Parameter("h1", "m", 0.003, "pipe wall thickness", 0.0, True),
    Parameter("rho1", "kg/m3", 7800.0, "pipe density", 0.0, True),
    Parameter("rho2", "kg/m3", 1800.0, "plug density", 0.0, True),
    Parameter("E1", "Pa", 1.95e11, "pipe Young's modulus (elastic model)", 0.0, True,
              active_with="elastic"),
    Parameter("E2", "Pa", 6.0e8, "plug Young's modulus (elastic model)", 0.0, True,
              active_with="elastic"),
    Parameter("tau1", "Pa", 0.0, "limit shear stress, pipe outer face / soil", 0.0),
    Parameter("tau2", "Pa", 1.0e4, "limit shear stress, pipe inner face / plug", 0.0),
    Parameter("dt", "s", 2.0e-4, "largest internal step of the fd solver", 0.0, True,
              active_with="fd"),
    Parameter("dx", "m", 0.01, "elastic grid spacing; L1 and L2 must be multiples of it", 0.0,
              True, upper_of="L1/2", active_with="elastic"),
    Parameter("courant", "1", 1.0, "elastic: internal step = courant*dx/(fastest wave speed)",
              0.0, True, upper=1.0, active_with="elastic"),
    Parameter("x_monitor", "m", 0.5, "elastic: reference section whose motion is output", 0.0,
              upper_of="L1", active_with="elastic"),
    Parameter("max_internal_steps", "1", 1.0e8, "elastic and fd: the most internal steps one "
              "communication step may take (a longer step is refused)", 1.0),
    Parameter("ram_mass", "kg", 0.0, "mass of the ram striking the pipe's head; 0: no ram, Q "
              "alone drives the pipe", 0.0),
    Parameter("cushion_stiffness", "N/m", 0.0, "loading stiffness of the cushion between ram "
              "and head; 0: the ram strikes the head directly", 0.0),
    Parameter("cushion_restitution", "1", 1.0, "coefficient of restitution of the cushion "
              "(unloading stiffness cushion_stiffness / e^2)", 0.0, True, upper=1.0),
    Parameter("q_face", "Pa", 0.0, "end resistance of the soil on the steel annulus S1 while the "
              "pipe's front end advances into it (set-valued: up to q_face S1 at rest, none "
              "while it retreats); 0: absent", 0.0),
    Parameter("q_plug_face", "Pa", 0.0, "end resistance of the soil on the plug's front face S2 "
              "while the plug advances into it (the same law); 0: absent", 0.0),
    Parameter("J_shaft", "s/m", 0.0, "Smith damping of the shaft friction: a sliding contact "
              "resists with P L tau (1 + J_shaft v), v its sliding speed (the soil on the "
              "pipe's outer face, the plug on its inner face); 0: absent", 0.0, upper=1e3),
    Parameter("J_face", "s/m", 0.0, "Smith damping of the end resistances: an advancing end "
              "resists with q S (1 + J_face v), v its speed; 0: absent", 0.0, upper=1e3),
    Parameter("L2_after_cleanout", "m", 0.0, "plug length a clean-out leaves (each increase of "
              "the input cleanouts removes the plug down to it; model III: rounded down to "
              "whole cells)", 0.0, upper_of="L1"),
)

_BY_NAME = {p.name: p for p in PARAMETERS}
_DEFAULTS = {p.name: p.default for p in PARAMETERS}

#: The largest magnitude of any active parameter the models compute with (squares and products
#: of a few such values stay finite).
LARGEST = 1e100


@dataclass(frozen=True)
class Limit:
    """A derived quantity the models divide by or multiply with, and the range they compute
    with; a value outside refuses the parameter ``named`` (only where ``active_with`` is: the
    conditional group, or ``"plug"`` when the plug is simulated)."""

    quantity: str          # a property of Params: P1, S1, M1, ...
    formula: str
    unit: str
    smallest: float        # inclusive
    largest: float         # inclusive
    named: str
    active_with: str | None = None

    def allowed(self, params) -> str:
        """The allowed range in words, with the quantity's value for ``params``."""
        return (f"finite, with {self.quantity} = {self.formula} within [{self.smallest:g}, "
                f"{self.largest:g}] {self.unit} (here {_derived(self, params)!r})")


#: Computable limits: areas and masses that would underflow, friction limits (and so works)
#: that would overflow, wave speeds that would give no internal step, grids too fine to hold.
LIMITS: tuple[Limit, ...] = (
    Limit("S1", "pi((R1+h1)^2 - R1^2)", "m2", 1e-100, LARGEST, "h1"),
    Limit("M1", "rho1*S1*L1", "kg", 1e-100, LARGEST, "rho1"),
    Limit("S2", "pi*R1^2", "m2", 1e-100, LARGEST, "R1", "plug"),
    Limit("M2", "rho2*S2*L2", "kg", 1e-100, LARGEST, "rho2", "plug"),
    Limit("F1", "P1*L1*tau1", "N", 0.0, LARGEST, "tau1"),
    Limit("F2", "P2*L2*tau2", "N", 0.0, LARGEST, "tau2"),
    Limit("F_face", "q_face*S1", "N", 0.0, LARGEST, "q_face"),
    Limit("F_plug_face", "q_plug_face*S2", "N", 0.0, LARGEST, "q_plug_face"),
    Limit("C_shaft", "J_shaft*P1*L1*tau1", "N s/m", 0.0, LARGEST, "J_shaft"),
    Limit("C_inner", "J_shaft*P2*L2*tau2", "N s/m", 0.0, LARGEST, "J_shaft"),
    Limit("C_face", "J_face*q_face*S1", "N s/m", 0.0, LARGEST, "J_face"),
    Limit("C_plug_face", "J_face*q_plug_face*S2", "N s/m", 0.0, LARGEST, "J_face"),
    Limit("c1", "sqrt(E1/rho1)", "m/s", 1e-100, LARGEST, "E1", "elastic"),
    Limit("c2", "sqrt(E2/rho2)", "m/s", 1e-100, LARGEST, "E2", "elastic"),
    Limit("cells", "L1/dx", "cells", 1.0, 1e6, "dx", "elastic"),
)


# The derived quantities, each one function of a parameter holder ``p`` that reads its values
# as attributes: a Params, a ParamArrays (arrays of values; the wave speeds excepted) or, in
# compiled code, a record of RECORD_DTYPE (FORMULAS are registered with numba by the exact
# solver's record module). Arithmetic only, and ``&``/``|`` for the flags, so that the same
# source serves floats, arrays and records.
def outer_perimeter(p):
    """Outer perimeter of the pipe, P1 = 2 pi (R1 + h1) [m]."""
    return 2.0 * math.pi * (p.R1 + p.h1)


def inner_perimeter(p):
    """Inner perimeter of the pipe, P2 = 2 pi R1 [m]."""
    return 2.0 * math.pi * p.R1


def wall_section(p):
    """Cross-section of the pipe wall, S1 = pi ((R1 + h1)^2 - R1^2) [m^2]."""
    return math.pi * ((p.R1 + p.h1) ** 2 - p.R1 ** 2)


def plug_section(p):
    """Cross-section of the plug, S2 = pi R1^2 [m^2]."""
    return math.pi * p.R1 ** 2


def pipe_mass(p):
    """Pipe mass, M1 = rho1 S1 L1 [kg]."""
    return p.rho1 * wall_section(p) * p.L1


def plug_mass(p):
    """Plug mass, M2 = rho2 S2 L2 [kg]."""
    return p.rho2 * plug_section(p) * p.L2


def outer_limit(p):
    """Outer friction limit over the whole pipe length, F1 = P1 L1 tau1 [N]."""
    return outer_perimeter(p) * p.L1 * p.tau1


def inner_limit(p):
    """Inner (plug) friction limit, F2 = P2 L2 tau2 [N]."""
    return inner_perimeter(p) * p.L2 * p.tau2


def face_limit(p):
    """End resistance on the steel annulus, F_face = q_face S1 [N]."""
    return p.q_face * wall_section(p)


def plug_face_limit(p):
    """End resistance on the plug's front face, F_plug_face = q_plug_face S2 [N]."""
    return p.q_plug_face * plug_section(p)


def shaft_damping(p):
    """Damping coefficient of the outer shaft friction, C_shaft = J_shaft F1 [N s/m]."""
    return p.J_shaft * outer_limit(p)


def inner_damping(p):
    """Damping coefficient of the plug's inner friction, C_inner = J_shaft F2 [N s/m]."""
    return p.J_shaft * inner_limit(p)


def face_damping(p):
    """Damping coefficient of the annulus' end resistance, C_face = J_face q_face S1
    [N s/m]."""
    return p.J_face * face_limit(p)


def plug_face_damping(p):
    """Damping coefficient of the plug face's end resistance, C_plug_face = J_face
    q_plug_face S2 [N s/m]."""
    return p.J_face * plug_face_limit(p)


def has_plug(p):
    """True when the plug is coupled to the pipe (tau2 > 0 and L2 > 0)."""
    return (p.tau2 > 0.0) & (p.L2 > 0.0)


def has_face(p):
    """True when an end resistance acts (q_face > 0, or q_plug_face > 0 on a coupled plug)."""
    return (p.q_face > 0.0) | ((p.q_plug_face > 0.0) & has_plug(p))


def has_damping(p):
    """True when Smith damping acts on a resistance that is there (J_shaft with shaft
    friction, J_face with an end resistance)."""
    return (((p.J_shaft > 0.0) & ((p.tau1 > 0.0) | has_plug(p)))
            | ((p.J_face > 0.0) & has_face(p)))


def has_ram(p):
    """True when a ram strikes the pipe (ram_mass > 0)."""
    return p.ram_mass > 0.0


def cells(p):
    """Cells of the elastic pipe, L1/dx [1]."""
    return p.L1 / p.dx


def pipe_wave_speed(p):
    """Rod wave speed of the pipe, c1 = sqrt(E1/rho1) [m/s]."""
    return math.sqrt(p.E1 / p.rho1)


def plug_wave_speed(p):
    """Rod wave speed of the plug, c2 = sqrt(E2/rho2) [m/s]."""
    return math.sqrt(p.E2 / p.rho2)


#: the derived quantities by their names in the formulas and LIMITS (the properties of Params)
DERIVED = {"P1": outer_perimeter, "P2": inner_perimeter, "S1": wall_section, "S2": plug_section,
           "M1": pipe_mass, "M2": plug_mass, "F1": outer_limit, "F2": inner_limit,
           "F_face": face_limit, "F_plug_face": plug_face_limit, "C_shaft": shaft_damping,
           "C_inner": inner_damping, "C_face": face_damping, "C_plug_face": plug_face_damping,
           "has_plug": has_plug, "has_face": has_face, "has_damping": has_damping,
           "has_ram": has_ram, "cells": cells, "c1": pipe_wave_speed, "c2": plug_wave_speed}


class _Formulas:
    """The derived quantities (:data:`DERIVED`) as properties."""


for _name, _formula in DERIVED.items():
    setattr(_Formulas, _name, property(_formula))


class _Derived(_Formulas):
    """Construction and checks of :class:`Params`, and the derived quantities."""

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The parameter names in table order."""
        return tuple(f.name for f in fields(cls))

    def with_(self, **changes: float) -> Params:
        """A copy with some values changed (unknown names raise :class:`ParameterError`)."""
        return replace(self, **_checked_names(changes))

    @classmethod
    def from_mapping(cls, values) -> Params:
        """Parameters from a mapping of contract names; missing ones take their defaults."""
        params = object.__new__(cls)      # the fields set at once, not one by one as the
        fields = params.__dict__          # frozen dataclass's __init__ sets them
        fields.update(_DEFAULTS)
        fields.update(_checked_names(values))
        return params

    def validate(self, active: frozenset[str] = frozenset()) -> Params:
        """Check every active parameter against its range.

        Parameters
        ----------
        active : frozenset of str
            Which conditional groups are active: ``"elastic"``, ``"fd"``. Parameters tied to
            an inactive group are not checked (the contract's rule).

        Returns
        -------
        Params
            ``self``, for chaining.

        Raises
        ------
        ParameterError
            Naming the first offending parameter, its value and the allowed range.
        """
        active = frozenset(active)
        values = self.__dict__                   # the fields, read once each
        floats = True                            # every value a Python float
        for name, p, checked, low, strict, high, of, factor in _checks(active):
            value = values[name]
            if type(value) is float:             # the common case, decided without calls
                if not checked:
                    if value - value == 0.0:
                        continue
                elif ((value > low if strict else value >= low) and value <= high
                      and -LARGEST <= value <= LARGEST
                      and (of is None or value <= values[of] * factor)):
                    continue
            else:
                floats = False
            if not checked:
                ok, allowed = _finite(value), _INACTIVE
            elif not _within(p, value, self):
                ok, allowed = False, _allowed(p, self)
            else:
                ok, allowed = abs(value) <= LARGEST, _LARGEST
            if not ok:
                raise ParameterError(name, value, allowed)
        # Python floats raise where numpy scalars warn (caught by _derived either way).
        with contextlib.nullcontext() if floats else np.errstate(all="ignore"):
            plug = self.has_plug
            for limit in _limits(active):
                if limit.active_with == "plug" and not plug:
                    continue                     # the plug is not simulated
                value = _derived(limit, self)
                if not limit.smallest <= value <= limit.largest:      # False for NaN
                    raise ParameterError(limit.named, values[limit.named], limit.allowed(self))
        return self


class ParamArrays(_Formulas):
    """Parameter values of many cases at once: one array per parameter (missing ones take their
    defaults), broadcast to one length, with the derived quantities of :class:`Params` computed
    by the same formulas.

    Parameters
    ----------
    values : mapping of str to float or array
        Values by contract name (SI).
    """

    def __init__(self, values):
        named = _checked_names(values)
        columns = np.broadcast_arrays(*(np.asarray(named.get(p.name, p.default), dtype=float)
                                        for p in PARAMETERS))
        for p, column in zip(PARAMETERS, columns):
            setattr(self, p.name, np.atleast_1d(column).ravel())
        self.size = len(self.L1)

    def validate(self, active: frozenset[str] = frozenset()) -> ParamArrays:
        """Check every active parameter of every case (see :meth:`Params.validate`).

        Raises
        ------
        ParameterError
            Naming the first offending parameter and its first offending value.
        """
        active = frozenset(active)
        for p in PARAMETERS:
            values = getattr(self, p.name)
            checks = ([(_in_range(p, values, self), _allowed(p, self)),
                       (abs(values) <= LARGEST, _LARGEST)] if p in _checked(active)
                      else [(values - values == 0.0, _INACTIVE)])
            for ok, allowed in checks:
                if not np.all(ok):
                    raise ParameterError(p.name, float(values[np.argmin(ok)]), allowed)
        for limit in _limits(active):
            with np.errstate(all="ignore"):
                ok = _in_limits(limit, self)
            if not np.all(ok):
                first = int(np.argmin(ok))
                raise ParameterError(limit.named, float(getattr(self, limit.named)[first]),
                                     limit.allowed(_Case(self, first)))
        return self


Params = make_dataclass(
    "Params", [(p.name, float, p.default) for p in PARAMETERS], bases=(_Derived,), frozen=True)
Params.__doc__ = """Parameter values in SI units; defaults are the paper's base case.

Fields are the names of :data:`PARAMETERS` (one place for units, defaults and ranges).
Construct with keywords; :meth:`validate` checks the ranges.
"""
Params.__module__ = __name__


#: the parameter values as the fields of one record, in table order (compiled code reads them by
#: name from a record array over the values)
RECORD_DTYPE = np.dtype([(p.name, np.float64) for p in PARAMETERS])
_INDEX = {p.name: i for i, p in enumerate(PARAMETERS)}
_DEFAULT_VALUES = np.array([p.default for p in PARAMETERS])
_DEFAULT_VIEW = memoryview(_DEFAULT_VALUES)
_SCRATCH = threading.local()    # per thread: the values and the record over them (see below)


def values_record(values) -> tuple[np.ndarray, np.ndarray] | None:
    """``values`` over the defaults, as ``(flat, record)``: floats in table order and a record
    array of :data:`RECORD_DTYPE` over the same memory, or None when a name is unknown or a
    value is not a ``float`` (the general path converts or refuses it by name).

    The two arrays are this thread's own and are overwritten by its next call: a record dtype
    costs microseconds per array made, more than the check it serves.
    """
    try:
        flat, record, view = _SCRATCH.arrays
    except AttributeError:
        flat = _DEFAULT_VALUES.copy()
        _SCRATCH.arrays = flat, flat.view(RECORD_DTYPE), memoryview(flat)
        flat, record, view = _SCRATCH.arrays
    view[:] = _DEFAULT_VIEW           # a memoryview sets floats faster than numpy's indexing
    index = _INDEX.get
    for name, value in values.items():
        i = index(name)
        if i is None or type(value) is not float:
            return None
        view[i] = value
    return flat, record


@cache
def check_rules(active: frozenset[str]) -> tuple[np.ndarray, np.ndarray]:
    """The checks of :meth:`Params.validate` with the groups ``active`` as arrays, for
    :func:`first_refused`: per parameter ``(checked, low, strict, high, of, factor)`` (1.0 for
    true; ``of`` the index of the bounding parameter, -1 for none), per limit of :data:`LIMITS`
    ``(when, smallest, largest)``, ``when`` 0 (inactive), 1 (always) or 2 (where the plug is
    simulated)."""
    rules = np.array([(float(checked), low, float(strict), high,
                       -1.0 if of is None else float(_INDEX[of]), factor)
                      for _, _, checked, low, strict, high, of, factor in _checks(active)])
    active_limits = _limits(active)
    limits = np.array([(0.0 if x not in active_limits else 2.0 if x.active_with == "plug"
                        else 1.0, x.smallest, x.largest) for x in LIMITS])
    return rules, limits


def limit_values(p):
    """The quantities of :data:`LIMITS`, in its order, for the parameter holder ``p``."""
    return (wall_section(p), pipe_mass(p), plug_section(p), plug_mass(p), outer_limit(p),
            inner_limit(p), face_limit(p), plug_face_limit(p), shaft_damping(p),
            inner_damping(p), face_damping(p), plug_face_damping(p), pipe_wave_speed(p),
            plug_wave_speed(p), cells(p))


def first_refused(values, p, rules, limits):
    """The first value :meth:`Params.validate` refuses, without messages (compiled code runs it
    over floats; the message is built by ``validate`` itself where this finds one).

    Parameters
    ----------
    values : array of float
        The values in table order.
    p : record
        The same values as the fields of a record of :data:`RECORD_DTYPE`.
    rules, limits : arrays
        :func:`check_rules` of the active groups.

    Returns
    -------
    int
        The index of the first parameter refused, ``len(values)`` plus the index of the first
        limit refused, or -1 when every check passes.
    """
    n = values.shape[0]
    for i in range(n):
        value = values[i]
        if rules[i, 0] == 0.0:                       # not checked: finite only
            if not value - value == 0.0:
                return i
            continue
        low, of = rules[i, 1], int(rules[i, 4])
        ok = ((value > low if rules[i, 2] != 0.0 else value >= low) and value <= rules[i, 3]
              and -LARGEST <= value <= LARGEST)
        if ok and of >= 0:
            ok = value <= values[of] * rules[i, 5]
        if not ok:
            return i
    plug = has_plug(p)
    quantities = limit_values(p)
    for j in range(limits.shape[0]):
        when = limits[j, 0]
        if when == 0.0 or (when == 2.0 and not plug):
            continue
        if not limits[j, 1] <= quantities[j] <= limits[j, 2]:    # False for NaN
            return n + j
    return -1


def _checked_names(values) -> dict:
    """``values`` with numbers as floats; an unknown name raises :class:`ParameterError`."""
    for key in values:
        if key not in _BY_NAME:
            raise ParameterError(key, values[key], "one of " + ", ".join(_BY_NAME))
    return {k: v if type(v) is float else _as_number(v) for k, v in values.items()}


def _as_number(value):
    """A plain ``float`` for real numbers (numpy scalars included); anything else unchanged."""
    if type(value) is float:          # the common case, first
        return value
    if isinstance(value, (bool, str)):
        return value
    try:
        return float(value)
    except (TypeError, ValueError):
        return value


@cache
def _checked(active: frozenset[str]) -> tuple[Parameter, ...]:
    """The parameters checked when the groups ``active`` are: all but those of other groups."""
    return tuple(p for p in PARAMETERS if p.active_with is None or p.active_with in active)


@cache
def _checks(active: frozenset[str]) -> tuple[tuple, ...]:
    """Per parameter: its name, itself, whether its range is checked when the groups ``active``
    are, and its range (:func:`_range`): found once per set of groups, not searched per
    parameter and call."""
    checked = _checked(active)
    return tuple((p.name, p, any(p is c for c in checked), *_range(p)) for p in PARAMETERS)


@cache
def _range(p: Parameter) -> tuple:
    """The range of ``p`` as numbers: ``(low, strict, high, of, factor)``, the value within
    ``low`` (excluded when ``strict``) and ``high`` (-inf and inf where the table gives none),
    and at most ``factor`` times the parameter named ``of`` (None: no such bound)."""
    low = -math.inf if p.lower is None else p.lower
    high = math.inf if p.upper is None else p.upper
    of, factor = {None: (None, 1.0), "L1": ("L1", 1.0), "L1/2": ("L1", 0.5)}[p.upper_of]
    return low, p.strict_lower, high, of, factor


@cache
def _limits(active: frozenset[str]) -> tuple[Limit, ...]:
    """The limits checked when the groups ``active`` are (a ``"plug"`` limit is checked where
    the plug is simulated)."""
    return tuple(x for x in LIMITS if x.active_with in (None, "plug") or x.active_with in active)


def _finite(value) -> bool:
    """True for a finite real number (inactive parameters must still be one)."""
    return not isinstance(value, bool) and isinstance(value, (int, float)) and value - value == 0


_INACTIVE = "finite (checked also where the parameter is not used)"
_LARGEST = f"a magnitude <= {LARGEST:g} (the largest the models compute with)"


def _allowed(p: Parameter, params) -> str:
    """What a refusal of ``p`` says is allowed: its range, with the value of the parameter that
    bounds it from above."""
    if p.upper_of is None:
        return p.allowed()
    _, _, _, of, factor = _range(p)
    return f"{p.allowed()} ({p.upper_of} = {_first(getattr(params, of) * factor)!r})"


def _first(value):
    """A scalar, or the first element of an array (for messages)."""
    return float(np.ravel(value)[0]) if np.ndim(value) else value


class _Case:
    """One case of a :class:`ParamArrays`, for messages."""

    def __init__(self, arrays: ParamArrays, index: int):
        for p in PARAMETERS:
            setattr(self, p.name, float(getattr(arrays, p.name)[index]))

    def __getattr__(self, name):               # derived quantities, by Params' formulas
        return getattr(_Formulas, name).fget(self)


def _derived(limit: Limit, params):
    """The quantity of ``limit`` for ``params``; inf where its formula overflows."""
    try:
        return getattr(params, limit.quantity)
    except (OverflowError, ZeroDivisionError):
        return math.inf


def _in_limits(limit: Limit, params):
    """Whether the quantity of ``limit`` is within it (a bool, or an array of them); always
    where it is inactive (the plug not simulated)."""
    value = _derived(limit, params)
    ok = (value >= limit.smallest) & (value <= limit.largest)    # False for NaN
    if limit.active_with == "plug":
        ok = ok | ~np.asarray(params.has_plug)
    return ok


def _within(p: Parameter, value: float, params: Params) -> bool:
    """True when ``value`` is a finite number inside the range of ``p``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    return bool(_in_range(p, value, params))


def _in_range(p: Parameter, value, params):
    """Whether ``value`` is finite and inside the range of ``p``: a bool for a float, an array
    of them for an array (the one statement of the range rules)."""
    low, strict, high, of, factor = _range(p)
    ok = value - value == 0.0                              # finite
    ok = ok & ((value > low) if strict else (value >= low)) & (value <= high)
    if of is not None:
        ok = ok & (value <= getattr(params, of) * factor)
    return ok
