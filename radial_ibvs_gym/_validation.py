"""Input checks shared by every layer: clear ``ValueError`` messages that name the bad value.

This module is at the bottom of the import graph (pure numpy, no gymnasium, no pymunk).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "as_float_array",
    "check_finite",
    "check_last_dim",
    "check_positive",
]


def as_float_array(value: ArrayLike, name: str) -> NDArray[np.float64]:
    """Convert ``value`` to a float64 array, raising ``ValueError`` if that fails.

    Parameters
    ----------
    value
        Anything ``numpy.asarray`` accepts.
    name
        Name of the argument, used in the error message.

    Returns
    -------
    numpy.ndarray
        ``value`` as ``float64`` (no copy when it already is).
    """
    try:
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric, got {value!r}") from exc


def check_finite(array: NDArray[Any], name: str) -> None:
    """Raise ``ValueError`` if ``array`` holds NaN or inf, naming the first bad entry."""
    finite = np.isfinite(array)
    if not np.all(finite):
        index = tuple(int(i) for i in np.argwhere(~finite)[0])
        raise ValueError(f"{name} must be finite, got {array[index]!r} at index {index}")


def check_last_dim(array: NDArray[Any], size: int, name: str) -> None:
    """Raise ``ValueError`` unless ``array.shape[-1] == size``."""
    if array.ndim == 0 or array.shape[-1] != size:
        raise ValueError(f"{name} must have shape (..., {size}), got shape {array.shape}")


def check_positive(value: float, name: str, *, allow_zero: bool = False) -> float:
    """Return ``float(value)`` if it is finite and positive (or zero when allowed).

    Raises
    ------
    ValueError
        Naming ``name`` and the value, when the check fails.
    """
    try:
        v = float(value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a number, got {value!r}") from exc
    ok = np.isfinite(v) and (v >= 0.0 if allow_zero else v > 0.0)
    if not ok:
        bound = "non-negative" if allow_zero else "positive"
        raise ValueError(f"{name} must be finite and {bound}, got {value!r}")
    return v
