from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from radial_ibvs_gym.physics import (
    KinematicWorld,
    RobotConfig,
    integrate_unicycle,
    limit_command,
    limited_twist,
    twist_to_wheels,
    wheels_to_twist,
)

FREE = RobotConfig(max_linear_accel=math.inf, max_angular_accel=math.inf)


@pytest.mark.parametrize("dt", [0.01, 0.05, 0.1, 0.3])
def test_a_full_circle_returns_to_the_start_whatever_dt(dt: float) -> None:
    world = KinematicWorld(FREE, (20.0, 20.0))
    world.reset([10.0, 10.0, 0.3])
    n = round(6.0 / dt)
    omega = 2 * math.pi / (dt * n)  # one turn in about 6 s
    for _ in range(n):
        result = world.step([0.4, omega], dt)
    np.testing.assert_allclose(result.pose, [10.0, 10.0, 0.3], atol=1e-9)


@given(
    v=st.floats(-1.2, 1.2),
    omega=st.floats(-5, 5),
    th=st.floats(-math.pi, math.pi),
    dt=st.floats(1e-3, 1.0),
)
def test_arc_matches_the_closed_form(v: float, omega: float, th: float, dt: float) -> None:
    end = integrate_unicycle([1.0, 2.0, th], v, omega, dt)
    # the end point lies on the circle of radius v/omega around the centre of rotation
    if abs(omega) > 1e-3:
        r = v / omega
        centre = np.array([1.0 - r * math.sin(th), 2.0 + r * math.cos(th)])
        assert np.hypot(*(end[:2] - centre)) == pytest.approx(abs(r), abs=1e-9)
    chord = np.hypot(*(end[:2] - [1.0, 2.0]))
    arc = abs(v) * dt
    assert chord <= arc + 1e-12
    assert float(np.cos(end[2] - th - omega * dt)) == pytest.approx(1.0)


def test_scale_saturation_keeps_the_curvature_and_clip_does_not() -> None:
    scale = RobotConfig(saturation="scale")
    clip = RobotConfig(saturation="clip")
    cmd = [3.0, 10.0]  # both beyond the limits
    a = limit_command(cmd, cmd, 1e9, scale)
    b = limit_command(cmd, cmd, 1e9, clip)
    assert a[1] / a[0] == pytest.approx(10.0 / 3.0)
    assert b[1] / b[0] != pytest.approx(10.0 / 3.0)
    assert abs(a[0]) <= 1.2 and abs(a[1]) <= math.radians(300) + 1e-12


def test_acceleration_limits_bound_the_change_per_step() -> None:
    robot = RobotConfig()
    out = limit_command([1.2, 0.0], [0.0, 0.0], 0.1, robot)
    assert out[0] == pytest.approx(robot.max_linear_accel * 0.1)


finite = st.floats(-50, 50, allow_subnormal=False)


@given(
    v=finite,
    w=finite,
    v0=st.floats(-1.2, 1.2),
    w0=st.floats(-5.3, 5.3),
    dt=st.sampled_from([0.01, 0.1, 0.25]),
    saturation=st.sampled_from(["scale", "clip"]),
)
def test_limits_on_floats_equal_the_array_form_bit_for_bit(v, w, v0, w0, dt, saturation) -> None:
    robot = RobotConfig(saturation=saturation)
    array = limit_command(np.array([v, w]), np.array([v0, w0]), dt, robot)
    floats = limited_twist((v, w), (v0, w0), dt, robot)
    assert all(type(x) is float for x in floats)
    assert np.array(floats).tobytes() == array.tobytes()
    assert limited_twist([v, w], (v0, w0), dt, robot) == floats  # a list reads the same


def test_the_world_reports_the_limited_velocity_as_fresh_arrays() -> None:
    world = KinematicWorld(RobotConfig(), (4.0, 4.0))
    world.reset([2.0, 2.0, 0.0])
    assert world.velocity.tolist() == [0.0, 0.0]
    result = world.step((5.0, 0.0), 0.1)  # beyond the acceleration limit
    expected = limit_command([5.0, 0.0], [0.0, 0.0], 0.1, world.robot)
    assert result.velocity.tobytes() == expected.tobytes() == world.velocity.tobytes()
    result.velocity[0] = 99.0  # the caller's copy: the world's own velocity is untouched
    assert world.velocity.tobytes() == expected.tobytes()
    world.reset([2.0, 2.0, 0.0])
    assert world.velocity.tolist() == [0.0, 0.0]


@given(left=st.floats(-20, 20), right=st.floats(-20, 20))
def test_wheel_conversions_are_inverses(left: float, right: float) -> None:
    robot = RobotConfig()
    np.testing.assert_allclose(
        twist_to_wheels(wheels_to_twist([left, right], robot), robot), [left, right], atol=1e-9
    )


def test_driving_into_a_wall_is_reported() -> None:
    world = KinematicWorld(FREE, (4.0, 4.0))
    world.reset([2.0, 2.0, 0.0])
    hits = [world.step([1.0, 0.0], 0.1).collision for _ in range(30)]
    assert not hits[0] and hits[-1]
    assert world.step([0.0, 0.0], 0.1).n_collisions == sum(hits) + 1


def test_determinism_and_pickling() -> None:
    rng = np.random.default_rng(0)
    commands = rng.uniform(-1, 1, (50, 2))
    a = KinematicWorld(RobotConfig(), (10.0, 10.0))
    a.reset([5.0, 5.0, 0.0])
    for c in commands[:25]:
        a.step(c, 0.05)
    b = pickle.loads(pickle.dumps(a))
    for c in commands[25:]:
        ra, rb = a.step(c, 0.05), b.step(c, 0.05)
        np.testing.assert_array_equal(ra.pose, rb.pose)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: RobotConfig(wheel_base=0.0), "wheel_base must be a positive number, got 0.0"),
        (lambda: RobotConfig(max_linear_speed=-1.0), "max_linear_speed"),
        (lambda: RobotConfig(max_linear_speed=math.inf), "max_linear_speed"),
        (lambda: RobotConfig(saturation="wrap"), "saturation must be"),  # type: ignore[arg-type]
        (
            lambda: RobotConfig.from_dict({"wheelbase": 0.3}),
            r"unknown robot key\(s\) \['wheelbase'\]",
        ),
        (lambda: limit_command([np.nan, 0.0], [0, 0], 0.1, FREE), "two finite numbers"),
        (lambda: limited_twist((0.0, np.inf), (0.0, 0.0), 0.1, FREE), "two finite numbers"),
        (lambda: limited_twist([1.0, 2.0, 3.0], (0.0, 0.0), 0.1, FREE), "two finite numbers"),
        (lambda: KinematicWorld(FREE, (0.0, 3.0)), "room must be"),
        (lambda: KinematicWorld(FREE, (3.0, 3.0)).reset([0.1, 1.0, 0.0]), "into a wall"),
        (lambda: KinematicWorld(FREE, (3.0, 3.0)).reset([1.0, np.inf, 0.0]), "finite"),
    ],
)
def test_bad_values_are_named(call, match) -> None:
    with pytest.raises(ValueError, match=match):
        call()
