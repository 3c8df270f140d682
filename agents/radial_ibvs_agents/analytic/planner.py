"""``planner``: a privileged policy with a map, the physical limit of the parking task.

It sees what no image-based policy may: the true poses and the map
(``gym.make(..., privileged=True, privileged_map=True)``: ``robot_pose``, ``goal_pose``, ``room``,
``obstacles``, ``landmarks``, ``landmark_range``). At the start of an episode it plans a
collision-free path of straight segments (:mod:`radial_ibvs_agents.analytic.path_planning`: the
straight segment where free, else OMPL), keeping at least ``min_visible`` landmarks in view, and
follows it turn-drive-turn: it turns in place towards the next waypoint (forwards or backwards,
whichever needs less turning), drives straight with its heading held, and at the goal turns to the
goal heading. Speeds follow the robot's limits with deceleration ramps, so it stops on each waypoint
within millimetres. As a distillation teacher it takes near-goal rules
(:class:`~radial_ibvs_agents.analytic.near_goal.NearGoalRules`) that keep its commands learnable
from the image.

OMPL is optional: ``pip install 'radial_ibvs_gym[planning]'``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_agents.analytic.docking import (
    goal_frame,
    in_docking_cone,
    line_docking,
    ramp,
    turn_in_place,
)
from radial_ibvs_agents.analytic.near_goal import NearGoalRules
from radial_ibvs_agents.analytic.path_planning import (
    PLANNING_EXTRA,
    Visibility,
    import_ompl,
    plan_path,
    segment_free,
)
from radial_ibvs_agents.analytic.pose_oracle import PoseOracle
from radial_ibvs_gym.geometry import pose_in_frame
from radial_ibvs_gym.physics import RobotConfig

__all__ = ["PLANNING_EXTRA", "MapPlanner", "NearGoalRules", "Plan", "plan_path", "segment_free"]

F64 = NDArray[np.float64]


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
    **near_goal
        The near-goal rules (:class:`~radial_ibvs_agents.analytic.near_goal.NearGoalRules`:
        ``hold_radius``, ``drive_gate``, ``reverse``, ``final_radius``, ``align_radius``,
        ``approach``, ``approach_limit``, ``align_unblock``, ``line_radius``, ``line_cone``,
        ``line_lateral_gain``, ``line_speed``, ``turn_radius``, ``turn_gain``, ``turn_floor``,
        ``turn_deadband``), each off by default; held as ``planner.rules``.

    Raises
    ------
    ValueError
        If OMPL is not installed (the message names the extra to install), or for a bad or
        unknown argument.
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` per
    #: robot (OMPL plans one robot at a time)
    batch_mode = "robot"

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
        **near_goal: Any,
    ) -> None:
        import_ompl()
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
        }
        for name, value in values.items():
            if not (math.isfinite(value) and value >= 0 and (value > 0 or name == "margin")):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        self.margin, self.gain = float(margin), float(gain)
        self.waypoint_tolerance = float(waypoint_tolerance)
        self.goal_tolerance = float(goal_tolerance)
        self.heading_tolerance = float(heading_tolerance)
        self.time_limit_s = float(time_limit_s)
        #: the near-goal rules (a teacher's; all off by default)
        self.rules = rules = NearGoalRules.from_kwargs(near_goal)
        if 0 < rules.align_radius <= self.goal_tolerance:
            raise ValueError(
                f"align_radius must exceed goal_tolerance ({goal_tolerance!r}), "
                f"got {rules.align_radius!r}"
            )
        self._oracle = PoseOracle(robot=self.robot) if rules.final_radius > 0 else None
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
            rules = self.rules
            if self._oracle is not None and self._near_goal(plans[i], pose, rules.final_radius):
                actions[i] = self._oracle.predict(row)[0]
            elif rules.turn_radius > 0 and self._near_goal(plans[i], pose, rules.turn_radius):
                actions[i] = self._turn(plans[i], pose)
            elif (docking := self._dock(plans[i], pose)) is not None:
                actions[i] = docking
            elif rules.align_radius > 0 and self._near_goal(plans[i], pose, rules.align_radius):
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
        if self.rules.line_radius <= 0 or not self._near_goal(plan, pose, self.rules.line_radius):
            return None
        x_g, y_g, phi = goal_frame(pose, self._goal_pose(plan))
        if not in_docking_cone(x_g, y_g, self.rules.line_cone, self.goal_tolerance):
            return None
        robot = self.robot
        v, omega = line_docking(
            x_g,
            y_g,
            phi,
            gain=self.gain,
            lateral_gain=self.rules.line_lateral_gain,
            max_speed=min(robot.max_linear_speed, self.rules.line_speed),
            max_accel=robot.max_linear_accel,
            max_turn=robot.max_angular_speed,
            max_turn_accel=robot.max_angular_accel,
        )
        return np.array([v / robot.max_linear_speed, omega / robot.max_angular_speed])

    def _turn(self, plan: Plan, pose: F64) -> np.ndarray:
        """Return the turn in place to the goal heading (``turn_radius``), action units."""
        phi = goal_frame(pose, self._goal_pose(plan))[2]
        if abs(phi) < self.rules.turn_deadband:  # parked: stand still
            return np.zeros(2)
        robot = self.robot
        omega = turn_in_place(
            phi,
            gain=self.rules.turn_gain,
            max_turn=robot.max_angular_speed,
            max_turn_accel=robot.max_angular_accel,
            floor=self.rules.turn_floor,
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
        along = pose_in_frame(pose, self._goal_pose(plan))[0]  # the goal's foot on the heading
        # the alignment: turn to the goal heading, drive to the foot (never farther from the goal)
        heading = _wrap(plan.goal_yaw - yaw)
        omega_align = math.copysign(
            self._ramp(abs(heading), w_max, robot.max_angular_accel), heading
        )
        v_align = math.copysign(self._ramp(abs(along), v_max, robot.max_linear_accel), along)
        radius = self.rules.align_radius
        weight = (radius - distance) / (radius - self.goal_tolerance)
        weight = min(max(weight, 0.0), 1.0)
        align = np.array([v_align / v_max, omega_align / w_max])
        if weight >= 1.0:
            return align
        drive = self._drive(*self._approach(dx, dy, plan.goal_yaw), yaw)
        blend = (1.0 - weight) * drive + weight * align
        if self.rules.align_unblock:  # the two commands cancel: a stall point of the blend
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
        if self.rules.approach <= 0:
            return dx, dy
        back = min(self.rules.approach * math.hypot(dx, dy), self.rules.approach_limit)
        return dx - back * math.cos(goal_yaw), dy - back * math.sin(goal_yaw)

    def _drive(self, dx: float, dy: float, yaw: float) -> np.ndarray:
        """Return the command towards a waypoint ``(dx, dy)`` metres away (action units)."""
        robot = self.robot
        v_max, w_max = robot.max_linear_speed, robot.max_angular_speed
        distance = math.hypot(dx, dy)
        bearing = math.atan2(dy, dx)
        forward, backward = _wrap(bearing - yaw), _wrap(bearing + math.pi - yaw)
        backwards = self.rules.reverse and abs(backward) < abs(forward)
        direction, error = (-1.0, backward) if backwards else (1.0, forward)
        along = distance * math.cos(error)
        if distance < self.rules.hold_radius:  # close: the bearing is sensitive to mm; hold heading
            speed = self._ramp(abs(along), v_max, robot.max_linear_accel)
            v = direction * math.copysign(speed, along)
            return np.array([v / v_max, 0.0])
        omega = math.copysign(self._ramp(abs(error), w_max, robot.max_angular_accel), error)
        if self.rules.drive_gate > 0:  # turn and drive together, slower the more the heading is off
            fade = max(0.0, 1.0 - abs(error) / self.rules.drive_gate)
            v = direction * fade * self._ramp(max(along, 0.0), v_max, robot.max_linear_accel)
            return np.array([v / v_max, omega / w_max])
        if abs(error) > self.heading_tolerance:  # turn in place first
            return np.array([0.0, omega / w_max])
        v = direction * self._ramp(max(along, 0.0), v_max, robot.max_linear_accel)
        return np.array([v / v_max, omega / w_max])


class ImageGoalPlanner(MapPlanner):
    """The planner driving to the goal the goal image shows: the limit the images allow.

    The same privileged planner (the true poses, the map), handed the *image goal* instead of
    the goal (the env's ``privileged_goal="image"``: the pose whose noise-free image through
    the episode's camera matches the goal image). Success is still judged at the true goal.
    Where the goal image is one noisy frame the image goal is off by about a centimetre, so a
    policy that settles where the images match parks at most this often: beside the planner's
    rate (what the task allows), this is what the images allow. Through an ideal camera the
    image goal is the goal (to the solve's precision) and the two limits agree.
    """

    env_kwargs: dict[str, Any] = {  # noqa: RUF012
        "privileged": True,
        "privileged_map": True,
        "privileged_goal": "image",
    }

    def __repr__(self) -> str:
        return f"ImageGoalPlanner(margin={self.margin}, gain={self.gain})"
