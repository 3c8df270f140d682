"""Many robots stepped at once: the batched twins of the physics backends (no gymnasium).

A *fleet* holds ``B`` robots, each in its own room, and steps them all with one call:

- :class:`KinematicFleet`: the exact unicycle of :class:`~.kinematic.KinematicWorld`, in numpy
  over the batch;
- :class:`PymunkFleet`: the rigid bodies of :class:`~.pymunk_world.PymunkWorld`, all in
  **one** ``pymunk.Space``. Each robot's room is placed apart in the plane, so a robot only
  meets its own walls; the bodies are read and written in bulk with ``pymunk.batch``, and one
  ``space.step`` per sub-step serves every robot.

The per-robot state (pose, applied velocity, collision flag) follows the scalar worlds
exactly; the tests compare the two.

About 460 lines: the base class and its two backends, which share the batch's bookkeeping
(rooms, obstacles, velocity limits); split, each would import the other's half.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym.geometry import wrap_angle
from radial_ibvs_gym.limits import MAX_SUBSTEPS
from radial_ibvs_gym.physics.base import check_obstacles, start_pose_error
from radial_ibvs_gym.physics.diffdrive import RobotConfig

__all__ = ["Fleet", "KinematicFleet", "PymunkFleet", "limit_commands", "make_fleet"]

Array = NDArray[np.float64]


def limit_commands(command: Array, previous: Array, dt: float, config: RobotConfig) -> Array:
    """Batched :func:`~.diffdrive.limit_command`: speed limits, then acceleration limits.

    Parameters
    ----------
    command, previous
        ``(B, 2)`` requested and previously applied ``(v, omega)``, m/s and rad/s (finite).
    dt
        Control period, seconds.
    config
        The robot.

    Returns
    -------
    numpy.ndarray
        ``(B, 2)`` the velocities to apply.
    """
    v, w = command[:, 0], command[:, 1]
    v_max, w_max = config.max_linear_speed, config.max_angular_speed
    if config.saturation == "scale":
        factor = np.maximum(np.maximum(1.0, np.abs(v) / v_max), np.abs(w) / w_max)
        v, w = v / factor, w / factor
    else:
        v, w = np.clip(v, -v_max, v_max), np.clip(w, -w_max, w_max)
    dv, dw = dt * config.max_linear_accel, dt * config.max_angular_accel
    v0, w0 = previous[:, 0], previous[:, 1]
    return np.stack(
        [np.minimum(np.maximum(v, v0 - dv), v0 + dv), np.minimum(np.maximum(w, w0 - dw), w0 + dw)],
        axis=-1,
    )


class Fleet:
    """``B`` differential-drive robots, each in its own rectangular room.

    Parameters
    ----------
    robot
        The robots' parameters (the same for all).
    n
        Number of robots ``B`` (>= 1).
    obstacles
        Circular obstacles ``(x, y, radius)`` of every room, metres, unless :meth:`reset` gives
        a robot's room its own.
    """

    def __init__(
        self,
        robot: RobotConfig,
        n: int,
        obstacles: tuple[tuple[float, float, float], ...] = (),
    ) -> None:
        if int(n) < 1:
            raise ValueError(f"a fleet needs at least 1 robot, got {n!r}")
        self.robot = robot
        self.n = int(n)
        self.obstacles = check_obstacles(obstacles)
        fixed = np.array(self.obstacles, dtype=np.float64).reshape(-1, 3)
        #: each robot's obstacles ``(B, K, 3)``, padded with zero radii (which touch nothing)
        self.room_obstacles = np.broadcast_to(fixed, (self.n, *fixed.shape)).copy()
        self.rooms = np.ones((self.n, 2))
        self.velocity = np.zeros((self.n, 2))
        self._half = (0.5 * robot.length, 0.5 * robot.width)

    @property
    def poses(self) -> Array:
        """``(B, 3)`` poses ``(x, y, yaw)`` in each room's frame, metres and radians."""
        raise NotImplementedError

    def colliding(
        self, poses: Array, rooms: Array, obstacles: Array | None = None
    ) -> NDArray[np.bool_]:
        """Tell which footprints at ``poses`` ``(k, 3)`` leave rooms ``(k, 2)`` or hit obstacles.

        ``obstacles`` ``(k, K, 3)``: each footprint's obstacles (zero radii touch nothing);
        default: those of every robot, ``room_obstacles`` (then ``k = B``).
        """
        x, y, th = poses[:, 0], poses[:, 1], poses[:, 2]
        cos, sin = np.cos(th), np.sin(th)
        hl, hw = self._half
        c, s = np.abs(cos), np.abs(sin)
        ex, ey = c * hl + s * hw, s * hl + c * hw  # half extents of the rotated footprint
        out = (x - ex < 0.0) | (y - ey < 0.0) | (x + ex > rooms[:, 0]) | (y + ey > rooms[:, 1])
        obs = self.room_obstacles if obstacles is None else obstacles
        if obs.shape[1]:
            dx, dy = obs[..., 0] - x[:, None], obs[..., 1] - y[:, None]
            u = cos[:, None] * dx + sin[:, None] * dy  # the obstacle's centre in the robot frame
            v = -sin[:, None] * dx + cos[:, None] * dy
            du, dv = u - np.clip(u, -hl, hl), v - np.clip(v, -hw, hw)
            out |= (du * du + dv * dv < obs[..., 2] * obs[..., 2]).any(axis=1)
        return np.asarray(out, dtype=bool)

    def reset(
        self,
        indices: ArrayLike,
        rooms: ArrayLike,
        poses: ArrayLike,
        obstacles: Sequence[ArrayLike] | None = None,
    ) -> None:
        """Place robots ``indices`` at rest at ``poses`` ``(k, 3)`` in new rooms ``(k, 2)``.

        ``obstacles``: per robot, its room's circular obstacles ``(K_i, 3)`` ``(x, y,
        radius)``, metres; default: the fleet's own (``obstacles`` of the constructor).

        Raises
        ------
        ValueError
            For a non-finite pose or room, a bad obstacle, or a robot overlapping a wall or an
            obstacle.
        """
        idx = np.asarray(indices, dtype=np.intp).reshape(-1)
        rooms_k = np.asarray(rooms, dtype=np.float64).reshape(-1, 2)
        poses_k = np.asarray(poses, dtype=np.float64).reshape(-1, 3)
        if not (np.isfinite(rooms_k).all() and (rooms_k > 0).all()):
            raise ValueError(f"rooms must be positive (width, depth), got {rooms_k.tolist()}")
        if not np.isfinite(poses_k).all():
            raise ValueError(f"poses must be finite (x, y, yaw), got {poses_k.tolist()}")
        if obstacles is not None:
            if len(obstacles) != len(idx):
                raise ValueError(f"got {len(obstacles)} obstacle lists for {len(idx)} robots")
            self._set_obstacles(idx, [np.asarray(o, dtype=np.float64) for o in obstacles])
        bad = self.colliding(poses_k, rooms_k, self.room_obstacles[idx])
        if bad.any():  # the same check, and message, in every backend
            raise ValueError(start_pose_error(poses_k[int(np.argmax(bad))]))
        self.rooms[idx] = rooms_k
        self.velocity[idx] = 0.0
        self._place(idx, rooms_k, poses_k)

    def _set_obstacles(self, idx: NDArray[np.intp], obstacles: list[Array]) -> None:
        lists = [_checked(o) for o in obstacles]
        widest = max([len(o) for o in lists] + [self.room_obstacles.shape[1]])
        if widest > self.room_obstacles.shape[1]:
            pad = np.zeros((self.n, widest - self.room_obstacles.shape[1], 3))
            self.room_obstacles = np.concatenate([self.room_obstacles, pad], axis=1)
        for i, o in zip(idx.tolist(), lists, strict=True):
            self.room_obstacles[i] = 0.0
            self.room_obstacles[i, : len(o)] = o

    def obstacles_of(self, i: int) -> Array:
        """``(K_i, 3)`` the obstacles of robot ``i``'s room."""
        obstacles = self.room_obstacles[i]
        return obstacles[obstacles[:, 2] > 0.0].copy()  # padding has zero radius

    def _place(self, idx: NDArray[np.intp], rooms: Array, poses: Array) -> None:
        raise NotImplementedError

    def step(self, command: Array, dt: float) -> tuple[Array, NDArray[np.bool_]]:
        """Apply ``(v, omega)`` commands ``(B, 2)`` for ``dt`` seconds (after the limits).

        Returns
        -------
        poses
            ``(B, 3)`` after the step.
        collision
            ``(B,)`` whether each robot touched a wall or an obstacle during the step.
        """
        raise NotImplementedError


