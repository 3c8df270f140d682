"""The IBVS policies (the paper's and its variants) and the registry, in the environments."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.evaluation import evaluate_policy

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import POLICY_NAMES, IBVSPolicy, PoseOracle, RandomPolicy, make_policy

TIGHT = {"success_position_m": 0.01, "success_heading_deg": 0.5}


def run_episode(policy, task: int, max_steps: int = 1500, **env_kwargs):
    """One episode; returns the last info, the poses ``(T, 3)`` and the number of steps."""
    kwargs = {"physics": "kinematic", **TIGHT, **env_kwargs, **policy.env_kwargs}
    env = gym.make("RadialIBVS/Parking-v0", task=task, max_episode_steps=max_steps, **kwargs)
    obs, info = env.reset(seed=0)
    poses = [info["robot_pose"]]
    for _ in range(max_steps):
        action, _ = policy.predict(obs)
        obs, _, terminated, truncated, info = env.step(action)
        poses.append(info["robot_pose"])
        if terminated or truncated:
            break
    return info, np.array(poses), len(poses) - 1


def path_length(poses: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(poses[:, :2], axis=0), axis=1).sum())


def hausdorff(a: np.ndarray, b: np.ndarray) -> float:
    d = np.linalg.norm(a[:, None, :2] - b[None, :, :2], axis=-1)
    return float(max(d.min(0).max(), d.min(1).max()))


@pytest.mark.parametrize("physics", ["kinematic", "pymunk"])
@pytest.mark.parametrize("task", range(4))
def test_paper_ibvs_oracle_and_depth_scale_all_park_to_1cm_and_half_a_degree(
    task: int, physics: str
) -> None:
    ibvs, p_ibvs, n_ibvs = run_episode(IBVSPolicy(), task, physics=physics)
    scaled, p_scaled, n_scaled = run_episode(IBVSPolicy(), task, physics=physics, depth_scale=1.3)
    oracle, p_oracle, _ = run_episode(PoseOracle(), task, physics=physics)
    for info in (ibvs, scaled, oracle):
        assert info["is_success"] and not info["collision"] and info["n_visible"] == 8
        assert info["position_error_m"] <= 0.01 and info["heading_error_deg"] <= 0.5
    # depths x1.3: faster (measured 12-16 %) on nearly the same path (within 3 %)
    assert n_scaled <= 0.9 * n_ibvs
    assert path_length(p_scaled) == pytest.approx(path_length(p_ibvs), rel=0.04)
    # IBVS vs the exact-3D law: close for goal yaw 0 and 90 deg, further apart for 180 and 270
    # (measured Hausdorff distances 0.24, 0.35, 1.19, 1.42 m; pymunk within a few mm of them)
    assert hausdorff(p_ibvs, p_oracle) < (0.4 if task < 2 else 1.5)


@pytest.mark.parametrize("lam", [0.25, 1.0])
def test_the_path_barely_depends_on_lambda_or_the_control_period(lam: float) -> None:
    # speed limits scale v and omega together, so the curvature (hence the path) depends only
    # on the image; lambda and the control period change the speed along it
    _, reference, _ = run_episode(IBVSPolicy(lam=0.5), 2, control_dt=0.1)
    _, other, _ = run_episode(IBVSPolicy(lam=lam), 2, control_dt=0.05, max_steps=4000)
    assert hausdorff(reference, other) < 0.1
    assert path_length(other) == pytest.approx(path_length(reference), rel=0.02)


def test_predict_is_batched_and_runs_under_sb3_evaluate_policy() -> None:
    policy = IBVSPolicy()
    venv = make_vec_env(
        "RadialIBVS/Parking-v0",
        n_envs=3,
        seed=0,
        env_kwargs={"physics": "kinematic", "task": 2, **policy.env_kwargs},
    )
    obs = venv.reset()
    batch, _ = policy.predict(obs)
    assert batch.shape == (3, 2) and batch.dtype == np.float32
    for i in range(3):
        single, _ = policy.predict({k: v[i] for k, v in obs.items()})
        np.testing.assert_array_equal(single, batch[i])
    mean, _ = evaluate_policy(policy, venv, n_eval_episodes=3)
    assert mean > 5.0  # progress (5.66 m) plus the success bonus, minus the time penalty


def observation(task: int = 1, options: dict | None = None) -> dict[str, np.ndarray]:
    env = gym.make("RadialIBVS/Parking-v0", task=task, goal_depths=True, privileged=True)
    obs, _ = env.reset(seed=0, options=options)
    return obs


@pytest.mark.parametrize("variant", ["paper", "no-frame-change", "current", "mean"])
def test_every_variant_stops_at_the_goal_and_moves_elsewhere(variant: str) -> None:
    policy = IBVSPolicy(variant)
    at_goal, _ = policy.predict(observation(options={"start": [7.0, 7.0, math.pi / 2]}))
    np.testing.assert_array_equal(at_goal, [0.0, 0.0])
    away, _ = policy.predict(observation(options={"start": [6.0, 6.5, 1.0]}))
    assert np.abs(away).max() > 0.01 and np.all(np.abs(away) <= 1.0)


def test_the_variants_estimate_the_goal_alike_near_it() -> None:
    # 3 cm and 3 deg from the goal, every variant's first-order estimate is the truth: the goal
    # (7, 7) seen from (6.98, 7.01) heading 87.1 deg, and the rotation to the goal heading
    yaw = math.pi / 2 - 0.05
    obs = observation(options={"start": [6.98, 7.01, yaw]})
    c, s = math.cos(yaw), math.sin(yaw)
    truth = np.array([c * 0.02 + s * -0.01, -s * 0.02 + c * -0.01])
    for variant in ("paper", "current", "mean"):
        policy = IBVSPolicy(variant)
        v, gamma = policy.twist(obs)
        np.testing.assert_allclose(v / policy.lam, truth, atol=2e-3)
        assert gamma == pytest.approx(0.05, abs=2e-3)


def test_fewer_than_three_shared_points_stop_the_robot() -> None:
    obs = observation()
    obs["visible"][2:] = 0.0
    obs["points"][4:] = 0.0
    action, _ = IBVSPolicy().predict(obs)
    np.testing.assert_array_equal(action, [0.0, 0.0])
    obs = observation()
    obs["visible"][3:] = 0.0  # three points left: still servoing
    assert np.abs(IBVSPolicy().predict(obs)[0]).max() > 0.0


@pytest.mark.parametrize("policy", [IBVSPolicy(), PoseOracle()], ids=repr)
def test_at_the_goal_position_the_robot_turns_on_the_spot_to_the_goal_heading(policy) -> None:
    obs = observation(options={"start": [7.0, 7.0, math.pi / 2 - 0.3]})
    turn, _ = policy.predict(obs)
    assert abs(turn[0]) < 1e-6
    assert turn[1] == pytest.approx(0.5 * 0.3 / math.radians(300), rel=1e-3)  # lam * gamma


def test_final_approach_drives_the_forward_part_and_turns_to_the_goal_heading() -> None:
    # 1 cm behind the goal (along its heading), 2 deg off: forwards, turning to the goal heading
    obs = observation(options={"start": [7.0, 6.99, math.pi / 2 - math.radians(2)]})
    action, _ = IBVSPolicy().predict(obs)
    assert action[0] * 1.2 == pytest.approx(0.5 * 0.01, rel=0.05)  # v_l = lam * 1 cm
    assert action[1] * math.radians(300) == pytest.approx(0.5 * math.radians(2), rel=0.05)


def test_without_the_final_rotation_eq38_is_singular_at_the_goal() -> None:
    # r -> 0: the curvature grows as 1/r and the speed limit leaves a full-speed turn whose
    # sign follows the noise in the direction of v; that is why rotate_radius exists
    obs = observation(options={"start": [7.0, 7.0, math.pi / 2 - 0.3]})
    action, _ = IBVSPolicy(rotate_radius=0.0).predict(obs)
    assert abs(action[0]) < 1e-6 and abs(action[1]) == pytest.approx(1.0)


@pytest.mark.parametrize("offset", [math.pi - 1e-3, -(math.pi - 1e-3)])
def test_heading_errors_near_pi_give_a_finite_bounded_command(offset: float) -> None:
    obs = observation(options={"start": [6.0, 6.0, math.pi / 2 + offset]})
    for variant in ("paper", "current", "mean", "no-frame-change"):
        action, _ = IBVSPolicy(variant).predict(obs)
        assert np.isfinite(action).all() and np.all(np.abs(action) <= 1.0)


def test_missing_observation_keys_name_the_gym_make_argument() -> None:
    env = gym.make("RadialIBVS/Parking-v0")
    obs, _ = env.reset(seed=0)
    with pytest.raises(KeyError, match="goal_depths"):
        IBVSPolicy().predict(obs)
    env = gym.make("RadialIBVS/Parking-v0", goal_depths=True)
    obs, _ = env.reset(seed=0)
    with pytest.raises(KeyError, match="privileged"):
        IBVSPolicy("current").predict(obs)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"variant": "classic"}, "variant"),
        ({"lam": 0.0}, "lam"),
        ({"k2": float("nan")}, "k2"),
        ({"stop_radius": -1.0}, "stop_radius"),
        ({"compensation": "wrong"}, "compensation"),
    ],
)
def test_bad_parameters_are_named(kwargs: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        IBVSPolicy(**kwargs)


def test_registry_builds_every_contract_name_and_rejects_unknown_ones() -> None:
    assert set(POLICY_NAMES) == {
        "ibvs",
        "ibvs-current",
        "ibvs-mean",
        "ibvs-no-frame-change",
        "oracle",
        "ibvs-backward",
        "oracle-backward",
        "ibvs-straight",
        "ibvs-straight-filtered",
        "planner",
        "planner-image-goal",
        "pbvs",
        "pbvs-ekf",
        "ekf-planner",
        "random",
    }
    for name in POLICY_NAMES:
        policy = make_policy(name)
        env = gym.make("RadialIBVS/Parking-v0", task=0, **policy.env_kwargs)
        obs, _ = env.reset(seed=0)
        action, state = policy.predict(obs)
        assert env.action_space.contains(action)
        # the filters' memories, the planner's plan and random's per-episode generators travel
        # in SB3's state; the others are stateless
        stateful = (
            "ibvs-straight-filtered",
            "planner",
            "planner-image-goal",
            "pbvs-ekf",
            "ekf-planner",
            "random",
        )
        assert (state is not None) == (name in stateful), name
    with pytest.raises(ValueError, match="unknown policy 'ppo-nothing'"):
        make_policy("ppo-nothing")
    with pytest.raises(ValueError, match=r"'ibvss' \(did you mean 'ibvs'\?\)"):
        make_policy("ibvss")


def test_random_policy_is_seeded() -> None:
    obs = {"points": np.zeros((4, 16), np.float32)}
    a, _ = RandomPolicy(seed=3).predict(obs)
    b, _ = RandomPolicy(seed=3).predict(obs)
    np.testing.assert_array_equal(a, b)
    assert a.shape == (4, 2)


def _episode(policy: RandomPolicy, steps: int) -> np.ndarray:
    one = {"points": np.zeros(16, np.float32)}
    actions, state, start = [], None, np.ones(1, bool)
    for _ in range(steps):
        action, state = policy.predict(one, state, start)
        actions.append(action)
        start = np.zeros(1, bool)
    return np.array(actions)


def test_a_random_episode_does_not_depend_on_the_lengths_of_the_ones_before() -> None:
    short, long = RandomPolicy(seed=5), RandomPolicy(seed=5)
    _episode(short, 3)
    _episode(long, 40)
    second = _episode(short, 10)
    np.testing.assert_array_equal(second, _episode(long, 10))
    assert np.all(np.abs(second) <= 1.0) and len(np.unique(second)) == second.size


def test_a_random_state_without_episode_start_goes_on_with_its_episode() -> None:
    """As SB3's recurrent policies: with a state and no ``episode_start``, none starts."""
    one = {"points": np.zeros(16, np.float32)}
    policy = RandomPolicy(seed=7)
    first, state = policy.predict(one)
    second, _ = policy.predict(one, state)
    np.testing.assert_array_equal(np.stack([first, second]), _episode(RandomPolicy(seed=7), 2))


