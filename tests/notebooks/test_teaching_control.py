"""Helpers of the control notebooks (``notebooks._helpers.teaching_control``)."""

from __future__ import annotations

import math
from pathlib import Path

import gymnasium as gym
import matplotlib
import matplotlib.pyplot as plt
import numpy as np
import pytest
from _helpers import teaching_control as tc

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import IBVSPolicy, make_policy
from radial_ibvs_agents.learned.training.zoo_config import load_train_config
from radial_ibvs_gym import paper

CONFIG = Path(__file__).resolve().parents[2] / "configs" / "agents" / "ppo_parking.yaml"
H = paper.CAMERA_HEIGHT_M


def test_goal_in_robot_frame_known_values() -> None:
    np.testing.assert_allclose(
        tc.goal_in_robot_frame(paper.START_POSE, paper.goal_pose(1)),
        [4.0, 4.0, math.pi / 2],
        atol=1e-12,
    )
    # robot facing +y: a goal straight ahead is at +x in the robot frame
    np.testing.assert_allclose(
        tc.goal_in_robot_frame([1.0, 1.0, math.pi / 2], [1.0, 3.0, 0.0]),
        [2.0, 0.0, -math.pi / 2],
        atol=1e-12,
    )
    # the rotation is wrapped to [-pi, pi)
    out = tc.goal_in_robot_frame([0.0, 0.0, 0.1], [0.0, 0.0, 2 * math.pi - 0.1])
    assert out[2] == pytest.approx(-0.2)
    batch = tc.goal_in_robot_frame(np.zeros((5, 3)), paper.goal_pose(2))
    assert batch.shape == (5, 3)
    with pytest.raises(ValueError):
        tc.goal_in_robot_frame([0.0, 0.0], [1.0, 1.0, 0.0])
    with pytest.raises(ValueError):
        tc.goal_in_robot_frame([0.0, math.nan, 0.0], [1.0, 1.0, 0.0])


@pytest.mark.parametrize("depth_scale", [1.0, 1.3])
@pytest.mark.parametrize("task", [0, 3])
def test_ideal_observation_is_the_envs(task: int, depth_scale: float) -> None:
    env = gym.make(
        "RadialIBVS/Parking-v0",
        scenario="paper-sim",
        task=task,
        physics="kinematic",
        goal_depths=True,
        depth_scale=depth_scale,
    )
    start = np.array([4.0, 2.5, 0.7])
    obs, _ = env.reset(seed=0, options={"start": start})
    ours = tc.ideal_observation(
        paper.EQ39_POINTS, start, paper.goal_pose(task), H, depth_scale=depth_scale
    )
    assert set(ours) == set(obs)
    for key, value in obs.items():
        assert ours[key].dtype == np.float32 and ours[key].shape == value.shape, key
        np.testing.assert_allclose(ours[key], value, atol=1e-6, err_msg=key)
    env.close()
    with pytest.raises(ValueError):
        tc.ideal_observation(paper.EQ39_POINTS, start, start, H, depth_scale=0.0)


def test_ibvs_estimates_match_the_truth_near_the_goal_and_scale_with_the_depths() -> None:
    policy = IBVSPolicy()
    goal = np.array(paper.goal_pose(1))
    near = goal + np.array([[0.01, -0.005, 0.002], [0.0, 0.0, 0.0]])
    est = tc.ibvs_estimates(policy, paper.EQ39_POINTS, near, goal, H)
    truth = tc.goal_in_robot_frame(near, goal)
    np.testing.assert_allclose(est, truth, atol=2e-4)  # first order: exact as r -> 0
    # the same as the policy's own estimate on the env's observation
    env = gym.make("RadialIBVS/Parking-v0", scenario="paper-sim", task=1, goal_depths=True)
    obs, _ = env.reset(seed=0)
    v, gamma = policy.twist(obs)
    start = tc.ibvs_estimates(policy, paper.EQ39_POINTS, [paper.START_POSE], goal, H)[0]
    np.testing.assert_allclose(start, [v[0] / policy.lam, v[1] / policy.lam, gamma], atol=1e-5)
    env.close()
    # d* -> s d*: L* -> L* / s, so the translation scales by s exactly and gamma is unchanged
    scaled = tc.ibvs_estimates(policy, paper.EQ39_POINTS, [paper.START_POSE], goal, H, 1.3)[0]
    np.testing.assert_allclose(scaled[:2], 1.3 * start[:2], rtol=1e-5)
    assert scaled[2] == pytest.approx(start[2], abs=1e-6)