def _checked(obstacles: Array) -> Array:
    """Validate one room's obstacles ``(K, 3)`` (:func:`~.base.check_obstacles`)."""
    rows = [(float(x), float(y), float(r)) for x, y, r in np.reshape(obstacles, (-1, 3))]
    return np.array(check_obstacles(tuple(rows)), dtype=np.float64).reshape(-1, 3)


class KinematicFleet(Fleet):
    """The exact unicycle, batched; collisions are only detected (nothing stops a robot)."""

    def __init__(
        self, robot: RobotConfig, n: int, obstacles: tuple[tuple[float, float, float], ...] = ()
    ) -> None:
        super().__init__(robot, n, obstacles)
        self._poses = np.zeros((self.n, 3))

    @property
    def poses(self) -> Array:  # noqa: D102
        return self._poses.copy()

    def _place(self, idx: NDArray[np.intp], rooms: Array, poses: Array) -> None:
        self._poses[idx] = np.stack([poses[:, 0], poses[:, 1], wrap_angle(poses[:, 2])], axis=-1)

    def step(self, command: Array, dt: float) -> tuple[Array, NDArray[np.bool_]]:  # noqa: D102
        vel = limit_commands(command, self.velocity, dt, self.robot)
        self.velocity = vel
        v, omega = vel[:, 0], vel[:, 1]
        x, y, th = self._poses[:, 0], self._poses[:, 1], self._poses[:, 2]
        half = 0.5 * omega * dt
        # the chord of the arc (see integrate_unicycle): no cancellation for small omega
        small = np.abs(half) <= 1e-12
        sinc = np.where(small, 1.0 - half * half / 6.0, np.sin(half) / np.where(small, 1.0, half))
        chord = v * dt * sinc
        mid = th + half
        poses = np.empty_like(self._poses)
        poses[:, 0] = x + chord * np.cos(mid)
        poses[:, 1] = y + chord * np.sin(mid)
        poses[:, 2] = wrap_angle(th + omega * dt)
        self._poses = poses
        return poses.copy(), self.colliding(poses, self.rooms)


