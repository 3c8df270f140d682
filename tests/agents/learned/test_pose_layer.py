"""The goal's pose solved from radial bearings (radial_ibvs_agents.learned.networks.pose_layer) and
its extractor."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch
from bearing_scenes import distance_to_danger_circle as _distance_to_danger_circle
from bearing_scenes import scene as _scene
from gymnasium import spaces
from hypothesis import example, given, settings
from hypothesis import strategies as st

from radial_ibvs_agents.learned.dagger.distill import goal_in_robot_frame
from radial_ibvs_agents.learned.networks.extractors import (
    LandmarkPoseExtractor,
    LandmarkSetExtractor,
)
from radial_ibvs_agents.learned.networks.pose_layer import (
    POSE_FEATURES,
    goal_pose_features,
    solve_goal_pose,
)

finite = st.floats(-3.0, 3.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 10_000), st.integers(3, 16), finite, finite, st.floats(-3.1, 3.1)
)  # fmt: skip
# a draw that once failed: the robot within 1e-5 (relative) of the three landmarks' circle
@example(seed=3, n=3, tx=0.0, ty=-0.24100748384958592, theta=0.0)
def test_the_pose_is_recovered_exactly_from_noise_free_bearings(seed, n, tx, ty, theta):
    now, goal, depth, mask = _scene(seed, n, tx, ty, theta)
    pose, valid = solve_goal_pose(now, goal, depth, mask)
    if _distance_to_danger_circle(seed, n, tx, ty, theta) < 1e-3:
        # near the danger circle the pose is (nearly) not unique: the solver may refuse it,
        # but what it answers is exact
        if not bool(valid[0]):
            assert bool((pose == 0).all())
            return
    assert bool(valid[0])
    np.testing.assert_allclose(pose[0, :2].numpy(), [tx, ty], atol=1e-6)
    error = np.arctan2(float(pose[0, 3]), float(pose[0, 2])) - theta
    assert abs(np.angle(np.exp(1j * error))) < 1e-6


def test_a_robot_on_the_danger_circle_of_three_landmarks_is_refused():
    # three landmarks on the unit circle and a robot on it too: every point of the circle's
    # arc sees the pairs under the same angles (inscribed angles), so the pose is not unique
    angle = np.array([0.3, 2.0, -2.2])
    p = np.stack([np.cos(angle), np.sin(angle)], axis=-1) + np.array([2.0, 0.0])  # goal frame
    robot = np.array([2.0 + np.cos(1.1), np.sin(1.1)])
    q = p - robot  # the robot heads as the goal does (theta = 0)
    now = q / np.linalg.norm(q, axis=-1, keepdims=True)
    depth = np.linalg.norm(p, axis=-1)
    goal = p / depth[:, None]
    args = (torch.tensor(a[None]) for a in (now, goal, depth, np.ones(3)))
    pose, valid = solve_goal_pose(*args)
    assert not bool(valid[0]) and bool((pose == 0).all())
    # one step off the circle, the same landmarks fix the pose
    q = p - robot * 0.8
    now = q / np.linalg.norm(q, axis=-1, keepdims=True)
    args = (torch.tensor(a[None]) for a in (now, goal, depth, np.ones(3)))
    pose, valid = solve_goal_pose(*args)
    assert bool(valid[0])
    np.testing.assert_allclose(pose[0, :2].numpy(), -robot * 0.8, atol=1e-9)  # t = -r


def test_every_random_scene_solves():
    # landmarks spread over a room are never degenerate: the validity check does not refuse them
    solved = [bool(solve_goal_pose(*_scene(s, 4, 0.7, -0.4, 1.0))[1][0]) for s in range(200)]
    assert all(solved)


def test_a_pose_needs_three_landmarks_and_ignores_hidden_slots():
    now, goal, depth, mask = _scene(3, 5, 0.4, 0.2, -0.5)
    pose, valid = solve_goal_pose(now, goal, depth, mask)
    assert bool(valid[0])
    mask2 = mask.clone()
    mask2[0, 3:] = 0.0
    now2 = now.clone()
    now2[0, 3:] = torch.tensor([0.6, 0.8], dtype=now.dtype)  # whatever a hidden slot holds
    pose2, valid2 = solve_goal_pose(now2, goal, depth, mask2)
    assert bool(valid2[0])
    torch.testing.assert_close(pose2, pose)
    mask2[0, 2] = 0.0  # two landmarks: a one-parameter family of poses
    pose3, valid3 = solve_goal_pose(now, goal, depth, mask2)
    assert not bool(valid3[0]) and bool((pose3 == 0).all())
    features = goal_pose_features(now, goal, depth, mask2)
    assert features.shape == (1, POSE_FEATURES) and bool((features == 0).all())  # flag 0


def test_the_features_hold_both_frames_and_sharp_soft_signs():
    # the robot 5 mm behind and 1 mm right of the goal, turned 2 deg from its heading
    theta = np.radians(2.0)
    c, s = np.cos(theta), np.sin(theta)
    r = np.array([-0.005, -0.001])  # the robot in the goal frame
    t = -np.array([[c, -s], [s, c]]) @ r  # the goal in the robot frame: t = -R r
    f = goal_pose_features(*_scene(7, 6, t[0], t[1], theta), eps=1e-3)[0].double().numpy()
    np.testing.assert_allclose(f[:2], t, atol=1e-6)
    np.testing.assert_allclose(f[5:7], r, atol=1e-6)
    np.testing.assert_allclose(f[7:9], r / (np.abs(r) + 1e-3), atol=1e-4)
    assert f[7] < -0.8 and f[8] == pytest.approx(-0.5, abs=1e-3)
    assert f[9] == pytest.approx(s, abs=1e-6) and f[10] == pytest.approx(c, abs=1e-6)
    assert f[11] > 0.9 and f[12] == 1.0  # a 2 deg turn is a clear left turn; valid


@pytest.mark.parametrize("scenario", ["random", "paper-sim"])
def test_the_pose_from_the_envs_images_is_the_true_one(scenario):
    # central and non-central mirrors: the radial lines are the horizontal bearings
    env = gym.make(
        "RadialIBVS/Parking-v0", scenario=scenario, physics="kinematic", obs_mode="features",
        goal_depths=True, max_landmarks=16, privileged=True,
    )  # fmt: skip
    solved = 0
    for episode in range(5):
        obs, _ = env.reset(seed=episode)
        for _ in range(10):
            o = {k: torch.as_tensor(np.asarray(v))[None] for k, v in obs.items()}
            now, goal = o["points"].reshape(1, -1, 2), o["goal_points"].reshape(1, -1, 2)
            mask = ((goal.norm(dim=2) > 0.5) & (o["visible"] > 0.5)).double()
            pose, valid = solve_goal_pose(now, goal, o["goal_depths"], mask)
            if bool(valid[0]):
                solved += 1
                truth = goal_in_robot_frame(obs)[0].astype(np.float64)
                np.testing.assert_allclose(pose[0, :2].numpy(), 3.0 * truth[:2], atol=1e-4)
                np.testing.assert_allclose(pose[0, 2:].numpy(), truth[2:], atol=1e-4)
            obs, *_ = env.step(env.action_space.sample())
    env.close()
    assert solved >= 40


def _obs(now, goal, depth, **past: torch.Tensor) -> dict[str, torch.Tensor]:
    """A features observation of one scene (:func:`_scene`), past frames' keys added."""
    n = depth.shape[1]
    obs = {
        "alpha_m_error": torch.tensor([[0.3]]),
        "goal_depths": depth.float(),
        "goal_points": goal.float().reshape(1, -1),
        "points": now.float().reshape(1, -1),
        "visible": torch.ones(1, n),
    }
    return obs | {k: v.float().reshape(1, -1) for k, v in past.items()}


