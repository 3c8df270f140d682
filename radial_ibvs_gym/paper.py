"""The numbers of the paper's simulations (Section 4.1) and the choices that complete them.

Values marked *paper* are printed in Aliakbarpour, Tahri and Araujo (RAS 2014); values marked
*choice* are not given there (see ``docs/reading-the-paper.md``) and were chosen so that all eight
points stay in mirror A's field of view on the four parking paths.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "CAMERA_HEIGHT_M",
    "EQ39_POINTS",
    "GOAL_OFFSET_M",
    "GOAL_YAWS_RAD",
    "K1",
    "K2",
    "START_POSE",
    "goal_pose",
]

#: *paper*, eq. (39): the 8 scene points, one row per point ``(X, Y, Z)`` in metres, world frame
#: (the printed matrix has one point per column; "-0" is 0).
EQ39_POINTS: np.ndarray = np.array(
    [
        [15.6, 7.62, 0.0],
        [15.6, 8.29, 0.86],
        [7.98, 15.6, 2.52],
        [5.38, 15.6, 0.32],
        [9.0, 0.0, 2.07],
        [6.62, 0.0, 2.14],
        [0.0, 8.15, 1.30],
        [0.0, 10.32, 1.79],
    ]
)
EQ39_POINTS.setflags(write=False)

#: *choice*: start pose ``(x, y, yaw)`` (metres, radians) of the four parking tasks.
START_POSE: tuple[float, float, float] = (3.0, 3.0, 0.0)
#: *paper*: each goal is the start shifted by (4, 4) m.
GOAL_OFFSET_M: tuple[float, float] = (4.0, 4.0)
#: *paper*: goal yaws of tasks 0..3 (0, 90, 180, 270 degrees), radians.
GOAL_YAWS_RAD: tuple[float, ...] = (0.0, np.pi / 2, np.pi, 3 * np.pi / 2)
#: *choice*: height of the camera's optical centre above the floor, metres.
CAMERA_HEIGHT_M: float = 1.8
#: *paper*: gains of the smooth control law (eq. 38) in the simulations.
K1: float = 4.0
K2: float = 12.0


def goal_pose(task: int) -> tuple[float, float, float]:
    """Goal pose ``(x, y, yaw)`` of parking task ``task`` in 0..3 (metres, radians).

    Raises
    ------
    ValueError
        If ``task`` is not one of 0, 1, 2, 3.
    """
    if task not in (0, 1, 2, 3):
        raise ValueError(f"task must be 0, 1, 2 or 3, got {task!r}")
    x0, y0, _ = START_POSE
    return (x0 + GOAL_OFFSET_M[0], y0 + GOAL_OFFSET_M[1], GOAL_YAWS_RAD[task])
