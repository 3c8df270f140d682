from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from radial_ibvs_gym import paper
from radial_ibvs_gym.config import ConfigError
from radial_ibvs_gym.scenarios import load_scenario

SHIPPED = ("paper-sim", "paper-lab", "random", "random-obstacles", "random-unseen")


def test_paper_sim_matches_the_paper_constants() -> None:
    s = load_scenario("paper-sim")
    np.testing.assert_array_equal(np.array(s.config.landmarks), paper.EQ39_POINTS)
    assert s.config.camera_height == paper.CAMERA_HEIGHT_M
    assert s.n_tasks == 4
    for k, task in enumerate(s.config.tasks):
        assert task.start == paper.START_POSE
        np.testing.assert_allclose(task.goal, paper.goal_pose(k), atol=1e-15)


@pytest.mark.parametrize("task", range(4))
def test_paper_sim_shows_all_8_points_at_start_and_goal(task: int) -> None:
    s = load_scenario("paper-sim")
    episode = s.sample(np.random.default_rng(0), task=task)
    assert episode.task == task
    assert s.visible(episode.start).all() and s.visible(episode.goal).all()


@pytest.mark.parametrize("name", SHIPPED)
def test_episodes_satisfy_the_scenario_and_are_seeded(name: str) -> None:
    s = load_scenario(name)
    c = s.config
    for seed in range(20):
        e = s.sample(np.random.default_rng(seed))
        again = s.sample(np.random.default_rng(seed))
        for a, b in zip(e, again, strict=True):
            np.testing.assert_array_equal(a, b)
        lo, hi = (len(c.landmarks),) * 2 if c.landmarks else c.random_landmarks.count_range
        assert lo <= len(e.landmarks) <= hi == s.n_landmarks and e.landmarks.shape[1] == 3
        assert c.camera_height_range[0] <= e.camera_height <= c.camera_height_range[1]
        for pose in (e.start, e.goal):
            assert c.wall_clearance <= pose[0] <= e.room[0] - c.wall_clearance
            assert c.wall_clearance <= pose[1] <= e.room[1] - c.wall_clearance
        dist = math.hypot(*(e.goal[:2] - e.start[:2]))
        assert c.min_start_goal_distance <= dist <= c.max_start_goal_distance
        for pose in (e.goal, e.start):
            seen = s.visible(pose, e.landmarks, camera_height=e.camera_height)
            assert seen.sum() >= c.min_visible_at_goal


def test_random_landmarks_lie_on_the_walls() -> None:
    s = load_scenario("random")
    e = s.sample(np.random.default_rng(3))
    x, y, z = e.landmarks.T
    on_wall = np.isclose(x, 0) | np.isclose(x, e.room[0]) | np.isclose(y, 0)
    on_wall |= np.isclose(y, e.room[1])
    assert on_wall.all()
    assert ((0.2 <= z) & (z <= 2.4)).all()


def test_goal_depths_are_horizontal_distances_scaled() -> None:
    exact = load_scenario("paper-sim")
    scaled = load_scenario("paper-sim", depth_scale=1.3)
    e = exact.sample(np.random.default_rng(0), task=1)
    d = np.hypot(*(paper.EQ39_POINTS[:, :2] - np.array([7.0, 7.0])).T)
    np.testing.assert_allclose(exact.goal_depths(e), d)
    np.testing.assert_allclose(scaled.goal_depths(e), 1.3 * d)


