"""``RadialIBVS/ParkingGoal-v1``: the step reward is ``compute_reward`` (GoalEnv rule), slots."""

from __future__ import annotations

import warnings

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401  (registers the envs)
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env
from radial_ibvs_gym.envs.rules import reward_terms_in

KW = {"scenario": "random", "physics": "kinematic"}
#: narrow rooms, every landmark needed, driving on after a collision: random actions collide
#: (about 900 steps in 5,000) and lose landmarks (about 13 episodes in 40)
HARSH = {
    "max_landmarks": 12, "min_visible": 8, "min_visible_at_goal": 8,
    "terminate_on_collision": False, "random_room": {"width": [3.0, 4.0], "depth": [3.0, 4.0]},
}  # fmt: skip


def _rollouts(env: gym.Env, episodes: int, seed: int) -> tuple[list, list, list, list]:
    """Random-action episodes: (achieved, desired, info, reward) of every step."""
    achieved, desired, infos, rewards = [], [], [], []
    env.action_space.seed(seed)
    for episode in range(episodes):
        env.reset(seed=seed + episode)
        done = False
        while not done:
            obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
            achieved.append(obs["achieved_goal"])
            desired.append(obs["desired_goal"])
            infos.append(info)
            rewards.append(reward)
            done = terminated or truncated
    return achieved, desired, infos, rewards


@pytest.fixture(scope="module")
def steps():
    env = gym.make("RadialIBVS/ParkingGoal-v1", max_episode_steps=150, **HARSH, **KW)
    return env.unwrapped, _rollouts(env, 40, seed=0)


def test_step_reward_is_compute_reward_one_by_one_and_batched(steps):
    env, (achieved, desired, infos, rewards) = steps
    assert sum(i["collision"] for i in infos) >= 3  # the events the v0 reward left out
    assert sum(i["lost"] for i in infos) >= 3
    for a, d, info, reward in zip(achieved, desired, infos, rewards, strict=True):
        assert reward == float(env.compute_reward(a, d, info))
        assert reward == sum(reward_terms_in(info).values())
    batched = env.compute_reward(np.stack(achieved), np.stack(desired), np.array(infos))
    np.testing.assert_array_equal(batched, np.array(rewards))


def test_relabelled_goals_keep_the_penalties(steps):
    env, (achieved, _, infos, _) = steps
    crash = next(i for i, info in enumerate(infos) if info["collision"])
    other_goal = achieved[crash]  # HER: the goal relabelled to what was achieved
    with_crash = env.compute_reward(achieved[crash], other_goal, infos[crash])
    without = env.compute_reward(achieved[crash], other_goal, {"collision": False, "lost": False})
    assert with_crash == pytest.approx(without - env.config.weights["collision_penalty"])
    assert without == env.config.weights["success_bonus"]  # the relabelled goal is reached exactly


def test_her_calls_reach_the_penalties_through_the_vector_env(steps):
    """HER's call, ``env_method("compute_reward", achieved, desired, infos)``, on SB3's VecEnv."""
    env, (achieved, desired, infos, rewards) = steps
    venv = make_vec_env("RadialIBVS/ParkingGoal-v1", 2, seed=0, **HARSH, **KW)
    (batched,) = venv.env_method(
        "compute_reward", np.stack(achieved), np.stack(desired), np.array(infos), indices=[0]
    )
    np.testing.assert_array_equal(batched, np.array(rewards))
    relabelled = venv.env_method(
        "compute_reward", np.stack(achieved), np.stack(achieved), np.array(infos), indices=[0]
    )[0]
    crashes = np.array([i["collision"] for i in infos])
    w = env.config.weights
    lost = np.array([i["lost"] for i in infos])
    expected = w["success_bonus"] - w["collision_penalty"] - w["lost_penalty"] * lost[crashes]
    np.testing.assert_allclose(relabelled[crashes], expected)


