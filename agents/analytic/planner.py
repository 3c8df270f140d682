"""``planner``: a privileged policy with a map, the physical limit of the parking task.

It sees what no image-based policy may: the true poses and the map (``gym.make(...,
privileged=True, privileged_map=True)``: ``robot_pose``, ``goal_pose``, ``room``,
``obstacles``, ``landmarks``, ``landmark_range``). At the start of an episode it plans a
collision-free path of straight segments:

- the straight segment from start to goal, where that is free;
- otherwise a path of OMPL (RRT-Connect in SE(2), then simplified), seeded from the episode
  (the same episode, the same plan).

A position is free when the robot can turn in place there: its footprint swept over every
heading (a disc of half its diagonal, plus ``margin``) stays inside the room and clear of
every obstacle, so the follower may turn at any waypoint; and it sees at least
``min_visible`` landmarks there (the env's rule), each seen when its horizontal distance lies
within the range the nominal camera sees it at (``landmark_range``). The follower drives the
path turn-drive-turn: it turns in place towards the next waypoint (forwards or backwards,
whichever needs less turning), drives straight with its heading held, and at the goal turns
to the goal heading. Speeds follow the robot's limits with deceleration ramps, so it stops on
each waypoint within millimetres.

OMPL is optional: ``pip install 'radial_ibvs_gym[planning]'``.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from agents.analytic.docking import (
    goal_frame,
    in_docking_cone,
    line_docking,
    ramp,
    turn_in_place,
)
from agents.analytic.pose_oracle import PoseOracle
from radial_ibvs_gym.physics import RobotConfig

__all__ = ["PLANNING_EXTRA", "MapPlanner", "Plan", "plan_path", "segment_free"]

#: what to install for the planner
PLANNING_EXTRA = "pip install 'radial_ibvs_gym[planning]'"
F64 = NDArray[np.float64]


def _import_ompl() -> tuple[Any, Any, Any]:
    try:
        from ompl import base, geometric, util
    except ImportError:
        raise ValueError(
            f"the planner needs OMPL, which is not installed: {PLANNING_EXTRA}"
        ) from None
    return base, geometric, util


#: the landmarks the plan keeps in view: ``(landmarks (L, 3), ranges (L, 2), least count)``
Visibility = tuple[F64, F64, int] | None


def _free(points: F64, room: F64, obstacles: F64, radius: float, view: Visibility = None) -> bool:
    """Whether discs of ``radius`` at ``points`` ``(P, 2)`` are inside the room and clear.

    With ``view``, every point must also see at least that many landmarks: a landmark is seen
    when its horizontal distance lies within its visible range (the omnidirectional camera
    sees all around).
    """
    x, y = points[:, 0], points[:, 1]
    if not ((x >= radius).all() and (y >= radius).all()):
        return False
    if not ((x <= room[0] - radius).all() and (y <= room[1] - radius).all()):
        return False
    for ox, oy, r in obstacles:
        if r > 0 and (np.hypot(x - ox, y - oy) < r + radius).any():
            return False
    if view is not None:
        landmarks, ranges, least = view
        d = np.hypot(landmarks[None, :, 0] - x[:, None], landmarks[None, :, 1] - y[:, None])
        seen = ((d > ranges[None, :, 0]) & (d < ranges[None, :, 1])).sum(axis=1)
        if (seen < least).any():
            return False
    return True


def segment_free(
    a: F64, b: F64, room: F64, obstacles: F64, radius: float, view: Visibility = None
) -> bool:
    """Whether the disc of ``radius`` (metres) moves from ``a`` to ``b`` ``(2,)`` without a hit.

    Checked every centimetre along the segment.
    """
    n = max(2, math.ceil(float(np.hypot(*(b - a))) / 0.01) + 1)
    t = np.linspace(0.0, 1.0, n)[:, None]
    return _free(a + t * (b - a), room, obstacles, radius, view)


def plan_path(
    start: F64,
    goal: F64,
    room: F64,
    obstacles: F64,
    radius: float,
    *,
    view: Visibility = None,
    time_limit_s: float = 2.0,
) -> F64 | None:
    """Plan a collision-free path of straight segments for a disc of ``radius`` metres.

    Parameters
    ----------
    start, goal
        ``(2,)`` positions, metres.
    room
        ``(2,)`` width and depth of the room ``[0, w] x [0, d]``, metres.
    obstacles
        ``(K, 3)`` circles ``(x, y, radius)``, metres (radius 0: padding).
    radius
        The disc's radius, metres.
    view
        ``(landmarks (L, 3), ranges (L, 2), n)``: every point of the path must see at least
        ``n`` landmarks (``None``: no visibility rule).
    time_limit_s
        OMPL's planning budget, seconds (used only when the straight segment is blocked).

    Returns
    -------
    numpy.ndarray or None
        ``(M, 2)`` waypoints from ``start`` to ``goal`` (both included), or ``None`` if none
        was found (or the start or goal is not free).
    """
    start, goal = np.asarray(start, dtype=np.float64), np.asarray(goal, dtype=np.float64)
    if segment_free(start, goal, room, obstacles, radius, view):
        return np.stack([start, goal])
    ends = np.stack([start, goal])
    if not _free(ends, room, obstacles, radius, view):
        return None
    path = _ompl_path(start, goal, room, obstacles, radius, 0.0, view, time_limit_s)
    if path is None:  # OMPL checks states every 5 mm: its path may graze; plan with a margin
        path = _ompl_path(start, goal, room, obstacles, radius, 0.01, view, time_limit_s)
    return path


def _ompl_path(
    start: F64,
    goal: F64,
    room: F64,
    obstacles: F64,
    radius: float,
    clearance: float,
    view: Visibility,
    time_limit_s: float,
) -> F64 | None:
    """Plan with OMPL for a disc of ``radius + clearance``; check each segment at ``radius``."""
    ob, og, ou = _import_ompl()
    ou.setLogLevel(ou.LogLevel.LOG_NONE)
    # the episode's own seed: the same map, start and goal give the same plan in any process
    data = np.concatenate([start, goal, room, obstacles.ravel()]).tobytes()
    ou.RNG.setSeed(int.from_bytes(hashlib.sha256(data).digest()[:4], "little") % 2**31 or 1)
    space = ob.SE2StateSpace()
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(0, 0.0)
    bounds.setHigh(0, float(room[0]))
    bounds.setLow(1, 0.0)
    bounds.setHigh(1, float(room[1]))
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    setup.setStateValidityChecker(
        lambda s: _free(np.array([[s.getX(), s.getY()]]), room, obstacles, radius + clearance, view)
    )
    setup.getSpaceInformation().setStateValidityCheckingResolution(0.005)
    begin, end = space.allocState(), space.allocState()
    begin.setX(float(start[0]))
    begin.setY(float(start[1]))
    begin.setYaw(0.0)
    end.setX(float(goal[0]))
    end.setY(float(goal[1]))
    end.setYaw(0.0)
    setup.setStartAndGoalStates(begin, end)
    setup.setPlanner(og.RRTConnect(setup.getSpaceInformation()))
    if not setup.solve(time_limit_s) or not setup.haveExactSolutionPath():
        return None
    setup.simplifySolution()
    states = setup.getSolutionPath().getStates()
    path = np.array([[s.getX(), s.getY()] for s in states], dtype=np.float64)
    path[0], path[-1] = start, goal
    segments_ok = all(
        segment_free(path[k], path[k + 1], room, obstacles, radius, view)
        for k in range(len(path) - 1)
    )
    return path if segments_ok else None


@dataclass
class Plan:
    """A robot's plan and where it is along it (the planner's per-episode ``state``)."""

    waypoints: F64
    goal_yaw: float
    index: int = 1
    failed: bool = False


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class MapPlanner:
    """The ``planner`` policy: plan with the map, then follow the path turn-drive-turn.

    Parameters
    ----------
    robot
        The robot's limits (default: the Pioneer-like robot of the scenarios).
    margin
        Clearance kept beyond the footprint's turning disc, metres.
    gain
        Proportional gain of the drive and the turns, 1/s (below ``1 / control_dt``).
    waypoint_tolerance, goal_tolerance
        A waypoint (the goal) is reached within this distance, metres.
    heading_tolerance
        The robot drives only when heading within this angle of its waypoint, radians.
    time_limit_s
        OMPL's planning budget per episode, seconds.
    min_visible
        Every point of the plan keeps at least this many landmarks in view (the env's rule:
        fewer end the episode as lost).
    drive_gate
        ``0`` (the default): turn in place until heading within ``heading_tolerance``, then
        drive. ``> 0``: drive and turn together, the speed faded linearly from full at zero
        heading error to zero at ``drive_gate`` radians, so the command is a continuous
        function of the pose (what a student can learn: :mod:`agents.learned.distill`).
    reverse
        ``True`` (the default): drive forwards or backwards, whichever needs less turning.
        ``False``: forwards only. A teacher (:mod:`agents.learned.distill`) uses ``False``:
        with reversing, the turn's sign flips where the waypoint is abeam (90 deg), exactly
        where a student that drove past the goal ends up, and a student that averages the
        two labels there stands still.
    final_radius
        ``0`` (the default): the follower drives the whole path. ``> 0``: within this distance
        of the goal, on the path's last segment, the paper's smooth control law on the true
        poses (the ``oracle``, :class:`~agents.analytic.pose_oracle.PoseOracle`) takes over,
        metres. A teacher (:mod:`agents.learned.distill`) uses it: near the goal the follower's
        turn-creep-turn depends on millimetres, which an image-only student cannot see, while
        the smooth law is a continuous function of the pose.
    hold_radius
        Within this distance of a waypoint the follower holds its heading and only drives
        along it (the bearing is sensitive to millimetres there), metres. A teacher labelling
        states off its own path (:mod:`agents.learned.distill`) uses 0: from a state beside
        the goal it turns towards it instead of stopping there.
    approach, approach_limit
        ``0`` (the default): on the path's last segment the follower aims at the goal.
        ``> 0``: it aims at a point behind the goal on the line of the goal heading,
        ``min(approach * d, approach_limit)`` metres behind it at a distance ``d``, so the
        path bends to arrive along the goal heading and the aim still closes on the goal (a
        continuous function of the pose, with no state). A teacher
        (:mod:`agents.learned.distill`) uses it: a student that arrives with the goal heading
        has little turning left at the goal, where the image resolves the least.
    align_radius
        ``0`` (the default): off. ``> goal_tolerance``: near the goal, on the path's last
        segment, the command blends from the follower's (turn towards the goal, drive) into
        the final alignment (turn towards the goal *heading*, drive along the robot's own
        heading to the goal's foot on it), wholly the alignment within ``goal_tolerance``,
        linearly in the distance up to ``align_radius``, metres. The command is a continuous
        function of the pose there (the alignment uses no bearing to a goal millimetres
        away), but where the goal lies dead behind the robot beyond ``goal_tolerance`` (the
        forwards-only drive's turn flips sign there, while the alignment backs up), and the
        alignment never increases the distance to the goal. A teacher
        (:mod:`agents.learned.distill`) uses it instead of ``final_radius``: the smooth law's
        turn near the goal flips sign over centimetres, which an image-only student averages
        into a stall. Exclusive with ``final_radius``.
    align_unblock
        ``False`` (the default): the blend of ``align_radius`` as above. ``True``: where the
        two weighted commands cancel (the blend's larger component is under half of the
        largest component of their magnitudes added), the follower's command alone. A blend
        of two commands has zeros away from the goal, where the robot stands still for good:
        started 2.5 and 4 cm from the goal with any heading, in 64 validation rooms each, the
        blend timed out in 14 and 17, this rule in 2 and 0 (``approach=0.5``;
        ``benchmarks/teacher_check.py --near``). The command is discontinuous where the rule
        switches.
    line_radius, line_cone, line_lateral_gain, line_speed
        ``0`` (the default): off. ``> 0``: within ``line_radius`` metres of the goal, on the
        path's last segment, wherever the robot lies behind the goal within ``line_cone``
        radians of the goal heading line, or within ``goal_tolerance`` of that line, the
        line-following docking law of :mod:`agents.analytic.docking` instead of the follower
        and ``align_radius``'s blend: lateral gain ``line_lateral_gain``, rad/m^2, at most
        ``line_speed`` m/s (keep its steering gain, ``2 sqrt(line_lateral_gain) *
        line_speed``, below ``1 / control_dt``: 4.5/s by default). Its turn near the goal is
        mostly the heading error, which an image resolves, where the follower's is the
        bearing to a point centimetres away. A teacher (:mod:`agents.learned.distill`) uses
        it with ``approach``, which brings the robot into the cone.
    turn_radius, turn_gain
        ``0`` (the default): off. ``> 0``: within ``turn_radius`` metres of the goal, on the
        path's last segment, the robot stands and turns in place to the goal heading
        (:func:`~agents.analytic.docking.turn_in_place`, proportional gain ``turn_gain``, 1/s,
        below ``1 / control_dt``), before any other rule. Set it under the env's success
        radius: the episode then succeeds once the heading is within tolerance. A teacher
        (:mod:`agents.learned.distill`) uses it: its label there is a function of the heading
        error alone, and a larger gain than ``gain`` makes the last degrees' turn labels
        larger than an image-only student's fitting error.
    turn_floor
        The least turn rate of ``turn_radius``'s turn in place while the heading is off,
        rad/s (default 0: none; :func:`~agents.analytic.docking.turn_in_place`'s ``floor``).
        A teacher's proportional turn fades below what its student fits in the last degrees.

    Raises
    ------
    ValueError
        If OMPL is not installed (the message names the extra to install).
    """

    def __init__(
        self,
        robot: RobotConfig | None = None,
        margin: float = 0.05,
        gain: float = 2.0,
        waypoint_tolerance: float = 0.01,
        goal_tolerance: float = 0.003,
        heading_tolerance: float = math.radians(2.0),
        time_limit_s: float = 2.0,
        min_visible: int = 3,
        hold_radius: float = 0.03,
        drive_gate: float = 0.0,
        reverse: bool = True,
        final_radius: float = 0.0,
        align_radius: float = 0.0,
        approach: float = 0.0,
        approach_limit: float = 0.5,
        align_unblock: bool = False,
        line_radius: float = 0.0,
        line_cone: float = 0.3,
        line_lateral_gain: float = 900.0,
        line_speed: float = 0.15,
        turn_radius: float = 0.0,
        turn_gain: float = 6.0,
        turn_floor: float = 0.0,
    ) -> None:
        _import_ompl()
        if isinstance(min_visible, bool) or not isinstance(min_visible, int) or min_visible < 0:
            raise ValueError(f"min_visible must be an integer >= 0, got {min_visible!r}")
        self.min_visible = min_visible
        self.robot = robot or RobotConfig()
        values = {
            "margin": margin,
            "gain": gain,
            "waypoint_tolerance": waypoint_tolerance,
            "goal_tolerance": goal_tolerance,
            "heading_tolerance": heading_tolerance,
            "time_limit_s": time_limit_s,
            "hold_radius": hold_radius,
            "drive_gate": drive_gate,
            "final_radius": final_radius,
            "align_radius": align_radius,
            "approach": approach,
            "approach_limit": approach_limit,
            "line_radius": line_radius,
            "line_cone": line_cone,
            "line_lateral_gain": line_lateral_gain,
            "line_speed": line_speed,
            "turn_radius": turn_radius,
            "turn_gain": turn_gain,
            "turn_floor": turn_floor,
        }
        for name, value in values.items():
            zero_ok = name in (
                "margin",
                "hold_radius",
                "drive_gate",
                "final_radius",
                "align_radius",
                "approach",
                "line_radius",
                "line_cone",
                "line_lateral_gain",
                "turn_radius",
                "turn_floor",
            )
            if not (math.isfinite(value) and value >= 0 and (value > 0 or zero_ok)):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        self.margin, self.gain = float(margin), float(gain)
        self.waypoint_tolerance = float(waypoint_tolerance)
        self.goal_tolerance = float(goal_tolerance)
        self.heading_tolerance = float(heading_tolerance)
        self.time_limit_s = float(time_limit_s)
        self.hold_radius = float(hold_radius)
        self.drive_gate = float(drive_gate)
        self.reverse = bool(reverse)
        self.final_radius = float(final_radius)
        self.align_radius = float(align_radius)
        self.approach, self.approach_limit = float(approach), float(approach_limit)
        if not isinstance(align_unblock, bool):
            raise ValueError(f"align_unblock must be true or false, got {align_unblock!r}")
        self.align_unblock = align_unblock
        self.line_radius, self.line_lateral_gain = float(line_radius), float(line_lateral_gain)
        self.line_cone, self.line_speed = float(line_cone), float(line_speed)
        self.turn_radius, self.turn_gain = float(turn_radius), float(turn_gain)
        self.turn_floor = float(turn_floor)
        if self.line_cone >= math.pi / 2:
            raise ValueError(f"line_cone must be below pi/2 radians, got {line_cone!r}")
        if self.turn_radius > 0 and self.final_radius > 0:
            raise ValueError(
                f"turn_radius ({turn_radius!r}) and final_radius ({final_radius!r}) both "
                "take over near the goal: set one of them to 0"
            )
        if self.line_radius > 0 and self.final_radius > 0:
            raise ValueError(
                f"line_radius ({line_radius!r}) and final_radius ({final_radius!r}) both "
                "take over near the goal: set one of them to 0"
            )
        if self.turn_floor > 0 and self.turn_radius <= 0:
            raise ValueError(
                f"turn_floor ({turn_floor!r}) acts on turn_radius's turn in place: set "
                "turn_radius > 0"
            )
        if align_unblock and self.align_radius <= 0:
            raise ValueError("align_unblock acts on align_radius's blend: set align_radius > 0")
        if self.approach >= 1.0:
            raise ValueError(
                f"approach must be below 1 (the aim behind the goal must close on it), "
                f"got {approach!r}"
            )
        if self.align_radius > 0 and self.final_radius > 0:
            raise ValueError(
                f"align_radius ({align_radius!r}) and final_radius ({final_radius!r}) both "
                "take over near the goal: set one of them to 0"
            )
        if 0 < self.align_radius <= self.goal_tolerance:
            raise ValueError(
                f"align_radius must exceed goal_tolerance ({goal_tolerance!r}), "
                f"got {align_radius!r}"
            )
        self._oracle = PoseOracle(robot=self.robot) if self.final_radius > 0 else None
        self.radius = 0.5 * math.hypot(self.robot.length, self.robot.width) + self.margin

    env_kwargs: dict[str, bool] = {"privileged": True, "privileged_map": True}  # noqa: RUF012

    def __repr__(self) -> str:
        return f"MapPlanner(margin={self.margin}, gain={self.gain})"

    def make_plan(self, obs: dict[str, np.ndarray]) -> Plan:
        """Plan an episode from its first observation (one robot)."""
        pose = np.asarray(obs["robot_pose"], dtype=np.float64)
        goal = np.asarray(obs["goal_pose"], dtype=np.float64)
        room = np.asarray(obs["room"], dtype=np.float64)
        obstacles = np.asarray(obs["obstacles"], dtype=np.float64).reshape(-1, 3)
        view: Visibility = None
        if self.min_visible > 0:
            landmarks = np.asarray(obs["landmarks"], dtype=np.float64).reshape(-1, 3)
            ranges = np.asarray(obs["landmark_range"], dtype=np.float64).reshape(-1, 2)
            view = (landmarks, ranges, self.min_visible)
        path = plan_path(
            pose[:2], goal[:2], room, obstacles, self.radius, view=view,
            time_limit_s=self.time_limit_s,
        )  # fmt: skip
        if path is None:  # no free path for the turning disc: try the straight drive anyway
            return Plan(np.stack([pose[:2], goal[:2]]), float(goal[2]), failed=True)
        return Plan(path, float(goal[2]))

    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch, as stable-baselines3's ``predict``.

        ``state`` carries each robot's :class:`Plan` from step to step (plan afresh at
        ``episode_start``, or when ``state`` is ``None``).

        Raises
        ------
        KeyError
            If the observation lacks the poses or the map (the message names the
            ``gym.make`` arguments to use).
        """
        for key in ("robot_pose", "goal_pose", "room", "obstacles", "landmarks", "landmark_range"):
            if key not in observation:
                raise KeyError(
                    f"the planner needs observation[{key!r}]: make the env with {self.env_kwargs}"
                )
        poses = np.asarray(observation["robot_pose"], dtype=np.float64)
        batched = poses.ndim == 2
        n = len(poses) if batched else 1
        rows = [
            {k: (np.asarray(v)[i] if batched else np.asarray(v)) for k, v in observation.items()}
            for i in range(n)
        ]
        starts = np.zeros(n, dtype=bool)  # with a state and no episode_start: go on
        if episode_start is not None:
            starts = np.broadcast_to(np.asarray(episode_start, dtype=bool).reshape(-1), n).copy()
        plans: list[Plan] = list(state) if state is not None and len(state) == n else [None] * n  # type: ignore[list-item]
        actions = np.zeros((n, 2), dtype=np.float32)
        for i, row in enumerate(rows):
            if starts[i] or plans[i] is None:
                plans[i] = self.make_plan(row)
            pose = np.asarray(row["robot_pose"], dtype=np.float64)
            if self._oracle is not None and self._near_goal(plans[i], pose, self.final_radius):
                actions[i] = self._oracle.predict(row)[0]
            elif self.turn_radius > 0 and self._near_goal(plans[i], pose, self.turn_radius):
                actions[i] = self._turn(plans[i], pose)
            elif (docking := self._dock(plans[i], pose)) is not None:
                actions[i] = docking
            elif self.align_radius > 0 and self._near_goal(plans[i], pose, self.align_radius):
                actions[i] = self._align(plans[i], pose)
            else:
                actions[i] = self._follow(plans[i], pose)
        return (actions if batched else actions[0]), plans

    def _near_goal(self, plan: Plan, pose: F64, radius: float) -> bool:
        """Whether the robot is within ``radius`` of the goal (metres), on the last segment."""
        goal = plan.waypoints[-1]
        last = plan.index >= len(plan.waypoints) - 1
        return last and math.hypot(goal[0] - pose[0], goal[1] - pose[1]) < radius

    def _dock(self, plan: Plan, pose: F64) -> np.ndarray | None:
        """Return the docking law's command (``line_radius``), action units, or ``None``.

        ``None`` where the law does not apply: off, not near the goal, or outside its cone.
        """
        if self.line_radius <= 0 or not self._near_goal(plan, pose, self.line_radius):
            return None
        x_g, y_g, phi = goal_frame(pose, self._goal_pose(plan))
        if not in_docking_cone(x_g, y_g, self.line_cone, self.goal_tolerance):
            return None
        robot = self.robot
        v, omega = line_docking(
            x_g,
            y_g,
            phi,
            gain=self.gain,
            lateral_gain=self.line_lateral_gain,
            max_speed=min(robot.max_linear_speed, self.line_speed),
            max_accel=robot.max_linear_accel,
            max_turn=robot.max_angular_speed,
            max_turn_accel=robot.max_angular_accel,
        )
        return np.array([v / robot.max_linear_speed, omega / robot.max_angular_speed])

    def _turn(self, plan: Plan, pose: F64) -> np.ndarray:
        """Return the turn in place to the goal heading (``turn_radius``), action units."""
        phi = goal_frame(pose, self._goal_pose(plan))[2]
        robot = self.robot
        omega = turn_in_place(
            phi,
            gain=self.turn_gain,
            max_turn=robot.max_angular_speed,
            max_turn_accel=robot.max_angular_accel,
            floor=self.turn_floor,
        )
        return np.array([0.0, omega / robot.max_angular_speed])

    @staticmethod
    def _goal_pose(plan: Plan) -> F64:
        goal = plan.waypoints[-1]
        return np.array([float(goal[0]), float(goal[1]), plan.goal_yaw])

    def _align(self, plan: Plan, pose: F64) -> np.ndarray:
        """Return the blend of the drive to the goal and the final alignment (``align_radius``)."""
        robot = self.robot
        v_max, w_max = robot.max_linear_speed, robot.max_angular_speed
        x, y, yaw = (float(v) for v in pose)
        goal = plan.waypoints[-1]
        dx, dy = float(goal[0]) - x, float(goal[1]) - y
        distance = math.hypot(dx, dy)
        along = dx * math.cos(yaw) + dy * math.sin(yaw)  # the goal's foot on the heading line
        # the alignment: turn to the goal heading, drive to the foot (never farther from the goal)
        heading = _wrap(plan.goal_yaw - yaw)
        omega_align = math.copysign(
            self._ramp(abs(heading), w_max, robot.max_angular_accel), heading
        )
        v_align = math.copysign(self._ramp(abs(along), v_max, robot.max_linear_accel), along)
        weight = (self.align_radius - distance) / (self.align_radius - self.goal_tolerance)
        weight = min(max(weight, 0.0), 1.0)
        align = np.array([v_align / v_max, omega_align / w_max])
        if weight >= 1.0:
            return align
        drive = self._drive(*self._approach(dx, dy, plan.goal_yaw), yaw)
        blend = (1.0 - weight) * drive + weight * align
        if self.align_unblock:  # the two commands cancel: a stall point of the blend
            added = np.abs((1.0 - weight) * drive) + np.abs(weight * align)
            if np.abs(blend).max() < 0.5 * added.max():
                return drive
        return blend

    def _ramp(self, distance: float, limit: float, accel: float) -> float:
        """Return the speed that stops on ``distance``: proportional, limited, ramped down."""
        return ramp(distance, limit, accel, self.gain)

    def _follow(self, plan: Plan, pose: F64) -> np.ndarray:
        """Return the turn-drive-turn command towards the next waypoint (action units)."""
        robot = self.robot
        w_max = robot.max_angular_speed
        x, y, yaw = (float(v) for v in pose)
        while plan.index < len(plan.waypoints):
            target = plan.waypoints[plan.index]
            last = plan.index == len(plan.waypoints) - 1
            dx, dy = float(target[0]) - x, float(target[1]) - y
            distance = math.hypot(dx, dy)
            tolerance = self.goal_tolerance if last else self.waypoint_tolerance
            if distance > tolerance:
                break
            plan.index += 1
        if plan.index >= len(plan.waypoints):  # at the goal: the final turn
            error = _wrap(plan.goal_yaw - yaw)
            omega = math.copysign(self._ramp(abs(error), w_max, robot.max_angular_accel), error)
            return np.array([0.0, omega / w_max])
        if plan.index == len(plan.waypoints) - 1:
            dx, dy = self._approach(dx, dy, plan.goal_yaw)
        return self._drive(dx, dy, yaw)

    def _approach(self, dx: float, dy: float, goal_yaw: float) -> tuple[float, float]:
        """Return the aim on the last segment: the goal, or a point behind it (``approach``)."""
        if self.approach <= 0:
            return dx, dy
        back = min(self.approach * math.hypot(dx, dy), self.approach_limit)
        return dx - back * math.cos(goal_yaw), dy - back * math.sin(goal_yaw)

    def _drive(self, dx: float, dy: float, yaw: float) -> np.ndarray:
        """Return the command towards a waypoint ``(dx, dy)`` metres away (action units)."""
        robot = self.robot
        v_max, w_max = robot.max_linear_speed, robot.max_angular_speed
        distance = math.hypot(dx, dy)
        bearing = math.atan2(dy, dx)
        forward, backward = _wrap(bearing - yaw), _wrap(bearing + math.pi - yaw)
        backwards = self.reverse and abs(backward) < abs(forward)
        direction, error = (-1.0, backward) if backwards else (1.0, forward)
        along = distance * math.cos(error)
        if distance < self.hold_radius:  # close: the bearing is sensitive to mm; hold heading
            speed = self._ramp(abs(along), v_max, robot.max_linear_accel)
            v = direction * math.copysign(speed, along)
            return np.array([v / v_max, 0.0])
        omega = math.copysign(self._ramp(abs(error), w_max, robot.max_angular_accel), error)
        if self.drive_gate > 0:  # turn and drive together, slower the more the heading is off
            fade = max(0.0, 1.0 - abs(error) / self.drive_gate)
            v = direction * fade * self._ramp(max(along, 0.0), v_max, robot.max_linear_accel)
            return np.array([v / v_max, omega / w_max])
        if abs(error) > self.heading_tolerance:  # turn in place first
            return np.array([0.0, omega / w_max])
        v = direction * self._ramp(max(along, 0.0), v_max, robot.max_linear_accel)
        return np.array([v / v_max, omega / w_max])
