"""``ekf-planner``: the room read from the goal image, the map frame, and the policy's episodes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401  (registers the envs)
from radial_ibvs_agents import make_policy
from radial_ibvs_agents.analytic.ekf_planner import (
    LOOK,
    OPEN_ROOM_M,
    EKFPlanner,
    EKFPlannerState,
    RoomFrame,
    room_frame,
)
from radial_ibvs_agents.experiments.suites import SUITES
from radial_ibvs_agents.rollouts import make_env, run_episodes
from radial_ibvs_gym.geometry import pose_in_frame

VALIDATION_SEED = 10_000  # validation rooms: what a policy's settings may be chosen on


def _on_walls(u: np.ndarray, w: float, d: float) -> np.ndarray:
    """Points on the walls of ``[0, w] x [0, d]``, ``u`` the arc length from the origin."""
    x = np.select([u < w, u < w + d, u < 2 * w + d], [u, w, 2 * w + d - u], 0.0)
    y = np.select([u < w, u < w + d, u < 2 * w + d], [0.0, u - w, d], 2 * (w + d) - u)
    return np.stack([x, y], axis=-1)


def _placed(p: np.ndarray, angle: float, shift: np.ndarray) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return p @ np.array([[c, s], [-s, c]]) + shift


rooms = st.tuples(
    st.floats(3.0, 15.0),
    st.floats(3.0, 15.0),
    st.floats(-math.pi, math.pi),
    st.floats(-10.0, 10.0),
    st.floats(-10.0, 10.0),
)


@settings(max_examples=200, deadline=None)
@given(rooms, st.lists(st.floats(0.05, 0.95), min_size=8, max_size=8, unique=True))
def test_two_landmarks_on_every_wall_give_the_room(
    room: tuple[float, float, float, float, float], along: list[float]
) -> None:
    w, d, angle, sx, sy = room
    # two landmarks inside each wall, at least 5 % of its length from the corners
    sides = np.array([0, 0, 1, 1, 2, 2, 3, 3])
    starts = np.array([0.0, w, w + d, 2 * w + d])[sides]
    lengths = np.array([w, d, w, d])[sides]
    u = starts + lengths * np.array(along)
    if min(abs(a - b) * min(w, d) for a, b in zip(along[::2], along[1::2], strict=True)) < 0.05:
        return  # two landmarks of a wall closer than 5 cm: a pair's direction is noise
    points = _placed(_on_walls(u, w, d), angle, np.array([sx, sy]))
    frame = room_frame(points)
    assert sorted(frame.size) == pytest.approx(sorted([w, d]), abs=1e-6)
    centre = _placed(np.array([[0.5 * w, 0.5 * d]]), angle, np.array([sx, sy]))[0]
    np.testing.assert_allclose(frame.centre, centre, atol=1e-6)
    # in the map frame every landmark lies on the rectangle [0, w'] x [0, d']
    mapped = np.array([frame.to_map(np.array([*p, 0.0]))[:2] for p in points])
    edge = np.minimum(
        np.minimum(np.abs(mapped[:, 0]), np.abs(mapped[:, 0] - frame.size[0])),
        np.minimum(np.abs(mapped[:, 1]), np.abs(mapped[:, 1] - frame.size[1])),
    )
    assert edge.max() < 1e-6


@settings(max_examples=200, deadline=None)
@given(rooms, st.lists(st.floats(0.0, 1.0), min_size=3, max_size=16))
def test_any_landmarks_lie_in_their_rectangle(
    room: tuple[float, float, float, float, float], arcs: list[float]
) -> None:
    w, d, angle, sx, sy = room
    points = _placed(_on_walls(2.0 * (w + d) * np.array(arcs), w, d), angle, np.array([sx, sy]))
    frame = room_frame(points)
    mapped = np.array([frame.to_map(np.array([*p, 0.0]))[:2] for p in points])
    assert (mapped >= -1e-9).all() and (mapped <= frame.size + 1e-9).all()


def test_fewer_than_three_landmarks_give_an_open_room() -> None:
    frame = room_frame(np.array([[1.0, 2.0], [3.0, 4.0]]))
    assert frame.size.tolist() == [OPEN_ROOM_M, OPEN_ROOM_M]
    assert frame.to_map(np.zeros(3))[:2].tolist() == [OPEN_ROOM_M / 2, OPEN_ROOM_M / 2]


@settings(max_examples=200, deadline=None)
@given(
    st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi)),
    st.tuples(st.floats(-5, 5), st.floats(-5, 5), st.floats(-math.pi, math.pi)),
    st.floats(-math.pi, math.pi),
)
def test_the_map_frame_keeps_the_robots_pose_relative_to_the_goal(
    robot: tuple[float, float, float], goal: tuple[float, float, float], angle: float
) -> None:
    robot_w, goal_w = np.array(robot), np.array(goal)
    goal_in_robot = np.array(pose_in_frame(robot_w, goal_w))  # what the filter estimates
    frame = RoomFrame(np.array([0.3, -0.2]), angle, np.array([12.0, 9.0]))
    row = frame.observation(goal_in_robot)
    for seen, expected in (
        (pose_in_frame(row["robot_pose"], row["goal_pose"]), goal_in_robot),
        (pose_in_frame(row["goal_pose"], row["robot_pose"]), pose_in_frame(goal_w, robot_w)),
    ):
        np.testing.assert_allclose(seen[:2], expected[:2], atol=1e-9)
        assert abs(math.remainder(seen[2] - expected[2], 2 * math.pi)) < 1e-9


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"law_radius": -1.0}, "law_radius must be finite and >= 0"),
        ({"look_radius": math.nan}, "look_radius must be finite and >= 0"),
        ({"look_steps": 2.5}, "look_steps must be an integer >= 0"),
        ({"max_looks": -1}, "max_looks must be an integer >= 0"),
        ({"motion_floor": 0.0}, "motion_floor must be finite and positive"),
        ({"gian": 2.0}, "gian"),
    ],
)
def test_bad_settings_are_named(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(ValueError, match=match):
        EKFPlanner(**kwargs)  # type: ignore[arg-type]


def test_it_parks_validation_rooms_through_the_ideal_camera_without_a_collision() -> None:
    variant = SUITES["held-out"][0]
    seeds = [VALIDATION_SEED + k for k in range(40)]
    logs = run_episodes(make_policy("ekf-planner"), seeds, variant.scenario, variant.overrides)
    ends = [log.end for log in logs]
    assert ends.count("collision") <= 1 and ends.count("success") >= 38, ends


def test_it_stops_and_looks_then_restarts_its_filter_from_the_frames() -> None:
    policy = EKFPlanner(look_steps=10, look_radius=0.1)
    env = make_env(policy, "random", {"physics": "kinematic"})
    obs, _ = env.reset(seed=VALIDATION_SEED + 1)
    state: EKFPlannerState | None = None
    phases, actions = [], []
    for t in range(600):
        action, state = policy.predict(obs, state, episode_start=np.array([t == 0]))
        assert state is not None
        phases.append(int(state.phase[0]))
        actions.append(action)
        obs, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            break
    assert LOOK in phases
    first = phases.index(LOOK)
    looked = [a for a, p in zip(actions[first:], phases[first:], strict=True) if p == LOOK]
    assert len(looked) >= 10 and not np.any(looked)  # it stood still while looking
    assert int(state.looks[0]) >= 1
    assert terminated  # and parked


def test_a_state_cut_to_rows_keeps_those_robots() -> None:
    policy = EKFPlanner()
    env = make_env(policy, "random", {"physics": "kinematic"})
    observations = []
    for seed in (3, 4, 5):
        obs, _ = env.reset(seed=seed)
        observations.append(obs)
    batch = {k: np.stack([o[k] for o in observations]) for k in observations[0]}
    _, state = policy.predict(batch, None, episode_start=np.ones(3, bool))
    cut = EKFPlanner.select_state(state, np.array([2, 0]))
    np.testing.assert_array_equal(cut.filters.mean, state.filters.mean[[2, 0]])
    assert cut.rooms == [state.rooms[2], state.rooms[0]]
    assert cut.phase.shape == (2,)
