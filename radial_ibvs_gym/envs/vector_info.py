"""The native vector env's ``info``: Gymnasium's dict of arrays with a ``_key`` mask per key."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["masked", "put", "select", "spread"]


def spread(values: dict[str, Any], indices: NDArray[np.intp], mask: NDArray[np.bool_]) -> dict:
    """Rows of the envs ``indices`` as full arrays (zeros elsewhere) with ``_key`` masks."""
    out: dict[str, Any] = {}
    for key, rows in values.items():
        if isinstance(rows, dict):
            out[key] = spread(rows, indices, mask)
        else:
            full = np.zeros((len(mask), *rows.shape[1:]), dtype=rows.dtype)
            full[indices] = rows
            out[key] = full
        out[f"_{key}"] = mask.copy()
    return out


def put(info: dict[str, Any], values: dict[str, Any], indices: NDArray[np.intp]) -> None:
    """Write the rows of the envs ``indices`` into ``info`` (nested dicts too)."""
    for key, rows in values.items():
        if isinstance(rows, dict):
            put(info[key], rows, indices)
        else:
            info[key][indices] = rows


def masked(values: dict[str, Any], mask: NDArray[np.bool_]) -> dict[str, Any]:
    """``values`` with a ``_key`` mask beside every key (Gymnasium's vector info convention)."""
    out: dict[str, Any] = {}
    for key, value in values.items():
        out[key] = masked(value, mask) if isinstance(value, dict) else value
        out[f"_{key}"] = mask.copy()
    return out


def select(info: dict[str, Any], mask: NDArray[np.bool_]) -> dict[str, Any]:
    """Keep the entries of the envs in ``mask``: other rows zeroed and their masks off."""
    out: dict[str, Any] = {}
    for key, value in info.items():
        if key.startswith("_"):
            continue
        if isinstance(value, dict):
            out[key] = select(value, mask)
        elif isinstance(value, np.ndarray):
            # objects (a detection's status string): None elsewhere, as Gymnasium's _add_info
            kept = np.full_like(value, None) if value.dtype == object else np.zeros_like(value)
            kept[mask] = value[mask]
            out[key] = kept
        else:
            continue
        out[f"_{key}"] = mask & info.get(f"_{key}", np.ones_like(mask))
    return out
