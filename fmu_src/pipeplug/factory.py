"""Build the model that validated parameters and options call for (the only place choosing one).

Only the chosen variant's modules are imported: a rigid model never imports the elastic
kernels (nor numba).
"""
from __future__ import annotations

from collections.abc import Mapping

from .interface import PROFILE_POINTS, Model
from .options import Options
from .params import ParameterError, Params

__all__ = ["build_model"]

_NONE: dict = {}                       # no parameter given


def build_model(params: Params | Mapping[str, float] | None = None,
                options: Options | Mapping[str, object] | None = None, *,
                compiled: bool = True, profile_points: int = 0) -> Model:
    """Validate parameters and options and build the model they call for.

    Parameters
    ----------
    params : Params or mapping, optional
        Parameter values by contract name (SI); missing ones take their defaults.
    options : Options or mapping, optional
        ``solver`` ("exact" | "fd"), ``contact_growth`` (bool), ``elastic`` (bool),
        ``plug_growth`` (bool, with ``elastic``).
    compiled : bool, optional
        The exact rigid solver runs compiled by numba when it is installed (default), or as
        plain Python (``False``: no numba import, which a short run may not repay). The elastic
        kernels are compiled whenever numba is available; ``PIPEPLUG_NO_JIT=1`` turns both off.
    profile_points : int, optional
        Sections of the profiles (:data:`~pipeplug.interface.PROFILES`, ``model.profiles()``):
        0 (default) for none, else within :data:`~pipeplug.interface.PROFILE_POINTS`.

    Returns
    -------
    Model
        A fresh model at t = 0, at rest.

    Raises
    ------
    ParameterError
        Naming the offending parameter or option, its value and the allowed set.
    """
    if not isinstance(options, Options):
        options = Options.from_mapping(options)
    if compiled and not profile_points and options.rigid_exact:
        # the common case, checked and built compiled at once (or None: the general path)
        model = (_COMPILED_MODEL or _compiled_model())(
            params.__dict__ if isinstance(params, Params) else params or _NONE,
            options.contact_growth)
        if model is not None:
            return model
    if not isinstance(params, Params):
        params = Params.from_mapping(params or {})
    params.validate(options.active_groups())
    _check_profile_points(profile_points)
    if params.has_ram and not options.elastic:
        _check_rigid_ram(params, options)
    if params.has_face:
        _check_face(params, options)
    if params.has_damping:
        _check_damping(params, options)
    if options.plug_growth:
        _check_growth(params, options)
        if not options.elastic:
            model = _variant("rigid_growth")(params, options)
            if profile_points:
                from .rigid.stress import RigidProfiles
                model._profiler = RigidProfiles(params, options.contact_growth, profile_points)
            return model
    if options.elastic:
        name = "growth" if options.plug_growth else "elastic"
        return _variant(name)(params, options, profile_points=profile_points)
    if options.solver == "fd":
        model = _variant("fd")(params, options)
    elif params.has_damping:          # Smith damping: pieces of exponentials
        model = _variant("damped")(params, options)
    else:
        model = _variant("exact")(params, options, compiled)
    if profile_points:
        from .rigid.stress import RigidProfiles
        model._profiler = RigidProfiles(params, options.contact_growth, profile_points)
    return model


_COMPILED_MODEL = None                 # pipeplug.rigid.exact.compiled_model, once imported


def _compiled_model():
    """:func:`pipeplug.rigid.exact.compiled_model`, imported at the first build that takes it."""
    global _COMPILED_MODEL
    from .rigid.exact import compiled_model
    _COMPILED_MODEL = compiled_model
    return compiled_model


def _check_profile_points(n) -> None:
    """Refuse a number of profile sections outside :data:`PROFILE_POINTS` (0: none)."""
    _, lower, upper = PROFILE_POINTS
    if type(n) is not int or not (n == 0 or lower <= n <= upper):
        raise ParameterError("profile_points", n, f"an integer >= {lower} and <= {upper}")


def _elastic() -> type:
    from .elastic.model import ElasticModel
    return ElasticModel


def _growth() -> type:
    from .elastic.growth import GrowthModel
    return GrowthModel


def _fd() -> type:
    from .rigid.fd import RigidFd
    return RigidFd


