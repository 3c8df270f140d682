"""The meridian root-find compiled with numba where it is installed: the same bits as numpy.

:meth:`~radial_ibvs_gym.camera.meridian.MeridianSolver.solve` takes each point through the
table's first guess, a bracket about it and Illinois iterations, as whole-array numpy passes
(about 20 of them over every point). For the hyperboloids of the paper's mirrors,
:mod:`radial_ibvs_gym.camera._meridian_numba` does the same per point in one compiled loop:
the same operations in the same order, in IEEE double precision without fused multiply-adds,
so every root has the bits of the numpy path's (``tests/camera/test_meridian_jit.py`` checks it
over random points and mirrors). The points whose table cell does not bracket a root go back
to the numpy grid search, as in the numpy path.

numba is optional (the ``fast`` extra): without it, or with the environment variable
``RADIAL_IBVS_JIT=0``, :func:`kernel` returns ``None`` and the numpy path runs. numba is
imported at the first root-find, never when the maths is imported. The first call in a process
compiles the loop (about a second; numba caches it on disk after that).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

__all__ = ["kernel"]

_KERNEL: list[Callable[..., Any] | None] = []  # empty until the first call: [kernel or None]


def kernel() -> Callable[..., Any] | None:
    """Return the compiled hyperboloid root-find, or ``None`` (no numba, or disabled).

    ``RADIAL_IBVS_JIT=0`` in the environment disables it; it is read at each call, so a test
    can compare both paths in one process.
    """
    if os.environ.get("RADIAL_IBVS_JIT", "1") == "0":
        return None
    if not _KERNEL:
        try:
            from radial_ibvs_gym.camera._meridian_numba import solve_hyperboloid

            _warm_up(solve_hyperboloid)  # compiles now (or loads numba's cache), inside the try
        except Exception:  # no numba, or one that cannot compile or cache here
            _KERNEL.append(None)  # numpy gives the same bits
        else:
            _KERNEL.append(solve_hyperboloid)
    return _KERNEL[0]


def _warm_up(solve: Callable[..., Any]) -> None:
    """Call the loop once on a point off a one-cell table: numba compiles it for these types."""
    import numpy as np

    one = np.ones(1)
    solve(
        one, one, 1.0, 1.0, 1.0, -1.0, np.zeros((1, 5)), 1, 1, 1.0, 1.0, 1, np.empty(1),
        np.empty(1, dtype=np.bool_),
    )  # fmt: skip