def _touching(arbiter: Any, space: Any, data: dict[str, Any]) -> None:
    """Collision callback: flag the robot's env (its shape knows its index)."""
    data["touching"][data["index"][arbiter.shapes[0]]] = True


class PymunkFleet(Fleet):
    """``B`` pymunk robots in one ``pymunk.Space``, rooms placed apart on a grid.

    Each robot is built as :class:`~.pymunk_world.PymunkWorld` builds its one (a kinematic
    control body dragging the robot body through a pivot and a gear joint). Room ``i`` has its
    origin at ``offsets[i]``; its walls and obstacles are static shapes rebuilt at each reset of
    the robot (rooms may change between episodes).

    Parameters
    ----------
    robot, n, obstacles
        As :class:`Fleet`.
    physics_dt
        Physics sub-step, seconds.
    max_room
        ``(width, depth)`` of the largest room any episode may draw, metres (sets the spacing).
    """

    def __init__(
        self,
        robot: RobotConfig,
        n: int,
        obstacles: tuple[tuple[float, float, float], ...] = (),
        physics_dt: float = 0.01,
        max_room: tuple[float, float] = (20.0, 20.0),
    ) -> None:
        import pymunk
        import pymunk.batch

        from radial_ibvs_gym.physics.pymunk_world import ROBOT_TYPE, WALL_TYPE

        super().__init__(robot, n, obstacles)
        if not (math.isfinite(physics_dt) and physics_dt > 0):
            raise ValueError(f"physics_dt must be positive, got {physics_dt!r}")
        self.physics_dt = float(physics_dt)
        self._pymunk, self._batch, self._wall_type = pymunk, pymunk.batch, WALL_TYPE
        columns = math.ceil(math.sqrt(self.n))
        spacing = np.array(max_room, dtype=np.float64) + 5.0  # metres between rooms
        k = np.arange(self.n)
        self.offsets = np.stack([k % columns, k // columns], axis=-1) * spacing
        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        self.space = space
        self._bodies, self._shapes, self._controls = [], [], []
        index: dict[Any, int] = {}
        for i in range(self.n):
            body = pymunk.Body(
                robot.mass, pymunk.moment_for_box(robot.mass, (robot.length, robot.width))
            )
            shape = pymunk.Poly.create_box(body, (robot.length, robot.width))
            shape.collision_type = ROBOT_TYPE
            shape.friction = 0.5
            control = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            body.position = control.position = tuple(self.offsets[i] + 1.0)
            pivot = pymunk.PivotJoint(control, body, (0.0, 0.0), (0.0, 0.0))
            pivot.max_bias = 0.0
            pivot.max_force = 40.0 * robot.mass * 9.81
            gear = pymunk.GearJoint(control, body, 0.0, 1.0)
            gear.error_bias = 0.0
            gear.max_bias = 2.0 * robot.max_angular_speed
            gear.max_force = 40.0 * robot.mass * 9.81
            space.add(body, shape, control, pivot, gear)
            self._bodies.append(body)
            self._shapes.append(shape)
            self._controls.append(control)
            index[shape] = i
        self._walls: list[list[Any]] = [[] for _ in range(self.n)]
        self._contact: dict[str, Any] = {"touching": np.zeros(self.n, dtype=bool), "index": index}
        space.on_collision(ROBOT_TYPE, WALL_TYPE, pre_solve=_touching, data=self._contact)
        # pymunk.batch walks the space's bodies in the order they were added: robot i is row
        # 2 i, its control body row 2 i + 1 (checked here, as the order is pymunk's internals)
        # two buffers: one pymunk fills (its array grows as needed), one that only points at
        # our numpy array (set_float_buf); filling the latter would realloc numpy's memory
        self._buffer, self._writer = pymunk.batch.Buffer(), pymunk.batch.Buffer()
        self._out: Array | None = None  # the velocities written each sub-step (writer's array)
        self._poses_cache: Array | None = None
        pymunk.batch.get_space_bodies(space, pymunk.batch.BodyFields.BODY_ID, self._buffer)
        ids = np.frombuffer(self._buffer.int_buf(), dtype=np.uintp)
        expected = [b.id for pair in zip(self._bodies, self._controls, strict=True) for b in pair]
        if ids.tolist() != expected:
            raise RuntimeError("pymunk.batch does not list the bodies in the order they were added")
        self._read = pymunk.batch.BodyFields.ANGLE | pymunk.batch.BodyFields.VELOCITY
        self._read |= pymunk.batch.BodyFields.ANGULAR_VELOCITY
        self._write = pymunk.batch.BodyFields.VELOCITY | pymunk.batch.BodyFields.ANGULAR_VELOCITY

    #: what ``pickle`` and ``copy.deepcopy`` leave out (modules, pymunk.batch's C buffers),
    #: rebuilt by ``__setstate__``; the space, its bodies and handlers pickle as pymunk does
    _UNPICKLED = ("_pymunk", "_batch", "_buffer", "_writer", "_out", "_read", "_write")

    def __getstate__(self) -> dict[str, Any]:
        """Return the fleet's state without modules and C buffers (so the vector env pickles)."""
        return {k: v for k, v in self.__dict__.items() if k not in self._UNPICKLED}

    def __setstate__(self, state: dict[str, Any]) -> None:
        """Restore a pickled fleet: re-import pymunk and make new buffers."""
        import pymunk
        import pymunk.batch

        self.__dict__.update(state)
        self._pymunk, self._batch = pymunk, pymunk.batch
        self._buffer, self._writer = pymunk.batch.Buffer(), pymunk.batch.Buffer()
        self._out = None
        fields = pymunk.batch.BodyFields
        self._read = fields.ANGLE | fields.VELOCITY | fields.ANGULAR_VELOCITY
        self._write = fields.VELOCITY | fields.ANGULAR_VELOCITY

    @property
    def poses(self) -> Array:  # noqa: D102
        if self._poses_cache is None:  # read from pymunk once per step or reset
            self._buffer.clear()
            fields = self._batch.BodyFields.POSITION | self._batch.BodyFields.ANGLE
            self._batch.get_space_bodies(self.space, fields, self._buffer)
            data = np.frombuffer(self._buffer.float_buf(), dtype=np.float64).reshape(-1, 3)
            robot = data[0 : 2 * self.n : 2]
            poses = np.empty((self.n, 3))
            poses[:, :2] = robot[:, :2] - self.offsets
            poses[:, 2] = wrap_angle(robot[:, 2])
            self._poses_cache = poses
        return self._poses_cache.copy()

    def _build_walls(self, i: int, room: Array) -> None:
        pymunk = self._pymunk
        from radial_ibvs_gym.physics.pymunk_world import WALL_RADIUS

        if self._walls[i]:
            self.space.remove(*self._walls[i])
        ox, oy = self.offsets[i]
        w, d = float(room[0]), float(room[1])
        r = WALL_RADIUS
        corners = [
            (ox - r, oy - r),
            (ox + w + r, oy - r),
            (ox + w + r, oy + d + r),
            (ox - r, oy + d + r),
        ]
        shapes = []
        for a, b in zip(corners, corners[1:] + corners[:1], strict=True):
            shapes.append(pymunk.Segment(self.space.static_body, a, b, r))
        for cx, cy, radius in self.obstacles_of(i).tolist():
            shapes.append(pymunk.Circle(self.space.static_body, radius, (ox + cx, oy + cy)))
        for shape in shapes:
            shape.collision_type = self._wall_type
            shape.friction = 0.5
        self.space.add(*shapes)
        self._walls[i] = shapes

    def _place(self, idx: NDArray[np.intp], rooms: Array, poses: Array) -> None:
        self._poses_cache = None
        for k, i in enumerate(idx.tolist()):
            self._build_walls(i, rooms[k])
            position = (
                float(self.offsets[i, 0] + poses[k, 0]),
                float(self.offsets[i, 1] + poses[k, 1]),
            )
            for body in (self._bodies[i], self._controls[i]):
                body.position = position
                body.angle = float(poses[k, 2])
                body.velocity = (0.0, 0.0)
                body.angular_velocity = 0.0
            self.space.reindex_shapes_for_body(self._bodies[i])
            if self.space.shape_query(self._shapes[i]):  # the footprint as pymunk sees it
                raise ValueError(start_pose_error(poses[k]))

    def step(self, command: Array, dt: float) -> tuple[Array, NDArray[np.bool_]]:  # noqa: D102
        if not dt / self.physics_dt <= MAX_SUBSTEPS:  # NaN too
            raise ValueError(
                f"dt={dt!r} s is more than MAX_SUBSTEPS = {MAX_SUBSTEPS} sub-steps of "
                f"physics_dt={self.physics_dt!r} s"
            )
        steps = round(dt / self.physics_dt)
        if steps < 1 or abs(steps * self.physics_dt - dt) > 1e-9:
            raise ValueError(
                f"dt={dt!r} s must be a positive multiple of physics_dt={self.physics_dt!r} s"
            )
        vel = limit_commands(command, self.velocity, dt, self.robot)
        self.velocity = vel
        v, omega = vel[:, 0], vel[:, 1]
        half = 0.5 * omega * self.physics_dt
        touching = self._contact["touching"]
        touching[:] = False
        batch, buffer, writer = self._batch, self._buffer, self._writer
        cos, sin = np.empty(self.n), np.empty(self.n)
        space, h = self.space, self.physics_dt
        controls = slice(1, 2 * self.n, 2)  # rows of the control bodies (robots: even rows)
        robots = slice(0, 2 * self.n, 2)
        out = self._out
        for _ in range(steps):
            buffer.clear()
            batch.get_space_bodies(space, self._read, buffer)
            # per body: angle, velocity x, y, angular velocity; the robots and their control
            # bodies first (in the order added), then the static bodies
            data = np.frombuffer(buffer.float_buf(), dtype=np.float64).reshape(-1, 4)
            if out is None or len(out) != len(data):  # the static body joined the space
                out = self._out = np.empty((len(data), 3))
                writer.set_float_buf(out.reshape(-1))  # writer points at `out`, never grows it
            out[:] = data[:, 1:]  # every other body's velocity is written back unchanged
            heading = data[robots, 0] + half  # the robots' mid-step headings
            np.cos(heading, out=cos)
            np.sin(heading, out=sin)
            out[controls, 0] = v * cos
            out[controls, 1] = v * sin
            out[controls, 2] = omega
            batch.set_space_bodies(space, self._write, writer)
            space.step(h)
        self._poses_cache = None
        return self.poses, touching.copy()


def make_fleet(backend: str, robot: RobotConfig, n: int, **kwargs: Any) -> Fleet:
    """Build a fleet of the named backend (``"pymunk"`` or ``"kinematic"``).

    Raises
    ------
    ValueError
        For an unknown backend (the message lists the valid ones).
    """
    if backend == "pymunk":
        return PymunkFleet(robot, n, **kwargs)
    if backend == "kinematic":
        kwargs.pop("physics_dt", None)
        kwargs.pop("max_room", None)
        return KinematicFleet(robot, n, **kwargs)
    raise ValueError(f"unknown physics {backend!r}; valid: ['pymunk', 'kinematic']")
