"""Random scenes of landmark bearings, seen from the goal and from a robot (the pose tests).

Shared by the tests of the pose layer (``radial_ibvs_agents.learned.networks.pose_layer``) and of
position-based servoing (``radial_ibvs_agents.analytic.pbvs``), which solve the same scenes.
``conftest.py`` puts this folder on the path, last (so nothing shadows an installed module).
"""

from __future__ import annotations

import numpy as np
import torch


def scene(seed: int, n: int, tx: float, ty: float, theta: float):
    """Bearings of ``n`` random landmarks seen from the goal and from a robot whose camera
    frame holds the goal at ``(tx, ty)``, turned by ``theta``."""
    rng = np.random.default_rng(seed)
    radius, angle = rng.uniform(0.5, 5.0, n), rng.uniform(-np.pi, np.pi, n)
    p = np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=-1)  # goal frame
    c, s = np.cos(theta), np.sin(theta)
    q = p @ np.array([[c, s], [-s, c]]) + [tx, ty]  # R p + t, the robot's frame
    now = q / np.linalg.norm(q, axis=-1, keepdims=True)
    goal = p / radius[:, None]
    return (torch.tensor(a[None]) for a in (now, goal, radius, np.ones(n)))


def distance_to_danger_circle(seed: int, n: int, tx: float, ty: float, theta: float) -> float:
    """Relative distance of the robot to the circle through the landmarks (3 landmarks only).

    With three landmarks, a robot on the circle through them (the "danger circle" of planar
    three-point resection) has a one-parameter family of poses that explain its bearings: the
    solver must refuse it. With more landmarks the scene is degenerate only if all of them and
    the robot are concyclic, which the draw never gives (``inf`` is returned).
    """
    if n != 3:
        return np.inf
    rng = np.random.default_rng(seed)
    radius, angle = rng.uniform(0.5, 5.0, n), rng.uniform(-np.pi, np.pi, n)
    p = np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=-1)  # goal frame
    centre_x, centre_y, k = np.linalg.solve(np.c_[2 * p, np.ones(3)], (p**2).sum(axis=1))
    size = np.sqrt(k + centre_x**2 + centre_y**2)
    c, s = np.cos(theta), np.sin(theta)
    robot = -np.array([[c, -s], [s, c]]) @ [tx, ty]  # the robot's position in the goal frame
    return abs(np.hypot(*(robot - [centre_x, centre_y])) - size) / size
