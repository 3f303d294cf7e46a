"""Shared helpers for the elastic-model tests."""
from __future__ import annotations

import numpy as np

from pipeplug import Params, build_model

#: The paper's Fig. 7 scene (section 4, docs/corrections.md D1): defaults with elastic rods.
Q0, T0 = 23000.0, 0.05  # N, s


def elastic(params=None, growth=False, **changes):
    """A fresh elastic model with the given parameter changes."""
    return build_model(dict(params or {}, **changes),
                       {"elastic": True, "contact_growth": growth})


def impedance(p: Params) -> float:
    """Pipe impedance rho1 c1 S1 [N s/m]."""
    return p.rho1 * p.c1 * p.S1


def energy_residual(model) -> float:
    """W_input - (E_kinetic + E_strain + W_friction) [J]."""
    out = model.outputs()
    return out.W_input - (out.E_kinetic + out.E_strain + out.W_friction)


def sample(model, loads, h):
    """Advance by steps ``h`` [s] under the loads ``loads`` [N] (one per step); outputs."""
    rows = []
    for q in loads:
        model.advance(float(q), h)
        rows.append(model.outputs())
    return {name: np.array([getattr(r, name) for r in rows]) for name in rows[0]._fields}
