"""DAgger (``radial_ibvs_agents.learned.dagger.distill``) without a student: the goal in the robot's
frame, the teacher's labels, the config's errors, each round's step size and the loss. The tests
that train a student are in ``training/test_dagger_students.py``."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import torch
from dagger_setup import ENV, SMALL

from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.learned.dagger.distill import goal_in_robot_frame, load_dagger_config
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env


def test_goal_in_robot_frame():
    obs = {"robot_pose": np.array([[1.0, 1.0, np.pi / 2]]), "goal_pose": np.array([[1, 4, 0.0]])}
    np.testing.assert_allclose(goal_in_robot_frame(obs), [[1.0, 0.0, 0.0, -1.0]], atol=1e-7)


def test_the_teachers_labels_still_park():
    """The teacher's settings (turn and drive together, forwards only, the smooth law in the
    last 30 cm) park 32 of 32 rooms, and hand over to the oracle near the goal."""
    from radial_ibvs_agents.analytic import PoseOracle

    teacher = make_analytic(
        "planner", goal_tolerance=0.01, waypoint_tolerance=0.1, hold_radius=0.0,
        drive_gate=0.35, reverse=False, final_radius=0.3,
    )  # fmt: skip
    oracle, handed_over = PoseOracle(), 0
    n = 32
    venv = make_vec_env(
        "RadialIBVS/Parking-v0", n, seed=10_000, monitor=False, privileged=True,
        privileged_map=True, **ENV,
    )  # fmt: skip
    obs, state, starts = venv.reset(), None, np.ones(n, dtype=bool)
    done, success = np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
    while not done.all():
        action, state = teacher.predict(obs, state, starts)
        near = np.hypot(*(obs["goal_pose"][:, :2] - obs["robot_pose"][:, :2]).T) < 0.3
        if near.any():  # a straight room: the last segment is the only one
            expected = oracle.predict({k: v[near] for k, v in obs.items()})[0]
            np.testing.assert_array_equal(action[near], expected)
            handed_over += int(near.sum())
        assert (action[~near, 0] >= 0).all()  # forwards only
        obs, _, starts, infos = venv.step(action)
        for i in np.flatnonzero(starts & ~done):
            success[i] = infos[i]["is_success"]
        done |= starts
    assert success.all() and handed_over > 100


@pytest.mark.parametrize(
    ("line", "match"),
    [
        ("  rounds: 0", "rounds"),
        ("  beta: 1.5", "beta"),
        ("  teacher: teleport", "teleport"),
        ("  net_arch: [64, -1]", "net_arch"),
        ("  rouns: 3", "rouns"),
        ("  aux_weight: -1", "aux_weight"),
        ("  relative_floor: -0.1", "relative_floor"),
        ("  relative_floor: true", "relative_floor"),
        ("  extractor: transformer", "transformer"),
        ("  angle_keys: [points]", "angle_keys"),
        ("  final_learning_rate: 0.5", r"final_learning_rate .*up to learning_rate"),
        ("  final_learning_rate: -1.0e-4", "final_learning_rate"),
    ],
)
def test_config_errors_name_the_key(tmp_path, line, match):
    path = tmp_path / "bad.yaml"
    path.write_text(SMALL + line + "\n")
    with pytest.raises(ValueError, match=match):
        load_dagger_config(path)


def test_each_rounds_fit_anneals_the_step_size_from_the_full_one(tmp_path):
    """final_learning_rate: every round starts at learning_rate and ends at the final one,
    along a cosine (half-way: the mean); without it the step size is left alone."""
    from radial_ibvs_agents.learned.dagger.distill import round_schedule

    path = tmp_path / "config.yaml"
    path.write_text(SMALL + "  learning_rate: 0.001\n  final_learning_rate: 0.0001\n")
    config = load_dagger_config(path)
    weight = torch.nn.Parameter(torch.zeros(1))
    optimiser = torch.optim.Adam([weight], lr=config.learning_rate)
    for _ in range(2):  # two rounds
        schedule = round_schedule(optimiser, config)
        seen = [optimiser.param_groups[0]["lr"]]
        for _ in range(config.updates_per_round):
            optimiser.step()
            schedule.step()
            seen.append(optimiser.param_groups[0]["lr"])
        assert seen[0] == pytest.approx(1e-3) and seen[-1] == pytest.approx(1e-4)
        assert all(a >= b for a, b in itertools.pairwise(seen))
        half = seen[config.updates_per_round // 2]
        assert half == pytest.approx(5.5e-4, rel=0.05)
    path.write_text(SMALL)
    assert round_schedule(optimiser, load_dagger_config(path)) is None


def test_the_relative_loss_weighs_a_small_labels_error_as_a_large_ones():
    """With relative_floor, missing a label of 0.02 by 0.01 costs what missing a label of 1 by
    0.5 does (about); the plain loss makes the first 2,500 times cheaper."""
    from radial_ibvs_agents.learned.dagger.distill import action_loss

    labels = torch.tensor([[0.02, 1.0]])
    small_miss = torch.tensor([[0.03, 1.0]])
    large_miss = torch.tensor([[0.02, 1.5]])
    ones = torch.ones(2)
    plain = [float(action_loss(a, labels, ones)) for a in (small_miss, large_miss)]
    assert plain[1] / plain[0] == pytest.approx(2500.0)
    relative = [float(action_loss(a, labels, ones, 1e-3)) for a in (small_miss, large_miss)]
    assert relative[0] / relative[1] == pytest.approx(1.0, rel=0.1)
    assert float(action_loss(labels, labels, ones, 0.05)) == 0.0
