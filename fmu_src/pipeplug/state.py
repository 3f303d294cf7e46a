"""Exact, safe serialisation of a model state (a dict of floats, ints and numpy arrays)."""
from __future__ import annotations

import io

import numpy as np

__all__ = ["state_to_bytes", "state_from_bytes"]


def state_to_bytes(state: dict) -> bytes:
    """Serialise a state bit-exactly (numpy ``.npz``, no pickle)."""
    buf = io.BytesIO()
    np.savez(buf, **{k: np.asarray(v) for k, v in state.items()})
    return buf.getvalue()


def state_from_bytes(data: bytes) -> dict:
    """Inverse of :func:`state_to_bytes` (refuses pickled objects)."""
    with np.load(io.BytesIO(bytes(data)), allow_pickle=False) as npz:
        return {k: (npz[k].item() if npz[k].ndim == 0 else npz[k].copy()) for k in npz.files}
