from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import PoseOracle, make_policy


@pytest.mark.parametrize("task", range(4))
def test_oracle_parks_on_the_paper_tasks(task: int) -> None:
    env = gym.make("RadialIBVS/Parking-v0", task=task, physics="kinematic", privileged=True)
    oracle = PoseOracle()
    obs, _ = env.reset(seed=0)
    for _ in range(600):
        action, _ = oracle.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        if terminated or truncated:
            break
    assert info["is_success"]  # 2 cm / 2 deg at control_dt = 0.1 s
    assert info["n_visible"] == 8 and not info["collision"]


def test_oracle_runs_under_sb3_evaluate_policy_batched() -> None:
    venv = make_vec_env(
        "RadialIBVS/Parking-v0",
        n_envs=2,
        seed=0,
        env_kwargs={"physics": "kinematic", "privileged": True, "task": 1},
    )
    mean, _ = evaluate_policy(PoseOracle(), venv, n_eval_episodes=2)
    assert mean > 0  # progress towards the goal dominates the time penalty


def test_oracle_needs_the_privileged_observation() -> None:
    env = gym.make("RadialIBVS/Parking-v0")
    obs, _ = env.reset(seed=0)
    with pytest.raises(KeyError, match="privileged=True"):
        PoseOracle().predict(obs)


def test_oracle_stops_at_the_goal() -> None:
    obs = {"robot_pose": np.array([1.0, 2.0, 0.3]), "goal_pose": np.array([1.0, 2.001, 0.3])}
    action, state = PoseOracle().predict(obs)
    assert action.shape == (2,) and not action.any() and state is None


def test_oracle_with_nav2_speeds_drives_towards_the_goal() -> None:
    from radial_ibvs_agents import SmoothControlLaw

    oracle = PoseOracle(law=SmoothControlLaw())
    obs = {"robot_pose": np.array([0.0, 0.0, 0.0]), "goal_pose": np.array([2.0, 0.0, 0.0])}
    action, _ = oracle.predict(obs)
    assert action[0] == pytest.approx(1.0) and action[1] == pytest.approx(0.0)  # straight on


# --- backward driving (nav2's allow_backward) ----------------------------------------------


def test_backward_mode_reverses_to_a_goal_behind_and_parks_on_a_shorter_path() -> None:
    from radial_ibvs_agents.rollouts import make_env, run_episode

    options = {"start": [5.0, 5.0, 0.0], "goal": [3.0, 5.2, 0.0]}  # the goal 2 m behind
    logs = {}
    for name in ("oracle", "oracle-backward"):
        policy = make_policy(name)
        env = make_env(policy, "paper-sim", {"physics": "kinematic", "task": 0})
        logs[name] = run_episode(policy, env, seed=0, options=options)
    forward, backward = logs["oracle"], logs["oracle-backward"]
    assert forward.success and backward.success
    assert (forward.actions[:, 0] >= 0).all()  # the paper's law never reverses
    assert backward.actions[0, 0] < 0  # it backs up at once
    assert backward.path_length_m < 0.6 * forward.path_length_m


def test_backward_mode_changes_nothing_when_the_goal_is_ahead() -> None:
    from radial_ibvs_agents.analytic.ibvs_maths import robot_command

    rng = np.random.default_rng(0)
    for _ in range(200):
        v = rng.uniform(-1, 1, 2)
        v[0] = abs(v[0]) + 1e-3  # the virtual target ahead of the robot
        gamma = rng.uniform(-3, 3)
        assert robot_command(v, gamma, 0.5, allow_backward=True) == robot_command(v, gamma, 0.5)
    v = np.array([-0.4, 0.1])  # behind: reverses, within the limits
    v_l, omega = robot_command(v, 0.2, 0.5, allow_backward=True)
    assert v_l < 0 and abs(v_l) <= 1.2 and abs(omega) <= 5.24


@pytest.mark.parametrize("name", ["ibvs-backward", "oracle-backward"])
def test_backward_variants_park_the_papers_four_tasks(name: str) -> None:
    from radial_ibvs_agents.rollouts import make_env, run_episode

    policy = make_policy(name)
    for task in range(4):
        env = make_env(policy, "paper-sim", {"physics": "kinematic", "task": task})
        assert run_episode(policy, env, seed=0).success, task


@pytest.mark.parametrize("backward", [False, True])
def test_the_batched_law_from_the_origin_is_the_scalar_law_bit_for_bit(backward: bool) -> None:
    oracle = PoseOracle(allow_backward=backward)
    rng = np.random.default_rng(0)
    goals = np.concatenate([rng.uniform(-3, 3, (600, 2)), rng.uniform(-3.2, 3.2, (600, 1))], 1)
    goals[:200, :2] *= 1e-3  # the final approach and the stop
    goals[200:400, :2] *= 1e-2
    alone = np.array([oracle.act(np.zeros(3), goal) for goal in goals])
    np.testing.assert_array_equal(oracle.act_from_origin(goals), alone)
