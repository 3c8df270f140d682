"""The goal's pose from one radial image, solved in closed form (no parameters), for networks.

A radial camera (central or not) with a vertical mirror axis gives, for each landmark, its
horizontal bearing ``x_n`` (a point on the unit circle, eq. 9): the radial line through the
image centre does not depend on the mirror's shape. The goal image gives the bearing
``x_n*`` and the goal depth ``d*`` (metres), so the landmark's horizontal position in the
goal's camera frame, ``p_n = d* x_n*``. The goal frame seen from the robot's camera is a
planar rotation ``R(theta)`` and a translation ``t``, and every landmark seen in both images
ties them by the bearing constraint ``x_n x (R p_n + t) = 0``, linear in
``z = (cos theta, sin theta, t_x, t_y)``::

    [x_n x p_n,  x_n . p_n,  -x_n,y,  x_n,x] z = 0

Each row is divided by ``d*`` (the constraint's error for a bearing error ``delta`` is about
``d* delta`` near the goal, so every row then weighs the same in bearing). Three landmarks
or more fix ``z`` up to scale: it is the eigenvector of the rows' Gram matrix with the least
eigenvalue, scaled to ``cos^2 + sin^2 = 1`` and signed so that the landmarks lie in front of
their bearings. The solution is not unique, and the solver says so (``valid`` false), when
the least eigenvalue is not clearly alone: fewer than three landmarks, all of them on one line
through both camera centres, or, with exactly three, a robot on the circle through them (the
"danger circle" of planar three-point resection, where every point of the arc sees the
landmarks under the same angles). This is a perception layer, as the features ``c_ij`` are:
it turns what the image shows into a pose; what to do from there is the network's to learn.

The solve is :func:`radial_ibvs_gym.geometry.bearing_pose.solve_goal_pose` (numpy), which
PBVS uses too: one implementation. It has no parameters and no gradient, so it runs on the
tensors' values (taken to the CPU and back to their device); in numpy, one robot's solve
costs a fraction of what the same few dozen small torch operations cost.
"""

from __future__ import annotations

from typing import Any

__all__ = ["POSE_FEATURES", "goal_pose_features", "solve_goal_pose"]

#: the number of features :func:`goal_pose_features` returns per sample
POSE_FEATURES = 13


def solve_goal_pose(now: Any, goal: Any, depth: Any, mask: Any) -> tuple[Any, Any]:
    """Solve the goal's planar pose in the robot's camera frame from bearings.

    Parameters
    ----------
    now, goal
        ``(B, N, 2)`` tensors: the landmarks' current and goal bearings (unit vectors; the
        normalised image points).
    depth
        ``(B, N)`` goal depths ``d*``, metres (horizontal distances at the goal).
    mask
        ``(B, N)`` 1 where the landmark is seen in both images, 0 elsewhere.

    Returns
    -------
    pose : torch.Tensor
        ``(B, 4)`` float64: ``(t_x, t_y, cos theta, sin theta)``, the goal's position in the
        robot's camera frame (metres; x forward, y left) and its heading relative to the
        robot's (the heading error), zeros where not valid.
    valid : torch.Tensor
        ``(B,)`` bool: at least three landmarks seen and a unique solution.
    """
    import torch

    pose, valid = _solve(now, goal, depth, mask)
    return torch.from_numpy(pose).to(now.device), torch.from_numpy(valid).to(now.device)


def _solve(now: Any, goal: Any, depth: Any, mask: Any) -> tuple[Any, Any]:
    """Solve from the tensors' values in numpy: ``(B, 4)`` pose and ``(B,)`` valid."""
    from radial_ibvs_gym.geometry.bearing_pose import solve_goal_pose as solve

    def values(t: Any) -> Any:
        return t.detach().cpu().numpy()

    return solve(values(now), values(goal), values(depth), values(mask) > 0.5)


def goal_pose_features(now: Any, goal: Any, depth: Any, mask: Any, eps: float = 1e-3) -> Any:
    """Return the solved pose as network inputs, ``(B, 13)`` float32.

    With ``t`` the goal's position in the robot's frame, ``r = -R^T t`` the robot's position
    in the goal's frame (``r_x`` along the goal heading, ``r_y`` beside it) and ``theta`` the
    heading error (:func:`solve_goal_pose`): ``t`` (metres), its direction ``t / (|t| + eps)``
    and ``log(|t| + eps)``; ``r`` and its soft sign ``r / (|r| + eps)`` per component (sharp
    within ``eps`` metres, so centimetres near the goal stay visible); ``sin theta``,
    ``cos theta`` and the soft sign ``sin / (|sin| + eps) (1 + cos) / 2``; and the validity
    flag. All but the flag are zero where the pose is not valid.
    """
    import numpy as np
    import torch

    pose, valid = _solve(now, goal, depth, mask)
    t, c, s = pose[..., :2], pose[..., 2:3], pose[..., 3:4]
    size = np.linalg.norm(t, axis=-1, keepdims=True) + eps
    t0, t1 = t[..., :1], t[..., 1:]
    r = np.concatenate([-(c * t0 + s * t1), s * t0 - c * t1], axis=-1)
    turn = s / (np.abs(s) + eps) * (1.0 + c) / 2.0
    flag = valid[..., None].astype(np.float64)
    parts = [t, t / size, np.log(size), r, r / (np.abs(r) + eps), s, c, turn]
    out = np.concatenate([np.concatenate(parts, axis=-1) * flag, flag], axis=-1)
    return torch.from_numpy(out.astype(np.float32)).to(now.device)