def _rigid_growth() -> type:
    from .rigid.growth import RigidGrowth
    return RigidGrowth


def _exact() -> type:
    from .rigid.exact import RigidExact
    return RigidExact


def _damped() -> type:
    from .rigid.damped import RigidDamped
    return RigidDamped


_IMPORTS = {"elastic": _elastic, "growth": _growth, "fd": _fd, "exact": _exact,
            "damped": _damped, "rigid_growth": _rigid_growth}
_CLASSES: dict[str, type] = {}        # the variants imported so far


def _variant(name: str) -> type:
    """The model class of variant ``name``, its module imported at its first build only (an
    import statement per build costs more than a small model's build)."""
    try:
        return _CLASSES[name]
    except KeyError:
        return _CLASSES.setdefault(name, _IMPORTS[name]())


def _check_rigid_ram(params: Params, options: Options) -> None:
    """Refuse a ram where the rigid solvers cannot carry it: the exact solver carries it in
    model I (constant soil friction, or none); the paper's explicit scheme has none."""
    if options.solver == "fd":
        raise ParameterError("ram_mass", params.ram_mass, "0 with solver = 'fd' (the paper's "
                             "explicit scheme has no ram; the exact solver and the elastic "
                             "model carry one)")
    if options.contact_growth and params.tau1 > 0.0:
        raise ParameterError("ram_mass", params.ram_mass, "0 with contact_growth and tau1 > 0 "
                             "(model II: the soil's friction growing with the penetration and "
                             "the ram make two coupled frequencies, which the exact solver "
                             "does not carry in closed form; model I or the elastic model "
                             "carry a ram)")


def _check_face(params: Params, options: Options) -> None:
    """Refuse an end resistance where a model does not carry it yet: with a ram, the rigid
    model II (its front end meets the soil at U = 0, a change of the pieces the ram's do not
    look for; the exact solver carries a ram with end resistance in model I)."""
    name = "q_face" if params.q_face > 0.0 else "q_plug_face"
    if params.has_ram and not options.elastic and options.contact_growth:
        raise ParameterError(name, getattr(params, name), "0 with a ram (ram_mass > 0) and "
                             "contact_growth in the rigid models (model I or the elastic "
                             "model carry both)")


def _check_damping(params: Params, options: Options) -> None:
    """Refuse Smith damping where a model does not carry it: with a growing plug in the rigid
    models (their growing plug's solver carries no damping), with a ram in the rigid models,
    and in model II's exact solver (the shaft's damping force J_shaft P1 tau1 U1 U1' is not
    linear: no closed-form pieces; the fd scheme carries it). The elastic model carries it
    with every other effect."""
    if options.elastic:
        return
    name = "J_shaft" if params.J_shaft > 0.0 else "J_face"
    value = getattr(params, name)
    if options.plug_growth:
        raise ParameterError(name, value, "0 with plug_growth in the rigid models (their "
                             "growing plug's solver carries no damping; the elastic model "
                             "carries both)")
    if params.has_ram:
        raise ParameterError(name, value, "0 with a ram (ram_mass > 0) in the rigid models "
                             "(the elastic model carries both)")
    if options.contact_growth and options.solver == "exact":
        raise ParameterError(name, value, "0 with contact_growth and solver = 'exact' (model "
                             "II's damped shaft friction J_shaft P1 tau1 U1 U1' is not linear, "
                             "so its pieces are not in closed form; solver = 'fd' and the "
                             "elastic model carry it)")


def _check_growth(params: Params, options: Options) -> None:
    """Refuse a growing plug where a model does not carry it: the rigid exact solver carries
    it (without a ram), and so does the elastic model; the paper's explicit scheme does not."""
    if options.elastic:
        return                        # model III carries it, with a ram too
    if options.solver == "fd":
        raise ParameterError("plug_growth", True, "False with solver = 'fd' (the exact solver "
                             "carries a growing plug)")
    if params.has_ram:
        raise ParameterError("plug_growth", True, f"False with a ram (ram_mass = "
                             f"{params.ram_mass!r} > 0) in the rigid models")
    if not params.tau2 > 0.0:
        raise ParameterError("plug_growth", True, "False with tau2 = 0 (a plug without "
                             "friction on the pipe is not simulated)")
