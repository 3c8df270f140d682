"""The ``pymunk`` backend: a rigid robot body in a walled room, with contacts.

The top-down pattern of pymunk's ``examples/tank.py``: a kinematic control body drags the
robot's dynamic body through a ``PivotJoint`` (``max_bias = 0``: velocity only; ``max_force``
acts as the floor's friction, so there is no lateral slip) and a ``GearJoint`` (the turn rate).
Every physics sub-step sets the control body's velocity to the commanded ``(v, omega)`` along
the robot's heading. Collisions with the walls and obstacles are reported through
``space.on_collision``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pymunk
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.geometry import wrap_angle_scalar
from radial_ibvs_gym.limits import MAX_SUBSTEPS
from radial_ibvs_gym.physics.base import StepResult, World, start_pose_error
from radial_ibvs_gym.physics.diffdrive import RobotConfig, limited_twist

try:  # pymunk's C functions (what its Python wrappers call); see PymunkWorld.step
    from pymunk._chipmunk_cffi import lib as _cp
except ImportError:  # pragma: no cover - another pymunk layout: the public API only
    _cp = None

__all__ = ["PymunkWorld"]

ROBOT_TYPE, WALL_TYPE = 1, 2
WALL_RADIUS = 0.05  #: metres


def _touching(arbiter: pymunk.Arbiter, space: pymunk.Space, data: dict[str, Any]) -> None:
    """Collision callback (module level, so the space pickles): flag the contact."""
    data["touching"] = True


class PymunkWorld(World):
    """A differential-drive robot in a rectangular room, simulated by pymunk.

    Parameters
    ----------
    robot
        The robot's parameters (size, mass, limits).
    room
        ``(width, depth)`` of the room ``[0, width] x [0, depth]``, metres.
    obstacles
        Circular obstacles ``(x, y, radius)``, metres (static, like the walls).
    physics_dt
        Physics sub-step, seconds; every control period must be a multiple of it.
    """

    def __init__(
        self,
        robot: RobotConfig,
        room: tuple[float, float],
        obstacles: tuple[tuple[float, float, float], ...] = (),
        physics_dt: float = 1.0 / 200.0,
    ) -> None:
        super().__init__(robot, room, obstacles)
        if not (math.isfinite(physics_dt) and physics_dt > 0):
            raise ValueError(f"physics_dt must be positive, got {physics_dt!r}")
        w, d = self.room
        self.physics_dt = float(physics_dt)
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        r = WALL_RADIUS
        corners = [(-r, -r), (w + r, -r), (w + r, d + r), (-r, d + r)]
        for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
            wall = pymunk.Segment(space.static_body, a, b, r)
            wall.collision_type = WALL_TYPE
            wall.friction = 0.5
            space.add(wall)
        for ox, oy, radius in self.obstacles:
            post = pymunk.Circle(space.static_body, radius, (ox, oy))
            post.collision_type = WALL_TYPE
            post.friction = 0.5
            space.add(post)
        body = pymunk.Body(
            robot.mass, pymunk.moment_for_box(robot.mass, (robot.length, robot.width))
        )
        shape = pymunk.Poly.create_box(body, (robot.length, robot.width))
        shape.collision_type = ROBOT_TYPE
        shape.friction = 0.5
        control = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        pivot = pymunk.PivotJoint(control, body, (0.0, 0.0), (0.0, 0.0))
        pivot.max_bias = 0.0  # no position correction: the joint transmits velocity only
        pivot.max_force = 40.0 * robot.mass * 9.81  # floor friction (generous: no wheel slip)
        gear = pymunk.GearJoint(control, body, 0.0, 1.0)
        gear.error_bias = 0.0  # correct the angle error fully each step
        gear.max_bias = 2.0 * robot.max_angular_speed
        gear.max_force = 40.0 * robot.mass * 9.81
        space.add(body, shape, control, pivot, gear)
        self._contact: dict[str, Any] = {"touching": False}
        space.on_collision(ROBOT_TYPE, WALL_TYPE, pre_solve=_touching, data=self._contact)
        self.space, self._body, self._shape, self._control = space, body, shape, control
        self._period = (math.nan, 0)  # the last control period (s) and its checked sub-steps

    def _check_substeps(self, dt: float) -> int:
        """Return the sub-steps in a control period of ``dt`` seconds, checking it."""
        if not dt / self.physics_dt <= MAX_SUBSTEPS:  # NaN too
            raise ValueError(
                f"dt={dt!r} s is more than MAX_SUBSTEPS = {MAX_SUBSTEPS} sub-steps of "
                f"physics_dt={self.physics_dt!r} s"
            )
        n = round(dt / self.physics_dt)
        if n < 1 or abs(n * self.physics_dt - dt) > 1e-9:
            raise ValueError(
                f"dt={dt!r} s must be a positive multiple of physics_dt={self.physics_dt!r} s"
            )
        return n

    @property
    def pose(self) -> NDArray[np.float64]:  # noqa: D102
        if _cp is None:  # pragma: no cover - a pymunk without its cffi module
            p = self._body.position
            return np.array([p.x, p.y, wrap_angle_scalar(self._body.angle)])
        body = self._body._body
        p = _cp.cpBodyGetPosition(body)
        return np.array([p.x, p.y, wrap_angle_scalar(_cp.cpBodyGetAngle(body))])

    def reset(self, pose: ArrayLike) -> None:  # noqa: D102
        p = self._check_start(pose)
        for body in (self._body, self._control):
            body.position = (float(p[0]), float(p[1]))
            body.angle = float(p[2])
            body.velocity = (0.0, 0.0)
            body.angular_velocity = 0.0
        self.space.reindex_shapes_for_body(self._body)
        if self.space.shape_query(self._shape):  # the footprint as pymunk sees it
            raise ValueError(start_pose_error(p))
        self._restart()

    def step(self, command: ArrayLike, dt: float) -> StepResult:
        """Apply ``(v, omega)`` (after the robot's limits) for ``dt`` seconds of sub-steps.

        Raises
        ------
        ValueError
            If ``dt`` is not a positive multiple of ``physics_dt``, or the command is not finite.
        """
        if dt != self._period[0]:  # NaN too
            self._period = (dt, self._check_substeps(dt))
        n = self._period[1]
        v, omega = twist = limited_twist(command, self._twist, dt, self.robot)
        self._contact["touching"] = False
        h = self.physics_dt
        half = 0.5 * omega * h
        body, control, space = self._body, self._control, self.space
        if _cp is None:  # pragma: no cover - a pymunk without its cffi module
            control.angular_velocity = omega
            for _ in range(n):
                heading = body.angle + half  # mid-step heading: second-order accurate
                control.velocity = (v * math.cos(heading), v * math.sin(heading))
                space.step(h)
        else:  # the same calls, without the Python wrappers (they cost more than the physics)
            body_c, control_c, space_c = body._body, control._body, space._space
            get_angle, set_velocity = _cp.cpBodyGetAngle, _cp.cpBodySetVelocity
            step = _cp.cpSpaceStep
            cos, sin = math.cos, math.sin
            _cp.cpBodySetAngularVelocity(control_c, omega)
            first = 0
            if space._bodies_to_check:  # pymunk checks the bodies added since its last step
                heading = get_angle(body_c) + half
                set_velocity(control_c, (v * cos(heading), v * sin(heading)))
                space.step(h)  # the public step, once in a world's life
                first = 1
            # the rest of pymunk's step handles changes made to the space during a step
            # (queued additions, removals, post-step callbacks): this world makes none
            for _ in range(first, n):
                heading = get_angle(body_c) + half
                set_velocity(control_c, (v * cos(heading), v * sin(heading)))
                step(space_c, h)
        return self._finish_step(twist, dt, bool(self._contact["touching"]))