def _space_of(obs: dict[str, torch.Tensor]) -> spaces.Dict:
    return spaces.Dict({k: spaces.Box(-1e3, 1e3, tuple(v.shape[1:])) for k, v in obs.items()})


def test_the_pose_extractor_appends_the_pose_to_the_set_features():
    now, goal, depth, _ = _scene(11, 5, 1.0, 0.5, 0.3)
    obs = _obs(now, goal, depth)
    torch.manual_seed(0)
    extractor = LandmarkPoseExtractor(_space_of(obs), token_dim=8)
    torch.manual_seed(0)
    base = LandmarkSetExtractor(_space_of(obs), token_dim=8)
    assert extractor.features_dim == base.features_dim + POSE_FEATURES
    out = extractor(obs)
    torch.testing.assert_close(out[:, : base.features_dim], base(obs))
    np.testing.assert_allclose(out[0, -POSE_FEATURES:-11].detach().numpy(), [1.0, 0.5], atol=1e-4)
    with pytest.raises(ValueError, match="pose_eps"):
        LandmarkPoseExtractor(_space_of(obs), pose_eps=0.0)


def test_pose_history_solves_each_past_frame():
    now, goal, depth, _ = _scene(11, 5, 1.0, 0.5, 0.3)
    past, _, _, _ = _scene(11, 5, 1.2, 0.4, 0.1)  # the same landmarks, from an earlier pose
    obs = _obs(now, goal, depth, **{"points@-1": past, "visible@-1": torch.ones(1, 5)})
    space = _space_of(obs)
    extractor = LandmarkPoseExtractor(space, token_dim=8, pose_history=True)
    assert extractor.features_dim == LandmarkPoseExtractor(space, token_dim=8).features_dim + 13
    out = extractor(obs)[0].detach().numpy()
    np.testing.assert_allclose(out[-26:-24], [1.0, 0.5], atol=1e-4)  # now
    np.testing.assert_allclose(out[-13:-11], [1.2, 0.4], atol=1e-4)  # a step ago
    with pytest.raises(ValueError, match="points@-1"):
        LandmarkPoseExtractor(_space_of(_obs(now, goal, depth)), pose_history=True)


def test_pose_history_needs_the_pose_extractor_and_the_points_history(tmp_path):
    from radial_ibvs_agents.learned.dagger.distill import load_dagger_config

    path = tmp_path / "c.yaml"
    both, points = "{frames: 2, keys: [points, visible]}", "{frames: 2, keys: [points]}"
    for extra in (
        f"  pose_history: true\n  extractor: landmark_set\n  history: {both}\n",
        f"  pose_history: true\n  extractor: landmark_pose\n  history: {points}\n",
        "  pose_history: true\n  extractor: landmark_pose\n",
        f"  pose_history: 1\n  extractor: landmark_pose\n  history: {both}\n",
    ):
        path.write_text("dagger:\n  teacher: planner\n" + extra)
        with pytest.raises(ValueError, match="pose_history"):
            load_dagger_config(path)
