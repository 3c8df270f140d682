"""Visual features of the radial model and their interaction matrices (paper Section 3).

Pure numpy, batched: every function accepts leading batch dimensions (``(..., N, 2)`` points,
``(..., N)`` depths) and runs the same vectorised code for one scene or thousands.

- :mod:`.points`: ``x_n`` and its angle ``alpha`` (eq. 14-16, 19-21);
- :mod:`.pairs`: the rotation-invariant ``c_ij = x_ni^T x_nj`` (eq. 12-13, 17-18);
- :mod:`.virtual_point`: the virtual point ``p1`` and its angle ``alpha_m`` (eq. 22-29);
- :mod:`.compute`: everything at once; :mod:`.planar`: the ``(v_x, v_y, omega_z)`` columns.

Conventions: camera twist ``tau = (v_x, v_y, v_z, omega_x, omega_y, omega_z)`` in the camera
frame, a static point moves as ``dP/dt = -v - omega x P``, ``ds/dt = L tau``. With it the
printed eq. (15)-(18), (21), (24), (26) are right; the tests check every matrix against central
finite differences of the feature along ``exp(t tau)``.
"""

from radial_ibvs_gym.features.compute import Features, compute_features
from radial_ibvs_gym.features.pairs import L_cij, c_ij, pair_indices
from radial_ibvs_gym.features.planar import PLANAR_COLUMNS, planar
from radial_ibvs_gym.features.points import L_alpha, L_xn, alpha
from radial_ibvs_gym.features.virtual_point import (
    L_alpha_m,
    alpha_m,
    virtual_point,
    virtual_point_weights,
)

__all__ = [
    "PLANAR_COLUMNS",
    "Features",
    "L_alpha",
    "L_alpha_m",
    "L_cij",
    "L_xn",
    "alpha",
    "alpha_m",
    "c_ij",
    "compute_features",
    "pair_indices",
    "planar",
    "virtual_point",
    "virtual_point_weights",
]
