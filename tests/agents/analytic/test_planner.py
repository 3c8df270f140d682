"""``planner``: plans with the map (straight or OMPL), follows turn-drive-turn, parks."""

from __future__ import annotations

import sys

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import make_policy
from radial_ibvs_agents.analytic.planner import MapPlanner, Plan, plan_path, segment_free
from radial_ibvs_agents.cli import main
from radial_ibvs_agents.rollouts import make_env, run_episode

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
@example(sx=0.5, sy=1.5, gx=6.0, gy=1.5)  # OMPL's own path grazed the pillar: planned again
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
    from radial_ibvs_agents.experiments.benchmark import run_benchmark, summary_rows
    from radial_ibvs_agents.experiments.tables import markdown_table

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


def _aligner(approach: float = 0.0) -> MapPlanner:
    return MapPlanner(
        goal_tolerance=0.015, waypoint_tolerance=0.1, hold_radius=0.0, drive_gate=1.57,
        reverse=False, align_radius=0.04, approach=approach,
    )  # fmt: skip


def _park_rooms(planner: MapPlanner, n: int, watch) -> np.ndarray:
    """Run one episode in each of ``n`` held-out random rooms (kinematic); call
    ``watch(obs, action, done)`` before each step; return whether each episode parked."""
    from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env

    venv = make_vec_env(
        "RadialIBVS/Parking-v0", n, seed=10_000, monitor=False, scenario="random",
        physics="kinematic", privileged=True, privileged_map=True,
    )  # fmt: skip
    obs, state, starts = venv.reset(), None, np.ones(n, dtype=bool)
    done, success = np.zeros(n, dtype=bool), np.zeros(n, dtype=bool)
    while not done.all():
        action, state = planner.predict(obs, state, starts)
        watch(obs, action, done)
        obs, _, starts, infos = venv.step(action)
        for i in np.flatnonzero(starts & ~done):
            success[i] = infos[i]["is_success"]
        done |= starts
    venv.close()
    return success