def test_max_landmarks_slots_and_spaces():
    env = gym.make("RadialIBVS/ParkingGoal-v1", max_landmarks=16, **KW)
    obs, _ = env.reset(seed=3)
    assert env.observation_space["observation"].shape == (48,)
    assert env.observation_space["achieved_goal"].shape == (32,)
    assert env.observation_space.contains(obs)
    np.testing.assert_array_equal(obs["desired_goal"][16:], 0.0)  # 8 landmarks in 16 slots
    with pytest.raises(ValueError, match="max_landmarks"):
        gym.make("RadialIBVS/ParkingGoal-v1", max_landmarks=4, **KW)
    drawn = gym.make("RadialIBVS/ParkingGoal-v1", max_landmarks=16, slot_order="random", **KW)
    moved, _ = drawn.reset(seed=3)
    order = drawn.unwrapped._setup.slot_order
    goal = moved["desired_goal"].reshape(16, 2)
    np.testing.assert_array_equal(goal[order], obs["desired_goal"].reshape(16, 2)[:8])
    assert (np.delete(goal, order, axis=0) == 0).all()


@pytest.mark.parametrize("slot_order", ["fixed", "random"])
def test_native_vector_env_equals_sync(slot_order: str):
    kw = {**HARSH, **KW, "slot_order": slot_order}
    native, sync = (
        gym.make_vec("RadialIBVS/ParkingGoal-v1", 3, vectorization_mode=mode, **kw)
        for mode in ("vector_entry_point", "sync")
    )
    a, _ = native.reset(seed=5)
    b, _ = sync.reset(seed=5)
    rng = np.random.default_rng(0)
    resetting = np.zeros(3, dtype=bool)  # next-step autoreset: these rows reset, reward 0
    for _ in range(80):
        action = rng.uniform(-1, 1, (3, 2)).astype(np.float32)
        a, ra, ta, tra, ia = native.step(action)
        b, rb, tb, _, ib = sync.step(action)
        for key in a:
            np.testing.assert_allclose(a[key], b[key], atol=1e-6)
        np.testing.assert_allclose(ra, rb, atol=1e-6)
        np.testing.assert_array_equal(ta, tb)
        np.testing.assert_array_equal(ia["lost"], ib["lost"])
        # each stepped robot's reward is compute_reward of its row
        rewards = native.unwrapped.compute_reward(a["achieved_goal"], a["desired_goal"], ia)
        np.testing.assert_allclose(ra[~resetting], rewards[~resetting], atol=1e-12)
        resetting = ta | tra


def test_v0_is_gone_and_v1_makes_without_warnings():
    from gymnasium.error import Error

    with pytest.raises(Error):
        gym.make("RadialIBVS/ParkingGoal-v0", **KW)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gym.make("RadialIBVS/ParkingGoal-v1", **KW)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"goal_reward_power": 0.0}, "goal_reward_power"),
        ({"goal_image_tolerance": float("nan")}, "goal_image_tolerance"),
        ({"obs_mode": "features"}, "obs_mode='points' only"),
    ],
)
def test_bad_arguments_are_named(kwargs, match):
    with pytest.raises(ValueError, match=match):
        gym.make("RadialIBVS/ParkingGoal-v1", **KW, **kwargs)


def test_goal_depths_add_each_goals_depths_and_the_reward_reads_the_points():
    from radial_ibvs_gym.envs.parking_goal import depth_observation

    kw = {**KW, "max_landmarks": 16, "goal_depths": True}
    env = gym.make("RadialIBVS/ParkingGoal-v1", **kw)
    plain = gym.make("RadialIBVS/ParkingGoal-v1", **{**kw, "goal_depths": False})
    obs, _ = env.reset(seed=3)
    base, _ = plain.reset(seed=3)
    u = env.unwrapped
    assert obs["achieved_goal"].shape == obs["desired_goal"].shape == (48,)
    assert env.observation_space.contains(obs)
    np.testing.assert_array_equal(obs["desired_goal"][:32], base["desired_goal"])
    np.testing.assert_array_equal(obs["observation"], base["observation"])
    # the depths of a goal image taken at the goal are the goal depths d* of what it sees
    setup = u._setup
    seen = setup.goal_visible
    at_goal = depth_observation(u.config, setup.landmarks_c, setup.episode.goal, seen)
    np.testing.assert_allclose(at_goal[seen], setup.goal_depths[seen], rtol=1e-12)
    np.testing.assert_array_equal(at_goal[~seen], 0.0)
    np.testing.assert_allclose(obs["desired_goal"][32:40], setup.goal_depths, rtol=1e-6)
    for _ in range(5):
        action = np.array([0.5, 0.2], dtype=np.float32)
        obs, reward, _, _, info = env.step(action)
        base, base_reward, *_ = plain.step(action)
        assert reward == base_reward  # the depths do not enter the reward
        assert reward == pytest.approx(
            float(u.compute_reward(obs["achieved_goal"], obs["desired_goal"], info))
        )
        assert u.image_distance(obs["achieved_goal"], obs["desired_goal"]) == pytest.approx(
            u.image_distance(base["achieved_goal"], base["desired_goal"])
        )
    venv = gym.make_vec(
        "RadialIBVS/ParkingGoal-v1", num_envs=2, vectorization_mode="vector_entry_point", **kw
    )
    batch, _ = venv.reset(seed=[3, 4])
    single, _ = env.reset(seed=3)
    for key in single:
        np.testing.assert_array_equal(batch[key][0], single[key])


