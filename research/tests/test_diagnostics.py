"""research/diagnostics: the image goal, the imperfect suite's cameras, the teacher through it."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from radial_ibvs_agents.experiments.suites import SUITES

DIAGNOSTICS = Path(__file__).resolve().parents[1] / "diagnostics"
sys.path.insert(0, str(DIAGNOSTICS))  # the scripts import their shared _common, as they run

from _common import imperfect_cameras, solve_one  # noqa: E402


def _script():
    path = DIAGNOSTICS / "goal_image_limit.py"
    spec = importlib.util.spec_from_file_location("goal_image_limit", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    return script


def _env(label: str) -> gym.Env:
    return gym.make("RadialIBVS/Parking-v0", **imperfect_cameras([label])[label], privileged=True)


def test_imperfect_cameras_are_the_suites_and_ideal_has_no_imperfections():
    labels = [v.label for v in SUITES["imperfect"]]
    table = imperfect_cameras([*labels, "ideal"])
    for variant in SUITES["imperfect"]:
        assert table[variant.label] == {"scenario": variant.scenario, **variant.overrides}
    assert "imperfections" not in table["ideal"]["camera"]
    assert table["ideal"]["camera"]["mirror"] == table[labels[0]]["camera"]["mirror"]
    assert list(imperfect_cameras()) == [*labels, "ideal"]
    with pytest.raises(ValueError, match="moon"):
        imperfect_cameras(["moon"])


def test_compose_places_the_solved_goal_where_it_is():
    # from a pose off the goal, the relative pose solved through an ideal camera, composed
    # with that pose, is the goal (the convention of solve_one's (t, cos, sin))
    script = _script()
    env = _env("ideal")
    rng = np.random.default_rng(0)
    for episode in range(6):
        env.reset(seed=episode)
        setup = env.unwrapped._setup
        goal = np.array(setup.episode.goal, dtype=np.float64)
        pose = goal + np.array([*rng.uniform(-0.3, 0.3, 2), rng.uniform(-1.0, 1.0)])
        points, visible = env.unwrapped.image(setup, pose, "current", None)
        relative, valid = solve_one(
            points, visible, setup.goal_points, setup.goal_visible, setup.goal_depths
        )
        assert valid
        found = script.compose(pose, relative)
        np.testing.assert_allclose(found[:2], goal[:2], atol=1e-6)
        assert abs((found[2] - goal[2] + math.pi) % (2 * math.pi) - math.pi) < 1e-6
    env.close()


def test_the_image_goal_is_the_goal_through_an_ideal_camera_and_moves_with_noise():
    script = _script()
    for label in ("ideal", "pp (2, -1) px, fy +1 %", "noise 1 px"):
        env = _env(label)
        offsets = []
        for episode in range(4):
            env.reset(seed=100_000 + episode)
            setup = env.unwrapped._setup
            goal = np.array(setup.episode.goal, dtype=np.float64)
            found = script.image_goal(env)
            assert found is not None
            offsets.append(math.hypot(*(found[:2] - goal[:2])))
            # a fixed point: the noise-free image there matches the goal image best
            points, visible = env.unwrapped.image(setup, found, "current", None)
            rest, _ = solve_one(
                points, visible, setup.goal_points, setup.goal_visible, setup.goal_depths
            )
            assert math.hypot(rest[0], rest[1]) < 1e-5 and abs(rest[3]) < 1e-5
        env.close()
        if label == "noise 1 px":  # one noisy draw of the goal image moves the goal
            assert np.median(offsets) > 1e-3
        else:  # the calibration error cancels at the goal: the same camera took both images
            assert max(offsets) < 1e-6


def test_the_image_goal_driver_refuses_a_negative_pose_noise():
    with pytest.raises(ValueError, match="pose_noise"):
        _script().ToImageGoal(pose_noise=-0.01)


def test_the_teacher_through_the_camera_is_handed_the_true_pose_by_an_ideal_one():
    # teacher_through_camera.py hands its teacher the goal's pose composed with the solved
    # relative pose: through an ideal camera, the robot's true pose
    path = DIAGNOSTICS / "teacher_through_camera.py"
    spec = importlib.util.spec_from_file_location("teacher_through_camera", path)
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    env = gym.make(
        "RadialIBVS/Parking-v0", scenario="random", physics="kinematic", obs_mode="features",
        goal_depths=True, max_landmarks=16, slot_order="random", privileged=True,
    )  # fmt: skip
    checked = 0
    for episode in range(4):
        obs, _ = env.reset(seed=episode)
        for _ in range(8):
            solved = script.solved_robot_pose(obs)
            if solved is not None:
                checked += 1
                truth = np.asarray(obs["robot_pose"], dtype=np.float64)
                np.testing.assert_allclose(solved[:2], truth[:2], atol=1e-4)
                turn = (solved[2] - truth[2] + np.pi) % (2 * np.pi) - np.pi
                assert abs(turn) < 1e-4
            obs, *_ = env.step(env.action_space.sample())
    env.close()
    assert checked >= 24


def _load(name: str):
    spec = importlib.util.spec_from_file_location(name, DIAGNOSTICS / f"{name}.py")
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    return script


def test_the_pose_errors_are_against_the_true_goal_and_end_near_it():
    failure_modes = _load("failure_modes")
    ideal = SUITES["held-out"][0]
    rows = np.array(failure_modes.pose_errors("ekf-planner", ideal, [10_000]))
    assert rows.shape[1] == 5 and (rows >= 0).all()
    # through the ideal camera the image's solve is the truth, and the episode parks
    np.testing.assert_allclose(rows[:, 3], 0.0, atol=1e-6)
    assert rows[-1, 0] < 0.02


def test_the_failures_table_names_every_end(capsys: pytest.CaptureFixture[str]):
    failure_modes = _load("failure_modes")
    variant = next(v for v in SUITES["imperfect"] if v.label == "all together")
    failure_modes.failure_ends("ibvs", variant, [10_000 + k for k in range(6)])
    out = capsys.readouterr().out
    assert out.startswith("| ibvs | parked ")
    parked = int(out.split("parked ")[1].split("/")[0])
    failed = sum(int(line.split(": ")[1].split(" |")[0]) for line in out.splitlines()[1:])
    assert parked + failed == 6
