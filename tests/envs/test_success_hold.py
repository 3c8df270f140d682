"""``success_hold_steps``: success asks the pose held within the tolerances, not passed."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401  (registers the ids)
from radial_ibvs_agents import make_policy


def test_success_hold_steps_needs_the_pose_held_a_pass_does_not_count() -> None:
    from radial_ibvs_gym.envs import rules

    kwargs = {
        "success_position_m": 0.02,
        "success_heading_rad": 0.05,
        "min_visible": 3,
        "terminate_on_collision": True,
    }
    held = np.zeros(3, dtype=np.int64)
    errors = [(0.01, 0.01), (0.01, 0.01), (0.5, 0.01)]  # two in, then out: a pass
    outcomes = []
    for e_p, e_h in errors:
        success, _, terminated, held = rules.episode_end(
            np.full(3, e_p), np.full(3, e_h), np.full(3, 8), np.zeros(3, bool),
            held=held, hold_steps=3, **kwargs,
        )  # fmt: skip
        assert (terminated == success).all()
        outcomes.append((bool(success[0]), int(held[0])))
    assert outcomes == [(False, 1), (False, 2), (False, 0)]
    success, *_ = rules.episode_end(0.01, 0.01, 8, False, held=2, hold_steps=3, **kwargs)
    assert success  # the third step in a row


@pytest.mark.parametrize("physics", ["kinematic", "pymunk"])
def test_a_policy_that_stops_at_the_goal_succeeds_the_hold_later_scalar_and_batched(
    physics: str,
) -> None:
    policy = make_policy("ibvs-straight")
    kwargs = {"scenario": "random", "physics": physics, **policy.env_kwargs}
    lengths = {}
    for hold in (1, 10):
        env = gym.make("RadialIBVS/Parking-v0", success_hold_steps=hold, **kwargs)
        obs, _ = env.reset(seed=0)
        steps, done = 0, False
        while not done:
            action, _ = policy.predict(obs)
            obs, _, terminated, truncated, info = env.step(action)
            steps, done = steps + 1, terminated or truncated
        assert info["is_success"]
        lengths[hold] = steps
        env.close()
    assert lengths[10] == lengths[1] + 9  # it stayed: the 10th step in a row within them
    if physics == "kinematic":  # the vector env counts the same way
        venv = gym.make_vec(
            "RadialIBVS/Parking-v0", num_envs=2, vectorization_mode="vector_entry_point",
            autoreset_mode="disabled", success_hold_steps=10, **kwargs,
        )  # fmt: skip
        obs, _ = venv.reset(seed=[0, 1])
        for _ in range(lengths[10]):
            action, _ = policy.predict(obs)
            obs, _, terminated, _, info = venv.step(action)
        assert terminated[0] and info["is_success"][0]


@pytest.mark.parametrize("value", [0, 601, 2.5, True])
def test_bad_success_hold_steps_are_named(value: object) -> None:
    with pytest.raises(ValueError, match="success_hold_steps"):
        gym.make("RadialIBVS/Parking-v0", success_hold_steps=value)


@pytest.mark.parametrize(("control_dt", "steps"), [(0.1, 10), (0.05, 20), (0.25, 4), (2.0, 1)])
def test_the_default_is_a_park_held_one_second(control_dt: float, steps: int) -> None:
    env = gym.make("RadialIBVS/Parking-v0", control_dt=control_dt)
    assert env.unwrapped.config.success_hold_steps == steps
    assert env.unwrapped.config.hold_steps == steps
    env.close()
    goal = gym.make("RadialIBVS/ParkingGoal-v1", control_dt=control_dt)
    assert goal.unwrapped.config.success_hold_steps == steps
    goal.close()


def _drive(
    env_id: str, hold: int | None, actions: list | None = None, **extra: object
) -> tuple[list[tuple[bool, bool, float]], list]:
    """ibvs-straight to its park (or ``actions`` replayed): (reached, is_success, reward) a step.

    ``ParkingGoal-v1`` draws the same episode as ``Parking-v0`` for a seed, so the actions of
    one replay the other's trajectory.
    """
    policy = make_policy("ibvs-straight")
    kwargs = {"scenario": "random", "physics": "kinematic", **policy.env_kwargs, **extra}
    if hold is not None:
        kwargs["success_hold_steps"] = hold
    env = gym.make(env_id, **kwargs)
    obs, info = env.reset(seed=0)
    assert info["reached"] is False
    out, sent = [], []
    done = False
    while not done:
        action = policy.predict(obs)[0] if actions is None else actions[len(sent)]
        obs, reward, terminated, truncated, info = env.step(action)
        out.append((info["reached"], info["is_success"], float(reward)))
        sent.append(action)
        done = terminated or truncated
    env.close()
    return out, sent


def test_reached_marks_the_first_step_of_the_run_the_park_ends() -> None:
    steps, _ = _drive("RadialIBVS/Parking-v0", None)
    reached = [i for i, (r, _, _) in enumerate(steps) if r]
    assert steps[-1][1] and not any(s for _, s, _ in steps[:-1])  # the park ends it
    assert reached[-1] == len(steps) - 10  # the run's first step, 10 steps before the park
    # the older rule: the first step within the tolerances is reached and succeeds at once
    passed, _ = _drive("RadialIBVS/Parking-v0", 1)
    assert passed[-1][:2] == (True, True) and len(passed) == reached[-1] + 1


def test_parking_v0_pays_the_success_bonus_with_the_park() -> None:
    bonus = 7.0  # far above the shaping terms of a step
    steps, _ = _drive("RadialIBVS/Parking-v0", None, success_bonus=bonus)
    assert steps[-1][2] > bonus - 1.0
    assert all(reward < bonus - 1.0 for _, _, reward in steps[:-1])  # not at reached


def test_parking_goal_keeps_compute_reward_and_ends_at_the_park() -> None:
    """The hold changes termination and ``is_success`` only: the reward is compute_reward's."""
    _, actions = _drive("RadialIBVS/Parking-v0", None)
    held, _ = _drive("RadialIBVS/ParkingGoal-v1", None, actions)
    passed, _ = _drive("RadialIBVS/ParkingGoal-v1", 1, actions)
    assert len(held) == len(actions) == len(passed) + 9 and held[-1][1] and passed[-1][1]
    assert held[-10][0] and not any(s for _, s, _ in held[:-1])
    # the same trajectory up to the pass: the same rewards, step for step
    assert [r for _, _, r in held[: len(passed)]] == [r for _, _, r in passed]


@pytest.mark.parametrize("control_dt", [0.0, float("nan"), -0.1])
def test_a_bad_control_period_is_named_before_the_hold_is_resolved(control_dt: float) -> None:
    from radial_ibvs_gym.envs.config import ParkingConfig
    from radial_ibvs_gym.scenarios import load_scenario

    with pytest.raises(ValueError, match="control_dt"):
        ParkingConfig(scenario=load_scenario("paper-sim"), control_dt=control_dt)