class _Turn:
    """Drive on a curve, whatever the observation: one robot's or a batch's."""

    batch_mode = "batch"

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        n = len(obs["observation"]) if obs["observation"].ndim == 2 else None
        action = np.array([0.6, 0.3], dtype=np.float32)
        return (action if n is None else np.tile(action, (n, 1))), state


def test_achieved_depths_are_those_of_the_landmarks_seen():
    """No range to a landmark the camera does not see (0), a positive one to those it sees."""
    env = gym.make("RadialIBVS/ParkingGoal-v1", **KW, **HARSH, goal_depths=True)
    m = env.unwrapped.config.observed_landmarks
    env.action_space.seed(0)
    obs, _ = env.reset(seed=0)
    hidden = 0
    for _ in range(200):
        obs, _, terminated, truncated, _ = env.step(env.action_space.sample())
        visible = obs["observation"][2 * m :] > 0.5
        depths = obs["achieved_goal"][2 * m :]
        assert (depths[visible] > 0).all() and (depths[~visible] == 0).all()
        hidden += int((~visible).sum())
        if terminated or truncated:
            obs, _ = env.reset()
    assert hidden > 0  # the harsh rooms hide landmarks


def test_the_runners_read_goals_with_depths():
    """``run_episode`` and the batched runner take goals of ``3M`` values (points, then depths)."""
    from radial_ibvs_agents.rollouts import run_episode, run_episodes

    kw = {**KW, "max_landmarks": 16}
    logs = {}
    for depths in (False, True):
        env = gym.make("RadialIBVS/ParkingGoal-v1", **kw, goal_depths=depths)
        logs[depths] = run_episode(_Turn(), env, seed=2, max_steps=40)
    np.testing.assert_array_equal(logs[True].points, logs[False].points)
    np.testing.assert_array_equal(logs[True].goal_points, logs[False].goal_points)
    assert logs[True].points.shape == (41, 16, 2)
    assert logs[True].visible[0].any()
    env_id = "RadialIBVS/ParkingGoal-v1"
    batched = run_episodes(_Turn(), [2, 3], "random", {**kw, "goal_depths": True}, env_id=env_id)
    assert batched[0].batch == 2  # stepped together in the vector env
    np.testing.assert_array_equal(batched[0].points[:41], logs[True].points)
    np.testing.assert_array_equal(batched[0].goal_points, logs[True].goal_points)


def test_the_goal_pose_extractor_solves_the_students_pose_from_the_goals():
    torch = pytest.importorskip("torch")
    from gymnasium import spaces

    from radial_ibvs_agents.learned.networks.extractors import (
        GoalPoseExtractor,
        LandmarkPoseExtractor,
    )
    from radial_ibvs_agents.learned.networks.pose_layer import POSE_FEATURES

    kw = {**KW, "max_landmarks": 16, "goal_depths": True}
    goal_env = gym.make("RadialIBVS/ParkingGoal-v1", **kw)
    image_env = gym.make("RadialIBVS/Parking-v0", **kw)
    obs, _ = goal_env.reset(seed=5)
    student_obs, _ = image_env.reset(seed=5)
    keys = ("points", "goal_points", "visible", "goal_depths")
    student = LandmarkPoseExtractor(
        spaces.Dict({k: image_env.observation_space[k] for k in keys}), (), point_error=True
    )
    mine = GoalPoseExtractor(goal_env.observation_space)
    ours = mine({k: torch.as_tensor(v)[None] for k, v in obs.items()})
    theirs = student({k: torch.as_tensor(student_obs[k])[None] for k in keys})
    torch.testing.assert_close(ours[0, -POSE_FEATURES:], theirs[0, -POSE_FEATURES:])
    with pytest.raises(ValueError, match="goal_depths=True"):
        GoalPoseExtractor(gym.make("RadialIBVS/ParkingGoal-v1", **KW).observation_space)
