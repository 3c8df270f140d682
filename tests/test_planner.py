"""``planner``: plans with the map (straight or OMPL), follows turn-drive-turn, parks."""

from __future__ import annotations

import sys

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401
from agents import make_policy
from agents.analytic.planner import MapPlanner, plan_path, segment_free
from agents.cli import main
from agents.runner import make_env, run_episode

ROOM = np.array([8.0, 6.0])
WALL = np.array([[4.0, 3.0, 1.2]])  # a pillar between start and goal
NO_OBSTACLE = np.zeros((1, 3))


def test_a_free_straight_segment_is_the_plan() -> None:
    path = plan_path(np.array([1.0, 1.0]), np.array([7.0, 5.0]), ROOM, NO_OBSTACLE, 0.35)
    assert path is not None
    np.testing.assert_array_equal(path, [[1.0, 1.0], [7.0, 5.0]])


def test_a_blocked_segment_is_planned_around_and_every_segment_is_free() -> None:
    start, goal = np.array([1.0, 3.0]), np.array([7.0, 3.0])
    assert not segment_free(start, goal, ROOM, WALL, 0.35)
    path = plan_path(start, goal, ROOM, WALL, 0.35)
    assert path is not None and len(path) > 2
    np.testing.assert_array_equal(path[[0, -1]], [start, goal])
    assert all(segment_free(path[k], path[k + 1], ROOM, WALL, 0.35) for k in range(len(path) - 1))
    np.testing.assert_array_equal(plan_path(start, goal, ROOM, WALL, 0.35), path)  # seeded


def test_no_plan_when_the_goal_is_not_free() -> None:
    assert plan_path(np.array([1.0, 3.0]), np.array([4.0, 3.0]), ROOM, WALL, 0.35) is None


@settings(max_examples=25, deadline=None)
@given(
    sx=st.floats(0.5, 2.0), sy=st.floats(0.5, 5.5), gx=st.floats(6.0, 7.5), gy=st.floats(0.5, 5.5)
)
def test_plans_around_the_pillar_are_free(sx: float, sy: float, gx: float, gy: float) -> None:
    start, goal = np.array([sx, sy]), np.array([gx, gy])
    path = plan_path(start, goal, ROOM, WALL, 0.35, time_limit_s=1.0)
    assert path is not None
    assert all(segment_free(path[k], path[k + 1], ROOM, WALL, 0.35) for k in range(len(path) - 1))


@pytest.mark.parametrize("scenario", ["random", "random-obstacles"])
def test_it_parks_held_out_rooms_and_the_same_seed_replays_bit_for_bit(scenario: str) -> None:
    policy = make_policy("planner")
    env = make_env(policy, scenario, {"physics": "kinematic"})
    logs = [run_episode(policy, env, seed=100_000 + k) for k in range(12)]
    assert all(log.success for log in logs), [log.end for log in logs]
    again = run_episode(policy, env, seed=100_000 + 5)
    np.testing.assert_array_equal(again.poses, logs[5].poses)


def test_it_parks_with_pymunk_and_acts_on_a_batch() -> None:
    policy = make_policy("planner")
    env = make_env(policy, "paper-sim", {"physics": "pymunk"})
    assert all(run_episode(policy, env, seed=k).success for k in range(4))
    kwargs = dict(scenario="random-obstacles", physics="kinematic", **policy.env_kwargs)
    venv = gym.make_vec(
        "RadialIBVS/Parking-v0", num_envs=3, vectorization_mode="vector_entry_point", **kwargs
    )
    obs, _ = venv.reset(seed=0)
    state, starts = None, np.ones(3, dtype=bool)
    for _ in range(5):
        actions, state = policy.predict(obs, state, starts)
        assert actions.shape == (3, 2) and np.abs(actions).max() <= 1.0
        obs, _, terminated, truncated, _ = venv.step(actions)
        starts = terminated | truncated


def test_the_map_is_required_and_named() -> None:
    policy = make_policy("planner")
    obs, _ = gym.make("RadialIBVS/Parking-v0", privileged=True).reset(seed=0)
    with pytest.raises(KeyError, match="privileged_map"):
        policy.predict(obs)


def test_without_ompl_the_error_names_the_extra(monkeypatch, capsys) -> None:
    monkeypatch.setitem(sys.modules, "ompl", None)  # `from ompl import ...` raises ImportError
    with pytest.raises(ValueError, match=r"radial_ibvs_gym\[planning\]"):
        MapPlanner()
    assert main(["evaluate", "--policy", "planner", "--episodes", "1"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "radial_ibvs_gym[planning]" in err


def test_every_summary_gives_the_planners_rate_as_the_limit() -> None:
    from agents.experiments.benchmark import markdown_table, run_benchmark, summary_rows

    results = run_benchmark(["random", "planner"], ["paper-lab"], episodes=2, progress=False)
    summaries = summary_rows(results)
    assert {s["policy"]: s["limit"] for s in summaries} == {"random": 1.0, "planner": 1.0}
    random_row = next(s for s in summaries if s["policy"] == "random")
    table = markdown_table(summaries)
    assert f"| {random_row['success_rate']:.0%} | " in table and "| 100% |" in table
    assert "collision" in table or "lost" in table or "time-out" in table  # the failure causes


def test_passing_the_state_back_without_episode_start_keeps_the_plan() -> None:
    policy = make_policy("planner")
    env = make_env(policy, "random-obstacles", {"physics": "kinematic"})
    obs, _ = env.reset(seed=100_003)
    _, state = policy.predict(obs)
    plan = state[0]
    for _ in range(3):
        obs = env.step(policy.predict(obs, state)[0])[0]
        _, state = policy.predict(obs, state)
        assert state[0] is plan  # the same plan object, followed, not replanned


def test_the_plan_keeps_enough_landmarks_in_view() -> None:
    # two landmarks always seen; a third seen only between 1 and 2 m from (4, 3): the straight
    # drive through (4, 3) loses it, so the plan goes round
    landmarks = np.array([[0.0, 3.0, 1.0], [8.0, 3.0, 1.0], [4.0, 3.0, 1.0]])
    ranges = np.array([[0.1, 100.0], [0.1, 100.0], [1.0, 2.0]])
    view = (landmarks, ranges, 3)
    start, goal = np.array([2.5, 3.0]), np.array([5.5, 3.0])
    assert segment_free(start, goal, ROOM, NO_OBSTACLE, 0.35)
    assert not segment_free(start, goal, ROOM, NO_OBSTACLE, 0.35, view)
    path = plan_path(start, goal, ROOM, NO_OBSTACLE, 0.35, view=view)
    assert path is not None and len(path) > 2
    assert all(
        segment_free(path[k], path[k + 1], ROOM, NO_OBSTACLE, 0.35, view)
        for k in range(len(path) - 1)
    )
    far = np.array([7.0, 3.0])  # 3 m from the third landmark: it cannot be seen there
    assert plan_path(start, far, ROOM, NO_OBSTACLE, 0.35, view=view) is None


def test_the_map_observation_gives_each_landmarks_visible_range() -> None:
    env = gym.make("RadialIBVS/Parking-v0", scenario="paper-lab", physics="kinematic",
                   privileged=True, privileged_map=True)  # fmt: skip
    obs, _ = env.reset(seed=0)
    lo, hi = obs["landmark_range"].T
    assert obs["landmarks"].shape == (9, 3) and (lo < hi).all()
    d = np.hypot(*(obs["landmarks"][:, :2] - obs["robot_pose"][:2]).T)
    seen = (d > lo) & (d < hi)
    np.testing.assert_array_equal(seen, obs["visible"] > 0.5)  # the camera's own rule
