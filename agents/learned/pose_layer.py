"""The goal's pose from one radial image, solved in closed form (torch, no parameters).

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

    with torch.no_grad():
        x = now.double()
        g = goal.double()
        d = depth.double().clamp_min(1e-3)
        w = mask.double()
        cross = x[..., 0] * g[..., 1] - x[..., 1] * g[..., 0]  # (x_n x p_n) / d*
        dot = (x * g).sum(dim=-1)  # (x_n . p_n) / d*
        rows = torch.stack([cross, dot, -x[..., 1] / d, x[..., 0] / d], dim=-1) * w[..., None]
        gram = rows.transpose(-1, -2) @ rows  # (B, 4, 4)
        values, vectors = torch.linalg.eigh(gram)
        z = vectors[..., 0]
        scale = torch.linalg.vector_norm(z[..., :2], dim=-1)
        z = z / scale.clamp_min(1e-12)[..., None]
        c, s, tx, ty = z.unbind(dim=-1)
        p = d[..., None] * g
        qx = c[..., None] * p[..., 0] - s[..., None] * p[..., 1] + tx[..., None]
        qy = s[..., None] * p[..., 0] + c[..., None] * p[..., 1] + ty[..., None]
        front = ((x[..., 0] * qx + x[..., 1] * qy) * w).sum(dim=-1)
        z = torch.where((front < 0)[..., None], -z, z)
        # unique: a clear gap between the least eigenvalue and the next (3 landmarks or more
        # not all on one line through both camera centres)
        gap = values[..., 1] > 1e-9 * values[..., 3].clamp_min(1e-30)
        valid = (w.sum(dim=-1) >= 3) & (scale > 1e-6) & gap & torch.isfinite(z).all(dim=-1)
        z = torch.where(valid[..., None], z, torch.zeros_like(z))
        return torch.stack([z[..., 2], z[..., 3], z[..., 0], z[..., 1]], dim=-1), valid


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
    import torch

    pose, valid = solve_goal_pose(now, goal, depth, mask)
    t, c, s = pose[..., :2], pose[..., 2], pose[..., 3]
    size = torch.linalg.vector_norm(t, dim=-1, keepdim=True)
    r = torch.stack([-(c * t[..., 0] + s * t[..., 1]), s * t[..., 0] - c * t[..., 1]], dim=-1)
    turn = (s / (s.abs() + eps) * (1.0 + c) / 2.0)[..., None]
    flag = valid.double()[..., None]
    parts = [t, t / (size + eps), torch.log(size + eps), r, r / (r.abs() + eps)]
    out = torch.cat([*parts, s[..., None], c[..., None], turn], dim=-1) * flag
    return torch.cat([out, flag], dim=-1).float()