def _labels(planner: MapPlanner, poses: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """The planner's commands at ``poses`` ``(B, 3)``, for one goal in an empty room."""
    n = len(poses)
    obs = {
        "robot_pose": poses, "goal_pose": np.tile(goal, (n, 1)), "room": np.tile(ROOM, (n, 1)),
        "obstacles": np.zeros((n, 1, 3)), "landmarks": np.zeros((n, 1, 3)),
        "landmark_range": np.zeros((n, 1, 2)),
    }  # fmt: skip
    planner.min_visible = 0  # no landmarks here: plan without the visibility rule
    return planner.predict(obs, None, np.ones(n, dtype=bool))[0]


@settings(max_examples=60, deadline=None)
@given(
    r=st.floats(0.0, 0.039), bearing=st.floats(-np.pi, np.pi), yaw=st.floats(-np.pi, np.pi),
    goal_yaw=st.floats(-3.0, 3.0),
)  # fmt: skip
def test_the_final_alignment_is_continuous_and_never_moves_away(r, bearing, yaw, goal_yaw):
    """Within align_radius the command is a continuous function of the pose (a millimetre
    moves it by little) but where the goal lies dead behind (the forwards-only drive's turn
    flips there, while the alignment backs up), and where it is wholly the alignment the speed
    never increases the distance to the goal."""
    goal = np.array([4.0, 3.0, goal_yaw])
    pose = np.array([4.0 + r * np.cos(bearing), 3.0 + r * np.sin(bearing), yaw])
    nudged = pose + np.array([0.0005, -0.0005, 0.001])
    a, b = _labels(_aligner(), np.stack([pose, nudged]), goal)
    assert np.all(np.abs(a) <= 1.0 + 1e-9)
    behind = abs(abs(bearing + np.pi - yaw) % (2 * np.pi) - np.pi) < 0.1  # goal dead behind
    wrap = abs(abs(goal_yaw - yaw) % (2 * np.pi) - np.pi) < 0.01  # goal heading opposite
    if not (behind and r > 0.015) and not wrap and r > 0.002:
        np.testing.assert_allclose(a, b, atol=0.15)
    if r < 0.015:  # wholly the alignment: drive towards the goal's foot on the heading line
        to_goal = goal[:2] - pose[:2]
        along = to_goal @ [np.cos(yaw), np.sin(yaw)]
        assert a[0] * along >= 0.0


def test_the_aligning_teacher_parks_and_hands_over_near_the_goal() -> None:
    """From 4 cm in, the command leaves the follower's: the aligning teacher parks 16 of 16
    rooms through the env, forwards only until the alignment."""
    aligned = []

    def watch(obs, action, done) -> None:
        distance = np.hypot(*(obs["goal_pose"][:, :2] - obs["robot_pose"][:, :2]).T)
        far = distance >= 0.04
        assert (action[far, 0] >= 0).all()  # forwards only outside the alignment
        aligned.append(int((~far & ~done).sum()))

    assert _park_rooms(_aligner(), 16, watch).all() and sum(aligned) > 16


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"align_radius": 0.04, "final_radius": 0.3}, "set one of them to 0"),
        ({"align_radius": 0.01, "goal_tolerance": 0.015}, "align_radius must exceed"),
        ({"align_radius": float("nan")}, "align_radius must be finite"),
        ({"approach": 1.0}, "approach must be below 1"),
        ({"approach": -0.5}, "approach must be finite and positive"),
        ({"approach_limit": 0.0}, "approach_limit must be finite and positive"),
        ({"align_unblock": True}, "align_unblock acts on align_radius's blend"),
    ],
)
def test_align_radius_errors_name_the_value(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        MapPlanner(**kwargs)


def test_the_approach_arrives_along_the_goal_heading() -> None:
    """Aiming behind the goal (approach 0.5), the teacher parks 16 of 16 rooms and comes
    within 5 cm of the goal with a median heading error under 20 deg; aiming at the goal,
    over 45 deg."""
    medians = []
    for approach in (0.0, 0.5):
        arrival = np.full(16, np.nan)

        def watch(obs, action, done, arrival=arrival) -> None:
            distance = np.hypot(*(obs["goal_pose"][:, :2] - obs["robot_pose"][:, :2]).T)
            error = (obs["goal_pose"][:, 2] - obs["robot_pose"][:, 2] + np.pi) % (2 * np.pi)
            first = ~done & np.isnan(arrival) & (distance < 0.05)
            arrival[first] = np.degrees(np.abs(error[first] - np.pi))

        assert _park_rooms(_aligner(approach), 16, watch).all(), approach
        medians.append(np.nanmedian(arrival))
    assert medians[0] > 45.0 and medians[1] < 20.0, medians


def _teacher_env() -> gym.Env:
    """A random-room env with the planner's privileged observation."""
    return gym.make(
        "RadialIBVS/Parking-v0", scenario="random", physics="kinematic", privileged=True,
        privileged_map=True,
    )  # fmt: skip


#: the docking-law teacher's arguments (research/configs/dagger_planner_set_line.yaml)
LINE_TEACHER = {
    "goal_tolerance": 0.015, "waypoint_tolerance": 0.1, "hold_radius": 0.0, "drive_gate": 1.57,
    "reverse": False, "align_radius": 0.04, "approach": 0.5, "align_unblock": True,
    "line_radius": 0.3,
}  # fmt: skip


def test_align_unblock_leaves_no_stall_point_near_the_goal() -> None:
    """From 3 cm off the goal with the heading up to 90 deg off, the blend of align_radius
    stands still for good in some rooms (its two commands cancel); align_unblock parks all."""
    env = _teacher_env()
    rng = np.random.default_rng(0)
    starts = []
    for k in range(20):
        _, info = env.reset(seed=10_000 + k)
        g = np.asarray(info["goal_pose"], dtype=np.float64)
        bearing, error = rng.uniform(-np.pi, np.pi), rng.uniform(-np.pi / 2, np.pi / 2)
        starts.append(g + np.array([0.03 * np.cos(bearing), 0.03 * np.sin(bearing), error]))
    parked = {}
    for unblock in (False, True):
        planner = MapPlanner(
            goal_tolerance=0.015, waypoint_tolerance=0.1, hold_radius=0.0, drive_gate=1.57,
            reverse=False, align_radius=0.04, approach=0.5, align_unblock=unblock,
        )  # fmt: skip
        ends = [
            run_episode(
                planner, env, seed=10_000 + k, options={"start": start}, max_steps=300
            ).success
            for k, start in enumerate(starts)
        ]
        parked[unblock] = sum(ends)
    env.close()
    assert parked[True] == 20 and parked[False] <= 15, parked


def test_align_unblock_must_be_a_bool() -> None:
    with pytest.raises(ValueError, match="align_unblock must be true or false, got 'yes'"):
        MapPlanner(align_unblock="yes")  # type: ignore[arg-type]


def test_the_docking_law_parks_from_the_cone_and_turns_by_the_heading_error() -> None:
    """With line_radius, from 3-25 cm behind the goal in its cone (heading up to 30 deg off)
    and from just past it, the teacher parks 20 of 20 rooms; near the goal its turn is the
    docking law's, a function of the heading error and offsets, not of a bearing."""
    env = _teacher_env()
    planner = MapPlanner(**LINE_TEACHER)
    rng = np.random.default_rng(1)
    parked = 0
    for k in range(20):
        _, info = env.reset(seed=10_000 + k)
        g = np.asarray(info["goal_pose"], dtype=np.float64)
        if k % 4 == 3:  # past the goal, within the band around its line
            along, side = rng.uniform(0.0, 0.04), rng.uniform(-0.012, 0.012)
        else:
            along = -rng.uniform(0.03, 0.25)
            side = -along * np.tan(rng.uniform(-0.28, 0.28))
        c, s = np.cos(g[2]), np.sin(g[2])
        start = g + np.array([c * along - s * side, s * along + c * side, rng.uniform(-0.5, 0.5)])
        parked += run_episode(
            planner, env, seed=10_000 + k, options={"start": start}, max_steps=300
        ).success
    env.close()
    assert parked == 20
    # at the goal, on its line, 10 deg off: a pure turn back to the goal heading
    plan = Plan(waypoints=np.array([[-1.0, 0.0], [0.0, 0.0]]), goal_yaw=0.0)
    v, omega = planner._dock(plan, np.array([0.0, 0.0, np.radians(10.0)]))
    assert v == 0.0 and omega < 0.0


def test_within_turn_radius_it_turns_in_place_and_parks() -> None:
    """With turn_radius, from up to 1.8 cm off the goal and any heading, the teacher stands
    and turns (speed 0), and parks 10 of 10 rooms without leaving the spot."""
    env = _teacher_env()
    planner = MapPlanner(**LINE_TEACHER, turn_radius=0.018, turn_gain=6.0)
    rng = np.random.default_rng(2)
    for k in range(10):
        _, info = env.reset(seed=10_000 + k)
        g = np.asarray(info["goal_pose"], dtype=np.float64)
        bearing, offset = rng.uniform(-np.pi, np.pi), rng.uniform(0.0, 0.017)
        start = g + np.array([offset * np.cos(bearing), offset * np.sin(bearing), 0.0])
        start[2] = g[2] + rng.uniform(-np.pi, np.pi)
        result = run_episode(planner, env, seed=10_000 + k, options={"start": start})
        assert result.success, k
        assert np.allclose(result.poses[:, :2], start[:2], atol=1e-6), k  # never moved
    env.close()
    plan = Plan(waypoints=np.array([[-1.0, 0.0], [0.0, 0.0]]), goal_yaw=0.0)
    v, omega = planner._turn(plan, np.array([0.01, 0.0, np.radians(-6.0)]))
    assert v == 0.0
    assert np.isclose(omega, 6.0 * np.radians(6.0) / planner.robot.max_angular_speed)
    # with turn_floor, the last degrees' label stays at the floor (0.5 rad/s), not 6/s * 2 deg
    floored = MapPlanner(**LINE_TEACHER, turn_radius=0.018, turn_gain=6.0, turn_floor=0.5)
    v, omega = floored._turn(plan, np.array([0.01, 0.0, np.radians(2.0)]))
    assert v == 0.0
    assert np.isclose(omega, -0.5 / planner.robot.max_angular_speed)


def test_a_turn_floor_parks_only_with_a_deadband() -> None:
    """A floor turns from one side of the goal heading to the other for good: no park (the
    pose held 1 s). With ``turn_deadband`` the teacher stands still inside it, and parks."""
    env = _teacher_env()
    rules = {**LINE_TEACHER, "turn_radius": 0.018, "turn_gain": 6.0, "turn_floor": 0.5}
    floored = MapPlanner(**rules)
    parking = MapPlanner(**rules, turn_deadband=0.026)
    plan = Plan(waypoints=np.array([[-1.0, 0.0], [0.0, 0.0]]), goal_yaw=0.0)
    np.testing.assert_array_equal(
        parking._turn(plan, np.array([0.01, 0.0, np.radians(1.4)])), [0.0, 0.0]
    )
    v, omega = parking._turn(plan, np.array([0.01, 0.0, np.radians(1.6)]))
    assert v == 0.0 and np.isclose(omega, -0.5 / parking.robot.max_angular_speed)
    rng = np.random.default_rng(3)
    for k in range(5):
        _, info = env.reset(seed=10_000 + k)
        g = np.asarray(info["goal_pose"], dtype=np.float64)
        start = g + np.array([0.01, 0.0, rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 3.0)])
        stuck = run_episode(floored, env, seed=10_000 + k, options={"start": start})
        parked = run_episode(parking, env, seed=10_000 + k, options={"start": start})
        assert not stuck.success and parked.success, k
        assert np.allclose(parked.poses[:, :2], start[:2], atol=1e-6), k  # never moved
        assert np.all(parked.actions[-5:] == 0.0), k  # it stood still to be parked
    env.close()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"turn_radius": -0.01}, "turn_radius must be finite and positive, got -0.01"),
        ({"turn_gain": 0.0}, "turn_gain must be finite and positive, got 0.0"),
        ({"turn_floor": -0.5}, "turn_floor must be finite and positive, got -0.5"),
        ({"turn_floor": 0.5}, "turn_floor .* acts on turn_radius's turn in place"),
        ({"turn_deadband": 0.02}, "turn_deadband .* acts on turn_radius's turn in place"),
        ({"turn_deadband": -0.02}, "turn_deadband must be finite and positive, got -0.02"),
        ({"turn_radius": 0.01, "final_radius": 0.3}, "turn_radius .* and final_radius"),
        ({"line_cone": 1.6}, "line_cone must be below pi/2 radians, got 1.6"),
        ({"line_radius": -0.1}, "line_radius must be finite and positive, got -0.1"),
        ({"line_radius": 0.3, "final_radius": 0.3}, "line_radius .* and final_radius"),
        ({"line_speed": float("nan")}, "line_speed must be finite and positive"),
    ],
)
def test_line_errors_name_the_value(kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        MapPlanner(**kwargs)
