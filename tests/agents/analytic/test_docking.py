"""The line-following docking law (the teacher's last metres): frame, cone, convergence."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from radial_ibvs_agents.analytic.docking import (
    goal_frame,
    in_docking_cone,
    line_docking,
    turn_in_place,
)
from radial_ibvs_gym.physics import RobotConfig

ROBOT = RobotConfig()
LIMITS = {
    "gain": 2.0,
    "lateral_gain": 900.0,
    "max_speed": 0.15,  # the planner's line_speed: 2 * sqrt(900) * 0.15 = 4.5/s < 1/dt
    "max_accel": ROBOT.max_linear_accel,
    "max_turn": ROBOT.max_angular_speed,
    "max_turn_accel": ROBOT.max_angular_accel,
}
coord = st.floats(-5.0, 5.0)
angle = st.floats(-math.pi, math.pi)


@settings(max_examples=100, deadline=None)
@given(coord, coord, angle, coord, coord, angle, angle, coord, coord)
def test_the_goal_frame_ignores_where_the_world_frame_is(x, y, yaw, gx, gy, gyaw, turn, tx, ty):
    """Rotating and shifting the world moves robot and goal together: the same goal frame."""
    c, s = math.cos(turn), math.sin(turn)

    def move(p: tuple[float, float, float]) -> np.ndarray:
        return np.array([c * p[0] - s * p[1] + tx, s * p[0] + c * p[1] + ty, p[2] + turn])

    before = goal_frame(np.array([x, y, yaw]), np.array([gx, gy, gyaw]))
    after = goal_frame(move((x, y, yaw)), move((gx, gy, gyaw)))
    assert np.allclose(before[:2], after[:2], atol=1e-9)
    assert abs((before[2] - after[2] + math.pi) % (2 * math.pi) - math.pi) < 1e-9
    assert abs(math.hypot(*before[:2]) - math.hypot(x - gx, y - gy)) < 1e-9


def test_the_goal_frame_axes() -> None:
    """x along the goal heading, y to its left, phi the heading minus the goal's."""
    goal = np.array([1.0, 2.0, math.pi / 2])  # facing +y
    x_g, y_g, phi = goal_frame(np.array([1.0, 1.5, math.pi / 2 + 0.1]), goal)
    assert np.allclose((x_g, y_g, phi), (-0.5, 0.0, 0.1))
    x_g, y_g, _ = goal_frame(np.array([0.8, 2.0, 0.0]), goal)  # left of a goal facing +y
    assert np.allclose((x_g, y_g), (0.0, 0.2))


def test_the_cone_lies_behind_the_goal_and_the_band_on_its_line() -> None:
    assert in_docking_cone(-0.2, 0.1, cone=0.5, band=0.015)  # tan(0.5) * 0.2 = 0.109
    assert not in_docking_cone(-0.2, 0.12, cone=0.5, band=0.015)
    assert in_docking_cone(0.03, 0.01, cone=0.5, band=0.015)  # past the goal, in the band
    assert not in_docking_cone(0.03, 0.02, cone=0.5, band=0.015)


@settings(max_examples=200, deadline=None)
@given(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), st.floats(-3.0, 3.0))
def test_the_command_is_within_the_limits_and_mirrors_with_the_pose(x_g, y_g, phi) -> None:
    """Within the robot's limits; reflecting the pose across the goal line mirrors the turn."""
    v, omega = line_docking(x_g, y_g, phi, **LIMITS)
    assert abs(v) <= 0.15 + 1e-12
    assert abs(omega) <= ROBOT.max_angular_speed + 1e-12
    v_m, omega_m = line_docking(x_g, -y_g, -phi, **LIMITS)
    assert v_m == v and abs(omega_m + omega) < 1e-12


def test_at_the_goal_it_stands_still() -> None:
    assert line_docking(0.0, 0.0, 0.0, **LIMITS) == (0.0, 0.0)


def _dock(x_g: float, y_g: float, phi: float, steps: int = 300, dt: float = 0.1) -> np.ndarray:
    """Integrate the unicycle under the law (goal frame), speeds within the limits."""
    pose = np.array([x_g, y_g, phi])
    for _ in range(steps):
        v, omega = line_docking(*pose, **LIMITS)
        pose = pose + dt * np.array([v * math.cos(pose[2]), v * math.sin(pose[2]), omega])
    return pose


