"""Angle helpers."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["wrap_angle", "wrap_angle_scalar"]

_TWO_PI = 2.0 * math.pi


def wrap_angle(angle: ArrayLike) -> NDArray[np.float64]:
    """Wrap angles to the half-open interval ``[-pi, pi)``.

    Parameters
    ----------
    angle
        Angles in radians, any shape.

    Returns
    -------
    numpy.ndarray
        Same shape as ``angle``, in radians, in ``[-pi, pi)``.
    """
    a = np.asarray(angle, dtype=np.float64)
    shifted = np.mod(a + np.pi, 2.0 * np.pi)
    # np.mod(-tiny, 2 pi) rounds up to exactly 2 pi: fold it back so the result stays < pi.
    shifted = np.where(shifted >= 2.0 * np.pi, 0.0, shifted)
    return shifted - np.pi


def wrap_angle_scalar(angle: float) -> float:
    """Wrap one angle (radians) to ``[-pi, pi)``; a fast scalar twin of :func:`wrap_angle`."""
    shifted = (angle + math.pi) % _TWO_PI
    if shifted >= _TWO_PI:  # (-tiny) % 2 pi rounds up to 2 pi
        shifted = 0.0
    return shifted - math.pi
