"""Collision-free paths in a room with a map: free space for a turning robot, and OMPL.

A position is free when the robot can turn in place there: its footprint swept over every
heading (a disc of radius ``radius``) stays inside the room and clear of every obstacle; and,
with a visibility requirement, it sees at least that many landmarks there, each seen when its
horizontal distance lies within the range the nominal camera sees it at. :func:`plan_path`
returns the straight segment from start to goal where that is free, otherwise a path of OMPL
(RRT-Connect in SE(2), then simplified), seeded from the episode (the same episode, the same
plan). The ``planner`` policy (:mod:`radial_ibvs_agents.analytic.planner`) follows these paths.

OMPL is optional: ``pip install 'radial_ibvs_gym[planning]'``.
"""

from __future__ import annotations

import hashlib
import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["PLANNING_EXTRA", "Visibility", "import_ompl", "plan_path", "segment_free"]

#: what to install for the planner
PLANNING_EXTRA = "pip install 'radial_ibvs_gym[planning]'"
F64 = NDArray[np.float64]


def import_ompl() -> tuple[Any, Any, Any]:
    """Return OMPL's ``base``, ``geometric`` and ``util`` (a ValueError names the extra)."""
    try:
        from ompl import base, geometric, util
    except ImportError:
        raise ValueError(
            f"the planner needs OMPL, which is not installed: {PLANNING_EXTRA}"
        ) from None
    return base, geometric, util


#: the landmarks the plan keeps in view: ``(landmarks (L, 3), ranges (L, 2), least count)``
Visibility = tuple[F64, F64, int] | None


def _free(points: F64, room: F64, obstacles: F64, radius: float, view: Visibility = None) -> bool:
    """Whether discs of ``radius`` at ``points`` ``(P, 2)`` are inside the room and clear.

    With ``view``, every point must also see at least that many landmarks: a landmark is seen
    when its horizontal distance lies within its visible range (the omnidirectional camera
    sees all around).
    """
    x, y = points[:, 0], points[:, 1]
    if not ((x >= radius).all() and (y >= radius).all()):
        return False
    if not ((x <= room[0] - radius).all() and (y <= room[1] - radius).all()):
        return False
    for ox, oy, r in obstacles:
        if r > 0 and (np.hypot(x - ox, y - oy) < r + radius).any():
            return False
    if view is not None:
        landmarks, ranges, least = view
        d = np.hypot(landmarks[None, :, 0] - x[:, None], landmarks[None, :, 1] - y[:, None])
        seen = ((d > ranges[None, :, 0]) & (d < ranges[None, :, 1])).sum(axis=1)
        if (seen < least).any():
            return False
    return True


def segment_free(
    a: F64, b: F64, room: F64, obstacles: F64, radius: float, view: Visibility = None
) -> bool:
    """Whether the disc of ``radius`` (metres) moves from ``a`` to ``b`` ``(2,)`` without a hit.

    Checked every centimetre along the segment.
    """
    n = max(2, math.ceil(float(np.hypot(*(b - a))) / 0.01) + 1)
    t = np.linspace(0.0, 1.0, n)[:, None]
    return _free(a + t * (b - a), room, obstacles, radius, view)


def plan_path(
    start: F64,
    goal: F64,
    room: F64,
    obstacles: F64,
    radius: float,
    *,
    view: Visibility = None,
    time_limit_s: float = 2.0,
) -> F64 | None:
    """Plan a collision-free path of straight segments for a disc of ``radius`` metres.

    Parameters
    ----------
    start, goal
        ``(2,)`` positions, metres.
    room
        ``(2,)`` width and depth of the room ``[0, w] x [0, d]``, metres.
    obstacles
        ``(K, 3)`` circles ``(x, y, radius)``, metres (radius 0: padding).
    radius
        The disc's radius, metres.
    view
        ``(landmarks (L, 3), ranges (L, 2), n)``: every point of the path must see at least
        ``n`` landmarks (``None``: no visibility rule).
    time_limit_s
        OMPL's planning budget, seconds (used only when the straight segment is blocked).

    Returns
    -------
    numpy.ndarray or None
        ``(M, 2)`` waypoints from ``start`` to ``goal`` (both included), or ``None`` if none
        was found (or the start or goal is not free).
    """
    start, goal = np.asarray(start, dtype=np.float64), np.asarray(goal, dtype=np.float64)
    if segment_free(start, goal, room, obstacles, radius, view):
        return np.stack([start, goal])
    ends = np.stack([start, goal])
    if not _free(ends, room, obstacles, radius, view):
        return None
    path = _ompl_path(start, goal, room, obstacles, radius, 0.0, view, time_limit_s)
    if path is None:  # OMPL checks states every 5 mm: its path may graze; plan with a margin
        path = _ompl_path(start, goal, room, obstacles, radius, 0.01, view, time_limit_s)
    return path


def _ompl_path(
    start: F64,
    goal: F64,
    room: F64,
    obstacles: F64,
    radius: float,
    clearance: float,
    view: Visibility,
    time_limit_s: float,
) -> F64 | None:
    """Plan with OMPL for a disc of ``radius + clearance``; check each segment at ``radius``."""
    ob, og, ou = import_ompl()
    ou.setLogLevel(ou.LogLevel.LOG_NONE)
    # the episode's own seed: the same map, start and goal give the same plan in any process
    data = np.concatenate([start, goal, room, obstacles.ravel()]).tobytes()
    ou.RNG.setSeed(int.from_bytes(hashlib.sha256(data).digest()[:4], "little") % 2**31 or 1)
    space = ob.SE2StateSpace()
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(0, 0.0)
    bounds.setHigh(0, float(room[0]))
    bounds.setLow(1, 0.0)
    bounds.setHigh(1, float(room[1]))
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    setup.setStateValidityChecker(
        lambda s: _free(np.array([[s.getX(), s.getY()]]), room, obstacles, radius + clearance, view)
    )
    setup.getSpaceInformation().setStateValidityCheckingResolution(0.005)
    begin, end = space.allocState(), space.allocState()
    begin.setX(float(start[0]))
    begin.setY(float(start[1]))
    begin.setYaw(0.0)
    end.setX(float(goal[0]))
    end.setY(float(goal[1]))
    end.setYaw(0.0)
    setup.setStartAndGoalStates(begin, end)
    setup.setPlanner(og.RRTConnect(setup.getSpaceInformation()))
    if not setup.solve(time_limit_s) or not setup.haveExactSolutionPath():
        return None
    setup.simplifySolution()
    states = setup.getSolutionPath().getStates()
    path = np.array([[s.getX(), s.getY()] for s in states], dtype=np.float64)
    path[0], path[-1] = start, goal
    segments_ok = all(
        segment_free(path[k], path[k + 1], room, obstacles, radius, view)
        for k in range(len(path) - 1)
    )
    return path if segments_ok else None