@settings(max_examples=60, deadline=None)
@given(st.floats(0.03, 0.3), st.floats(-0.28, 0.28), st.floats(-0.5, 0.5))
def test_from_the_cone_it_docks_within_the_tolerance(distance, bearing, phi) -> None:
    """From behind the goal within 0.28 rad of its line (lateral gain 900), it parks (2 cm,
    2 deg)."""
    end = _dock(-distance * math.cos(bearing), distance * math.sin(bearing), phi)
    assert math.hypot(end[0], end[1]) < 0.02, end
    assert abs(end[2]) < math.radians(2.0), end


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 0.05), st.floats(-0.012, 0.012), st.floats(-0.5, 0.5))
def test_past_the_goal_in_the_band_it_backs_up(x_g, y_g, phi) -> None:
    """Past the goal within the band, it backs up onto it (the distance shrinks to <2 cm)."""
    end = _dock(x_g, y_g, phi)
    assert math.hypot(end[0], end[1]) < 0.02, end
    assert abs(end[2]) < math.radians(2.0), end


TURN = {"max_turn": ROBOT.max_angular_speed, "max_turn_accel": ROBOT.max_angular_accel}


@settings(max_examples=200, deadline=None)
@given(angle, st.floats(0.5, 9.5))
def test_the_turn_in_place_reduces_the_heading_error_every_step(phi, gain) -> None:
    """Against the heading error, within the limits, odd in it, and with a gain below
    1 / dt each 0.1 s step shrinks the error without overshoot to under 2 deg."""
    omega = turn_in_place(phi, gain=gain, **TURN)
    assert abs(omega) <= ROBOT.max_angular_speed + 1e-12
    assert omega * phi <= 0.0
    assert turn_in_place(-phi, gain=gain, **TURN) == -omega
    heading = phi
    for _ in range(200):
        after = heading + 0.1 * turn_in_place(heading, gain=gain, **TURN)
        assert abs(after) <= abs(heading) and after * heading >= 0.0
        heading = after
    assert abs(heading) < math.radians(2.0)


def test_the_turn_in_place_is_proportional_near_zero() -> None:
    """6/s of gain: 2 deg gives 0.21 rad/s (0.04 of the turn range), 6 deg three times that."""
    two = turn_in_place(math.radians(2.0), gain=6.0, **TURN)
    assert math.isclose(two, -6.0 * math.radians(2.0))
    assert math.isclose(turn_in_place(math.radians(6.0), gain=6.0, **TURN), 3.0 * two)
    assert turn_in_place(0.0, gain=6.0, **TURN) == 0.0


@settings(max_examples=200, deadline=None)
@given(angle.filter(lambda a: a != 0.0), st.floats(0.5, 9.5), st.floats(0.05, 0.69))
@example(5e-324, 1.0, 0.5)
def test_the_turn_floor_keeps_the_last_degrees_turn_and_parks(phi, gain, floor) -> None:
    """With a floor, the turn is at least ``floor`` (or the proportional turn, if larger)
    against the error, odd in it; each 0.1 s step shrinks the error or overshoots by at most
    ``floor * 0.1`` radians, and the heading gets under 2 deg (floor * 0.1 < 4 deg: a step
    lands within the tolerance rather than across it)."""
    omega = turn_in_place(phi, gain=gain, floor=floor, **TURN)
    plain = turn_in_place(phi, gain=gain, **TURN)
    # against the error by sign, not by omega * phi < 0, which underflows to -0.0 for a
    # subnormal phi (hypothesis found phi = 5e-324)
    assert omega != 0.0 and math.copysign(1.0, omega) == -math.copysign(1.0, phi)
    assert math.isclose(abs(omega), max(floor, abs(plain)))
    assert turn_in_place(-phi, gain=gain, floor=floor, **TURN) == -omega
    heading, steps = phi, 0
    while abs(heading) >= math.radians(2.0):
        after = heading + 0.1 * turn_in_place(heading, gain=gain, floor=floor, **TURN)
        assert abs(after) < abs(heading) or abs(after) <= 0.1 * floor + 1e-12
        heading, steps = after, steps + 1
        assert steps < 200
    assert turn_in_place(0.0, gain=gain, floor=floor, **TURN) == 0.0


def test_the_turn_floor_is_capped_by_the_turn_limit() -> None:
    """A floor above the robot's angular speed limit turns at the limit."""
    omega = turn_in_place(math.radians(1.0), gain=6.0, floor=100.0, **TURN)
    assert omega == -ROBOT.max_angular_speed
