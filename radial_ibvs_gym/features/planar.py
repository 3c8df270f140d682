"""Restriction of interaction matrices to the motions of a robot on a plane."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_last_dim

__all__ = ["PLANAR_COLUMNS", "planar"]

#: Columns ``(v_x, v_y, omega_z)`` of a 6-column interaction matrix.
PLANAR_COLUMNS = (0, 1, 5)


def planar(L: ArrayLike) -> NDArray[np.float64]:
    """Keep the ``(v_x, v_y, omega_z)`` columns of interaction matrices.

    With the camera's z axis (the mirror axis) normal to the floor, a robot moving on the floor
    only produces camera velocities ``v_x``, ``v_y`` (in the floor plane) and ``omega_z``
    (about the vertical axis); ``v_z = omega_x = omega_y = 0``, so the other three columns
    never contribute to ``ds/dt = L tau``. (For a unicycle robot with the camera on its
    rotation axis, ``v_y = 0`` as well.)

    Parameters
    ----------
    L
        ``(..., 6)`` interaction matrices, columns
        ``(v_x, v_y, v_z, omega_x, omega_y, omega_z)``.

    Returns
    -------
    numpy.ndarray
        ``(..., 3)``: columns ``(v_x, v_y, omega_z)`` (a copy).

    Raises
    ------
    ValueError
        If the last dimension of ``L`` is not 6.
    """
    m = as_float_array(L, "L")
    check_last_dim(m, 6, "L")
    return m[..., list(PLANAR_COLUMNS)]