def test_a_goal_that_sees_too_few_landmarks_is_rejected_at_load() -> None:
    high = [[10.0, 0.0, 9.0], [0.0, 10.0, 9.0], [5.0, 10.0, 9.0], [10.0, 5.0, 0.0]]
    with pytest.raises(ValueError, match=r"only 1 of 4 landmarks are visible at the goal"):
        load_scenario("paper-sim", landmarks=high)


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        ({"landmraks": []}, r"unknown key\(s\) \['landmraks'\]"),
        ({"room": [0.0, 5.0]}, "room must be a positive"),
        ({"depth_scale": -1.0}, "depth_scale must be finite and positive"),
        ({"min_visible_at_goal": 2}, "min_visible_at_goal must be >= 3"),
        ({"min_visible_at_goal": 9}, "exceeds the 8 landmarks"),
        ({"tasks": []}, "at least one task"),
        ({"random_landmarks": {"count": 5}}, "exactly one of landmarks"),
        ({"min_start_goal_distance": 3.0, "max_start_goal_distance": 2.0}, "min_start_goal"),
        ({"camera": {"mirror": "Z"}}, r"camera.mirror: 'Z' is not one of"),
        ({"tasks": [{"start": [0, 0, "x"], "goal": "anywhere"}]}, "matches none of"),
        ({"tasks": [{"start": "somewhere", "goal": "anywhere"}]}, "matches none of"),
        ({"random_obstacles": {"count": [3, 1]}}, r"count must be a \[low, high\] range"),
        ({"random_obstacles": {"radius": [0.0, 0.5]}}, "radius"),
        ({"random_obstacles": {"clearance": -1.0}}, "clearance must be finite and >= 0"),
    ],
)
def test_bad_scenarios_are_named(overrides: dict, match: str) -> None:
    with pytest.raises((ConfigError, ValueError), match=match):
        load_scenario("paper-sim", **overrides)


def test_unknown_scenario_lists_the_shipped_ones() -> None:
    with pytest.raises(
        ConfigError,
        match=r"available: \['paper-lab', 'paper-sim', 'random', 'random-obstacles', "
        r"'random-unseen'\]",
    ):
        load_scenario("parking")


def test_task_out_of_range_and_overconstrained_scenarios(tmp_path: Path) -> None:
    s = load_scenario("paper-sim")
    with pytest.raises(ValueError, match=r"task must be in 0\.\.3, got 4"):
        s.sample(np.random.default_rng(0), task=4)
    tight = load_scenario("random", min_start_goal_distance=30.0, max_start_goal_distance=31.0)
    with pytest.raises(ValueError, match="no valid episode"):
        tight.sample(np.random.default_rng(0))
    path = tmp_path / "mine.yaml"
    path.write_text(
        "name: mine\nlandmarks: [[5, 0, 1], [0, 5, 1], [5, 5, 1]]\n"
        "tasks: [{start: [2, 2, 0], goal: [3, 3, 1]}]\n"
    )
    assert load_scenario(path).n_landmarks == 3


def test_drawn_poses_keep_clear_of_obstacles() -> None:
    s = load_scenario("random", obstacles=[[4.0, 4.0, 1.0], [2.0, 5.0, 0.5]])
    for seed in range(30):
        e = s.sample(np.random.default_rng(seed))
        for pose in (e.start, e.goal):
            assert math.hypot(pose[0] - 4.0, pose[1] - 4.0) >= 1.0 + s.config.wall_clearance
    with pytest.raises(ValueError, match=r"obstacles\[0\] radius must be positive"):
        load_scenario("random", obstacles=[[4.0, 4.0, 0.0]])


def test_random_obstacles_are_drawn_inside_the_room_apart_and_clear_of_the_poses() -> None:
    s = load_scenario("random-obstacles")
    spec = s.config.random_obstacles
    assert spec is not None
    counts = []
    for seed in range(60):
        e = s.sample(np.random.default_rng(seed))
        counts.append(len(e.obstacles))
        for k, (x, y, r) in enumerate(e.obstacles):
            assert spec.radius[0] <= r <= spec.radius[1]
            margin = r + spec.clearance
            assert margin <= x <= e.room[0] - margin and margin <= y <= e.room[1] - margin
            for x2, y2, r2 in e.obstacles[k + 1 :]:
                assert math.hypot(x - x2, y - y2) >= r + r2 + spec.clearance
            for pose in (e.start, e.goal):
                assert math.hypot(pose[0] - x, pose[1] - y) >= r + s.config.wall_clearance
    assert set(counts) == {1, 2, 3}

    assert load_scenario("random").sample(np.random.default_rng(5)).obstacles.shape == (0, 3)
