from __future__ import annotations

import math
import pickle

import numpy as np
import pytest

from radial_ibvs_gym.physics import KinematicWorld, PymunkWorld, RobotConfig, make_world

FREE = RobotConfig(max_linear_accel=math.inf, max_angular_accel=math.inf)


@pytest.mark.parametrize("robot", [FREE, RobotConfig()], ids=["no-accel-limit", "default"])
@pytest.mark.parametrize("command", [(0.5, 0.0), (0.4, 0.8), (0.4, -0.8), (0.0, 1.5), (-0.3, 0.4)])
def test_pymunk_agrees_with_the_exact_unicycle(robot: RobotConfig, command) -> None:
    """Over 2 s the pymunk body lags the exact arc by one physics sub-step: 2.5 mm at 0.5 m/s."""
    a = PymunkWorld(robot, (20.0, 20.0), physics_dt=0.005)
    b = KinematicWorld(robot, (20.0, 20.0))
    a.reset([10.0, 10.0, 0.3])
    b.reset([10.0, 10.0, 0.3])
    for _ in range(40):
        ra, rb = a.step(command, 0.05), b.step(command, 0.05)
    assert np.hypot(*(ra.pose[:2] - rb.pose[:2])) <= 5e-3
    assert abs(math.remainder(ra.pose[2] - rb.pose[2], 2 * math.pi)) <= math.radians(0.5)
    np.testing.assert_array_equal(ra.velocity, rb.velocity)  # the same limits in both


def test_walls_stop_the_robot_and_report_the_collision() -> None:
    world = PymunkWorld(FREE, (4.0, 4.0))
    world.reset([2.0, 2.0, 0.0])
    results = [world.step([1.0, 0.0], 0.1) for _ in range(30)]
    assert not results[0].collision and results[-1].collision
    front = results[-1].pose[0] + FREE.length / 2
    assert front == pytest.approx(4.0, abs=0.01)  # at the wall, not through it
    assert results[-1].n_collisions == sum(r.collision for r in results)


def test_pymunk_world_is_deterministic_and_pickles() -> None:
    rng = np.random.default_rng(0)
    commands = rng.uniform(-1, 1, (40, 2))

    def run(world: PymunkWorld, cmds: np.ndarray) -> list[np.ndarray]:
        return [world.step(c, 0.05).pose for c in cmds]

    a, b = PymunkWorld(RobotConfig(), (10.0, 10.0)), PymunkWorld(RobotConfig(), (10.0, 10.0))
    a.reset([5.0, 5.0, 0.0])
    b.reset([5.0, 5.0, 0.0])
    for x, y in zip(run(a, commands[:20]), run(b, commands[:20]), strict=True):
        np.testing.assert_array_equal(x, y)
    clone = pickle.loads(pickle.dumps(a))
    for x, y in zip(run(a, commands[20:]), run(clone, commands[20:]), strict=True):
        np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: PymunkWorld(FREE, (4.0, 4.0), physics_dt=0.0), "physics_dt must be positive"),
        (lambda: PymunkWorld(FREE, (-1.0, 4.0)), "room must be"),
        (lambda: PymunkWorld(FREE, (4.0, 4.0)).reset([0.1, 2.0, 0.0]), "into a wall"),
        (lambda: make_world("bullet", FREE, (4.0, 4.0)), r"valid: \['pymunk', 'kinematic'\]"),
    ],
)
def test_bad_values_are_named(call, match) -> None:
    with pytest.raises(ValueError, match=match):
        call()


def test_control_period_must_be_a_multiple_of_the_physics_step() -> None:
    world = PymunkWorld(FREE, (4.0, 4.0), physics_dt=0.01)
    world.reset([2.0, 2.0, 0.0])
    with pytest.raises(ValueError, match="multiple of physics_dt"):
        world.step([0.1, 0.0], 0.025)
    # the checked period is remembered; another one (after a valid one) is checked again
    world.step([0.1, 0.0], 0.1)
    for dt in (0.025, float("nan"), 1e6):
        with pytest.raises(ValueError, match="physics_dt"):
            world.step([0.1, 0.0], dt)
    assert world.time == pytest.approx(0.1)


@pytest.mark.parametrize("backend", ["pymunk", "kinematic"])
def test_obstacles_are_reported_and_pymunk_stops_at_them(backend: str) -> None:
    world = make_world(backend, FREE, (10.0, 10.0), obstacles=((6.0, 5.0, 0.5),))
    world.reset([3.0, 5.0, 0.0])
    results = [world.step([1.0, 0.0], 0.1) for _ in range(40)]
    assert any(r.collision for r in results)
    if backend == "pymunk":  # stopped by the post: front edge at its surface
        assert results[-1].pose[0] + FREE.length / 2 == pytest.approx(5.5, abs=0.02)
    with pytest.raises(ValueError, match="obstacle"):
        world.reset([6.0, 5.2, 0.0])
    with pytest.raises(ValueError, match=r"obstacles\[0\] must be \(x, y, radius > 0\)"):
        make_world(backend, FREE, (10.0, 10.0), obstacles=((1.0, 1.0, -0.5),))
