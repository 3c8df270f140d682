"""The rendered room: a box with circular beacons painted on its walls.

Its own module, below both the renderer (:mod:`~radial_ibvs_gym.vision.omni`) and the rays'
hits (:mod:`~radial_ibvs_gym.vision.room_rays`) that read it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym._validation import as_float_array, check_finite

__all__ = ["RoomScene"]


@dataclass(frozen=True)
class RoomScene:
    """A box room with circular beacons painted on its walls.

    Attributes
    ----------
    size
        ``(width, depth)`` of the floor, metres (walls at ``x = 0, width`` and ``y = 0, depth``).
    height
        Ceiling height, metres.
    beacons
        ``(K, 3)`` beacon centres on the walls, world frame, metres.
    beacon_radius
        Radius of the beacon discs, metres (under half the room's smaller side).
    walls
        Set on creation: the wall of each beacon (:meth:`wall_of`).
    """

    size: tuple[float, float]
    height: float
    beacons: NDArray[np.float64]
    beacon_radius: float = 0.08
    walls: tuple[int, ...] = field(init=False, repr=False, compare=False, default=())

    def __post_init__(self) -> None:
        w, d = self.size
        if not (w > 0 and d > 0 and math.isfinite(w) and math.isfinite(d)):
            raise ValueError(f"size must be a positive (width, depth), got {self.size!r}")
        if not (math.isfinite(self.height) and self.height > 0):
            raise ValueError(f"height must be positive, got {self.height!r}")
        if not (math.isfinite(self.beacon_radius) and self.beacon_radius > 0):
            raise ValueError(f"beacon_radius must be positive, got {self.beacon_radius!r}")
        beacons = as_float_array(self.beacons, "beacons").reshape(-1, 3)
        check_finite(beacons, "beacons")
        object.__setattr__(self, "beacons", beacons)
        if not 2.0 * self.beacon_radius < min(w, d):
            raise ValueError(
                f"beacon_radius {self.beacon_radius!r} m does not fit the {w} x {d} m room "
                "(it must be under half its smaller side)"
            )
        walls = []
        for b in beacons:
            wall = self.wall_of(b)
            if wall is None:
                raise ValueError(f"beacon {b.tolist()} is not on a wall of the {w} x {d} m room")
            walls.append(wall)
        object.__setattr__(self, "walls", tuple(walls))

    def wall_of(self, point: NDArray[np.float64], tol: float = 1e-6) -> int | None:
        """Wall index of a point (0: x = 0, 1: x = width, 2: y = 0, 3: y = depth), or None."""
        w, d = self.size
        for index, (coordinate, value) in enumerate(
            ((point[0], 0.0), (point[0], w), (point[1], 0.0), (point[1], d))
        ):
            if abs(coordinate - value) <= tol:
                return index
        return None