def test_a_random_batch_acts_as_its_episodes_one_after_another() -> None:
    alone = RandomPolicy(seed=2)
    episodes = [_episode(alone, 6) for _ in range(3)]
    batch = RandomPolicy(seed=2)
    obs = {"points": np.zeros((3, 16), np.float32)}
    state, start = None, np.ones(3, bool)
    for t in range(6):
        rows = np.arange(3) if t < 4 else np.array([0, 2])  # robot 1 ended after 4 steps
        fed = {"points": obs["points"][rows]}
        if t == 4:
            state = batch.select_state(state, [0, 2])
        actions, state = batch.predict(fed, state, start[rows])
        start[:] = False
        for row, action in zip(rows.tolist(), actions, strict=True):
            np.testing.assert_array_equal(action, episodes[row][t])
    with pytest.raises(ValueError, match="state holds 2 episode"):
        batch.predict(obs, state, np.zeros(3, bool))


@pytest.mark.parametrize("name", ["ibvs-current", "ibvs-mean"])
def test_the_classic_variants_act_for_a_batch_as_for_each_robot_alone(name: str) -> None:
    """Grouped by landmarks in view, stacked pseudo-inverses: each row bit for bit."""
    policy = make_policy(name)
    venv = gym.make_vec(
        "RadialIBVS/Parking-v0",
        num_envs=24,
        vectorization_mode="vector_entry_point",
        scenario="random",
        physics="kinematic",
        **policy.env_kwargs,
    )
    obs, _ = venv.reset(seed=list(range(24)))
    obs["visible"][0, 2:] = 0.0  # fewer than 3 landmarks in view: a zero command
    for step in range(15):
        batch, _ = policy.predict(obs)
        if step == 0:
            assert not batch[0].any() and batch[1:].any()
        alone = np.array([policy.predict({k: v[i] for k, v in obs.items()})[0] for i in range(24)])
        np.testing.assert_array_equal(batch, alone)
        obs, *_ = venv.step(batch)
    venv.close()
