"""The closed table of model options.

Every option has a fixed set of allowed values and a default. An unknown option or value is
an error that names the allowed ones (like PyBaMM's options). The options are read once, when a
model is built; they choose which submodels exist, never a branch in a time loop.
"""
from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from .params import ParameterError

__all__ = ["OPTIONS", "Options"]

#: option name -> (allowed values, default, meaning)
OPTIONS: dict[str, tuple[tuple, object, str]] = {
    "solver": (("exact", "fd"), "exact",
               "rigid models: event-driven exact solver, or the paper's explicit scheme"),
    "contact_growth": ((False, True), False,
                       "model II: outer friction over the penetrated length min(max(s,0),L1)"),
    "elastic": ((False, True), False, "model III: pipe and plug are elastic rods"),
    "plug_growth": ((False, True), False,
                    "the plug grows by the soil that enters the pipe's front end while the pipe "
                    "advances over it (coring); rigid models: it shrinks by what leaves it while "
                    "it moves ahead of the pipe, model III: it keeps its length then"),
}


@dataclass(frozen=True)
class Options:
    """A validated choice of options (see :data:`OPTIONS`)."""

    solver: str = "exact"
    contact_growth: bool = False
    elastic: bool = False
    plug_growth: bool = False
    #: the rigid models' exact solver with a plug of constant length (set from the options
    #: above): the single-case API's common build
    rigid_exact: bool = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "rigid_exact", self.solver == "exact" and not self.elastic
                           and not self.plug_growth)

    @classmethod
    def from_mapping(cls, given: Mapping[str, object] | None = None) -> Options:
        """Validate ``given`` against the table and fill in defaults.

        Raises
        ------
        ParameterError
            For an unknown option (naming the known ones) or a value outside the allowed set.
        """
        given = given or _NONE
        try:                          # a choice seen before: validated then
            return _SEEN[_key(given)]
        except (KeyError, TypeError):   # new, or unhashable (not an allowed value)
            pass
        given = dict(given)
        for key, value in given.items():
            if key not in OPTIONS:
                raise ParameterError(key, value, "an option among " + ", ".join(OPTIONS))
            if not _is_allowed(key, value):
                raise ParameterError(key, value,
                                     "one of " + ", ".join(map(repr, OPTIONS[key][0])))
        options = cls(**{k: given.get(k, spec[1]) for k, spec in OPTIONS.items()})
        if cls is Options:
            _SEEN[_key(given)] = options
        return options

    def active_groups(self) -> frozenset[str]:
        """Which conditional parameter groups these options make active."""
        if self.elastic:
            return _ELASTIC
        return _FD if self.solver == "fd" else _NO_GROUP


_ELASTIC, _FD, _NO_GROUP = frozenset({"elastic"}), frozenset({"fd"}), frozenset()
#: validated choices by their (name, type, value) items: few, since every value is one of the
#: allowed ones (so a build does not check the table again)
_SEEN: dict[tuple, Options] = {}
_NONE: dict = {}                  # no option given


def _key(given) -> tuple:
    """The key of a choice in :data:`_SEEN`: its names, values and the values' types."""
    key = ()
    for name, value in given.items():
        key += (name, type(value), value)
    return key


#: the allowed values of each option with their types (so that 1 is not True, nor 1.0 1)
_ALLOWED = {name: {(type(a), a) for a in spec[0]} for name, spec in OPTIONS.items()}


def _is_allowed(name: str, value: object) -> bool:
    """True when ``value`` is one of the allowed values of option ``name``, of its type."""
    try:
        return (type(value), value) in _ALLOWED[name]
    except TypeError:                 # unhashable: not among the allowed values
        return False