def test_run_task_parks_and_records_the_goal_depths() -> None:
    log = tc.run_task(make_policy("ibvs"), 1, policy_name="ibvs", depth_scale=1.3)
    assert log.success and log.policy == "ibvs" and log.task == 1
    assert log.physics == "kinematic"
    np.testing.assert_allclose(log.extra["goal_depths"], log.info["goal_depths"])
    start = [4.0, 3.0, 0.5]
    oracle = tc.run_task(make_policy("oracle"), 0, options={"start": start}, max_steps=5)
    np.testing.assert_allclose(oracle.poses[0], start)
    assert oracle.steps == 5 and "goal_depths" in oracle.extra


def test_hausdorff_distance() -> None:
    a = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    b = np.array([[0.0, 0.5], [2.0, 0.5]])
    assert tc.hausdorff_distance(a, b) == pytest.approx(math.hypot(1.0, 0.5))
    assert tc.hausdorff_distance(b, a) == pytest.approx(math.hypot(1.0, 0.5))
    poses = np.column_stack([a, [0.0, 1.0, 2.0]])  # the yaw column is ignored
    assert tc.hausdorff_distance(poses, a) == 0.0
    with pytest.raises(ValueError):
        tc.hausdorff_distance(np.zeros((0, 2)), a)
    with pytest.raises(ValueError):
        tc.hausdorff_distance(np.zeros(3), a)


def test_starts_in_goal_frame() -> None:
    rows = [
        {"start_pose": [1.0, 3.0, 0.0], "goal_pose": [1.0, 1.0, math.pi / 2], "success": True},
        {"start_pose": [0.0, 0.0, 0.0], "goal_pose": [1.0, 0.0, 0.0], "success": False},
    ]
    xy, success = tc.starts_in_goal_frame(rows)
    np.testing.assert_allclose(xy, [[2.0, 0.0], [-1.0, 0.0]], atol=1e-12)
    assert success.tolist() == [True, False]
    xy, success = tc.starts_in_goal_frame([])
    assert xy.shape == (0, 2) and success.shape == (0,)


def test_small_train_config() -> None:
    config = load_train_config(CONFIG)
    small = tc.small_train_config(config, n_envs=2, n_steps=64, eval_freq=128, eval_episodes=2)
    assert small.n_envs == 2 and small.eval_freq == 128 and small.eval_episodes == 2
    assert small.algo_kwargs["n_steps"] == 64 and small.algo_kwargs["batch_size"] == 128
    assert small.env_kwargs == config.env_kwargs and small.policy == config.policy
    assert config.algo_kwargs["n_steps"] == 512 and config.n_envs == 8  # unchanged
    custom = tc.small_train_config(
        config, n_envs=2, n_steps=64, batch_size=32, eval_freq=1, eval_episodes=1
    )
    assert custom.algo_kwargs["batch_size"] == 32
    with pytest.raises(ValueError, match="batch_size"):
        tc.small_train_config(
            config, n_envs=2, n_steps=64, batch_size=48, eval_freq=1, eval_episodes=1
        )
    with pytest.raises(ValueError, match="n_envs"):
        tc.small_train_config(config, n_envs=0, n_steps=64, eval_freq=1, eval_episodes=1)
    with pytest.raises(ValueError, match=">= 2"):
        tc.small_train_config(config, n_envs=1, n_steps=1, eval_freq=1, eval_episodes=1)


