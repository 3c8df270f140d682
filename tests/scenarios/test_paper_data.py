from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from radial_ibvs_gym import paper
from radial_ibvs_gym.geometry import rot_z, world_to_camera


def test_goal_poses_are_the_start_shifted_by_4_4() -> None:
    for task, yaw in enumerate((0.0, 90.0, 180.0, 270.0)):
        x, y, th = paper.goal_pose(task)
        assert (x, y) == (7.0, 7.0)
        assert np.degrees(th) == pytest.approx(yaw)


@pytest.mark.parametrize("task", [-1, 4, 1.5, "0"])
def test_goal_pose_rejects_unknown_tasks(task: object) -> None:
    with pytest.raises(ValueError, match="task must be"):
        paper.goal_pose(task)  # type: ignore[arg-type]


def test_eq39_points_are_read_only_rows() -> None:
    assert paper.EQ39_POINTS.shape == (8, 3)
    with pytest.raises(ValueError):
        paper.EQ39_POINTS[0, 0] = 1.0


finite = st.floats(-20, 20, allow_nan=False)


@given(x=finite, y=finite, yaw=st.floats(-10, 10), h=st.floats(0.1, 3.0))
def test_world_to_camera_is_the_inverse_robot_motion(x: float, y: float, yaw: float, h: float):
    pts = paper.EQ39_POINTS
    p_cam = world_to_camera(pts, (x, y, yaw), h)
    back = p_cam @ rot_z(yaw).T + np.array([x, y, h])
    np.testing.assert_allclose(back, pts, atol=1e-12)


def test_world_to_camera_robot_heading_is_camera_x() -> None:
    p = world_to_camera([[2.0, 1.0, 0.0]], (1.0, 1.0, np.pi / 2), 1.8)
    np.testing.assert_allclose(p, [[0.0, -1.0, -1.8]], atol=1e-15)


def test_world_to_camera_rejects_nan_pose() -> None:
    with pytest.raises(ValueError, match="pose must be finite"):
        world_to_camera(paper.EQ39_POINTS, (np.nan, 0.0, 0.0), 1.8)