def test_read_progress_csv(tmp_path: Path) -> None:
    path = tmp_path / "progress.csv"
    path.write_text(
        "time/total_timesteps,rollout/ep_rew_mean,eval/mean_reward\n4096,,\n8192,-3.5,-2.0\n"
    )
    columns = tc.read_progress_csv(path)
    np.testing.assert_array_equal(columns["time/total_timesteps"], [4096.0, 8192.0])
    assert math.isnan(columns["rollout/ep_rew_mean"][0])
    assert columns["eval/mean_reward"][1] == -2.0
    with pytest.raises(ValueError, match="not found"):
        tc.read_progress_csv(tmp_path / "missing.csv")
    (tmp_path / "empty.csv").write_text("")
    with pytest.raises(ValueError, match="header"):
        tc.read_progress_csv(tmp_path / "empty.csv")


def test_preserve_matplotlib_backend() -> None:
    before = matplotlib.get_backend()
    with tc.preserve_matplotlib_backend():
        plt.switch_backend("pdf")
        assert matplotlib.get_backend() == "pdf"
    assert matplotlib.get_backend() == before


def test_the_library_figures_draw_into_the_notebooks_axes(tmp_path: Path) -> None:
    """The notebooks draw Fig. 3-4 and 6-8 with the library's functions (``axes=``): no figure
    of their own, nothing saved unless asked; the default still makes and saves one."""
    from radial_ibvs_agents.experiments.figures import plot_paths, plot_servoing
    from radial_ibvs_agents.experiments.reproduce import reproduce

    logs = reproduce(physics=("kinematic",), tasks=[1], progress=False)
    ibvs = next(log for log in logs if log.policy == "ibvs")
    figures = plt.get_fignums()
    fig, axes = plt.subplots(2, 3)
    assert plot_servoing(ibvs, axes=axes) is None
    n = len(ibvs.poses)
    assert len(axes[0, 1].get_lines()) == 28 and len(axes[0, 1].get_lines()[0].get_xdata()) == n
    assert len(axes[1, 0].get_lines()) == 3  # v_x, v_y, omega_z
    assert axes[0, 0].get_title().startswith("image point errors")
    with pytest.raises(ValueError, match=r"\(2, 3\)"):
        plot_servoing(ibvs, axes=axes[0])
    fig2, ax = plt.subplots()
    styles = {"oracle": ("k", "--"), "ibvs": ("C1", "-")}
    assert plot_paths(logs, ("ibvs", "oracle"), axes=ax, styles=styles) is None
    oracle = [line for line in ax.get_lines() if line.get_label() == "oracle"]
    assert len(oracle) == 1 and oracle[0].get_linestyle() == "--"
    assert ax.get_title() == "goal yaw 90 deg"
    with pytest.raises(ValueError, match="1 tasks"):
        plot_paths(logs, ("ibvs",), axes=[ax, ax])
    assert plt.get_fignums() == [*figures, fig.number, fig2.number]  # no figure of their own
    saved = plot_paths(logs, ("ibvs", "oracle"), tmp_path / "fig3.png", "title")
    assert saved == tmp_path / "fig3.png" and saved.stat().st_size > 0
    assert plot_servoing(ibvs, tmp_path / "fig6.png") == tmp_path / "fig6.png"
    assert plt.get_fignums() == [*figures, fig.number, fig2.number]  # closed once saved
    rows = [
        {"start_pose": [1.0, 3.0, 0.0], "goal_pose": [1.0, 1.0, 0.0], "success": True},
        {"start_pose": [0.0, 0.0, 0.0], "goal_pose": [1.0, 0.0, 0.0], "success": False},
    ]
    assert tc.draw_convergence_map(ax, rows, "ibvs") == 0.5
    assert ax.get_title() == "ibvs: 50% of 2"
    plt.close(fig)
    plt.close(fig2)
