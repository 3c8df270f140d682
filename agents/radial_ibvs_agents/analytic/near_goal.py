"""The planner's near-goal rules: how a teacher's commands stay learnable close to the goal.

The ``planner`` (:class:`~radial_ibvs_agents.analytic.planner.MapPlanner`) follows its path
turn-drive-turn; as a teacher for a student that sees only the image
(:mod:`radial_ibvs_agents.learned.dagger.distill`), its commands must be functions of what the image
resolves near the goal. :class:`NearGoalRules` holds the rules that make them so, each off by
default (the plain follower); the shipped student's config (``configs/agents/dagger_student.yaml``,
``teacher_kwargs``) sets them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import Any

from radial_ibvs_gym.config import did_you_mean

__all__ = ["NearGoalRules"]

#: the rules that may be 0 (off); the others must be positive
_ZERO_OK = (
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
    "turn_deadband",
)


@dataclass(frozen=True)
class NearGoalRules:
    """The follower's rules near a waypoint and near the goal (metres, radians, seconds).

    Parameters
    ----------
    hold_radius
        Within this distance of a waypoint the follower holds its heading and only drives
        along it (the bearing is sensitive to millimetres there), metres. A teacher labelling
        states off its own path uses 0: from a state beside the goal it turns towards it
        instead of stopping there.
    drive_gate
        ``0`` (the default): turn in place until heading within ``heading_tolerance``, then drive.
        ``> 0``: drive and turn together, the speed faded linearly from full at zero heading error
        to zero at ``drive_gate`` radians, so the command is a continuous function of the pose (what
        a student can learn: :mod:`radial_ibvs_agents.learned.dagger.distill`).
    reverse
        ``True`` (the default): drive forwards or backwards, whichever needs less turning.
        ``False``: forwards only. A teacher (:mod:`radial_ibvs_agents.learned.dagger.distill`) uses
        ``False``: with reversing, the turn's sign flips where the waypoint is abeam (90 deg),
        exactly where a student that drove past the goal ends up, and a student that averages the
        two labels there stands still.
    final_radius
        ``0`` (the default): the follower drives the whole path. ``> 0``: within this distance of
        the goal, on the path's last segment, the paper's smooth control law on the true poses (the
        ``oracle``, :class:`~radial_ibvs_agents.analytic.pose_oracle.PoseOracle`) takes over,
        metres. A teacher (:mod:`radial_ibvs_agents.learned.dagger.distill`) uses it: near the goal
        the follower's turn-creep-turn depends on millimetres, which an image-only student cannot
        see, while the smooth law is a continuous function of the pose.
    approach, approach_limit
        ``0`` (the default): on the path's last segment the follower aims at the goal. ``> 0``: it
        aims at a point behind the goal on the line of the goal heading,
        ``min(approach * d, approach_limit)`` metres behind it at a distance ``d``, so the path
        bends to arrive along the goal heading and the aim still closes on the goal (a continuous
        function of the pose, with no state). A teacher
        (:mod:`radial_ibvs_agents.learned.dagger.distill`) uses it: a student that arrives with the
        goal heading has little turning left at the goal, where the image resolves the least.
    align_radius
        ``0`` (the default): off. ``> goal_tolerance``: near the goal, on the path's last segment,
        the command blends from the follower's (turn towards the goal, drive) into the final
        alignment (turn towards the goal *heading*, drive along the robot's own heading to the
        goal's foot on it), wholly the alignment within ``goal_tolerance``, linearly in the distance
        up to ``align_radius``, metres. The command is a continuous function of the pose there (the
        alignment uses no bearing to a goal millimetres away), but where the goal lies dead behind
        the robot beyond ``goal_tolerance`` (the forwards-only drive's turn flips sign there, while
        the alignment backs up), and the alignment never increases the distance to the goal. A
        teacher (:mod:`radial_ibvs_agents.learned.dagger.distill`) uses it instead of
        ``final_radius``: the smooth law's turn near the goal flips sign over centimetres, which an
        image-only student averages into a stall. Exclusive with ``final_radius``.
    align_unblock
        ``False`` (the default): the blend of ``align_radius`` as above. ``True``: where the
        two weighted commands cancel (the blend's larger component is under half of the
        largest component of their magnitudes added), the follower's command alone. A blend
        of two commands has zeros away from the goal, where the robot stands still for good:
        started 2.5 and 4 cm from the goal with any heading, in 64 validation rooms each, the
        blend timed out in 14 and 17, this rule in 2 and 0 (``approach=0.5``;
        ``research/diagnostics/teacher_check.py --near``). The command is discontinuous
        where the rule switches.
    line_radius, line_cone, line_lateral_gain, line_speed
        ``0`` (the default): off. ``> 0``: within ``line_radius`` metres of the goal, on the path's
        last segment, wherever the robot lies behind the goal within ``line_cone`` radians of the
        goal heading line, or within ``goal_tolerance`` of that line, the line-following docking law
        of :mod:`radial_ibvs_agents.analytic.docking` instead of the follower and ``align_radius``'s
        blend: lateral gain ``line_lateral_gain``, rad/m^2, at most ``line_speed`` m/s (keep its
        steering gain, ``2 sqrt(line_lateral_gain) * line_speed``, below ``1 / control_dt``: 4.5/s
        by default). Its turn near the goal is mostly the heading error, which an image resolves,
        where the follower's is the bearing to a point centimetres away. A teacher
        (:mod:`radial_ibvs_agents.learned.dagger.distill`) uses it with ``approach``, which brings
        the robot into the cone.
    turn_radius, turn_gain
        ``0`` (the default): off. ``> 0``: within ``turn_radius`` metres of the goal, on the path's
        last segment, the robot stands and turns in place to the goal heading
        (:func:`~radial_ibvs_agents.analytic.docking.turn_in_place`, proportional gain
        ``turn_gain``, 1/s, below ``1 / control_dt``), before any other rule. Set it under the env's
        success radius: the episode then succeeds once the heading is within tolerance. A teacher
        (:mod:`radial_ibvs_agents.learned.dagger.distill`) uses it: its label there is a function of
        the heading error alone, and a larger gain than ``gain`` makes the last degrees' turn labels
        larger than an image-only student's fitting error.
    turn_floor
        The least turn rate of ``turn_radius``'s turn in place while the heading is off, rad/s
        (default 0: none; :func:`~radial_ibvs_agents.analytic.docking.turn_in_place`'s ``floor``). A
        teacher's proportional turn fades below what its student fits in the last degrees.
    turn_deadband
        ``0`` (the default): off. ``> 0``: within ``turn_radius``, a heading error under this many
        radians is parked: the robot stands still. Without it a floor turns on for good, from
        one side of the goal heading to the other, and a park (the pose held 1 s) never comes:
        with ``turn_floor = 0.5`` rad/s the shipped teacher timed out in each of 100 validation
        rooms, 1.5 cm from the goal. Set it above half a step's floor turn
        (``turn_floor * control_dt / 2``, so that a step from outside lands inside it) and under
        the env's heading tolerance; a teacher (:mod:`radial_ibvs_agents.learned.dagger.distill`)
        gives its student the label "stand still" where the robot is parked.

    """

    hold_radius: float = 0.03
    drive_gate: float = 0.0
    reverse: bool = True
    final_radius: float = 0.0
    align_radius: float = 0.0
    approach: float = 0.0
    approach_limit: float = 0.5
    align_unblock: bool = False
    line_radius: float = 0.0
    line_cone: float = 0.3
    line_lateral_gain: float = 900.0
    line_speed: float = 0.15
    turn_radius: float = 0.0
    turn_gain: float = 6.0
    turn_floor: float = 0.0
    turn_deadband: float = 0.0

    @classmethod
    def from_kwargs(cls, kwargs: dict[str, Any]) -> NearGoalRules:
        """Build the rules from keyword arguments, refusing unknown names with a did-you-mean."""
        names = [f.name for f in fields(cls)]
        unknown = sorted(set(kwargs) - set(names))
        if unknown:
            raise ValueError(
                f"unknown planner argument(s) {unknown}{did_you_mean(unknown[0], names)}; "
                f"the near-goal rules: {names}"
            )
        return cls(**kwargs)

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.type in ("bool", bool):
                if not isinstance(value, bool):
                    raise ValueError(f"{f.name} must be true or false, got {value!r}")
                continue
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ValueError(f"{f.name} must be a number, got {value!r}")
            zero_ok = f.name in _ZERO_OK
            if not (math.isfinite(value) and value >= 0 and (value > 0 or zero_ok)):
                raise ValueError(f"{f.name} must be finite and positive, got {value!r}")
            object.__setattr__(self, f.name, float(value))
        if self.line_cone >= math.pi / 2:
            raise ValueError(f"line_cone must be below pi/2 radians, got {self.line_cone!r}")
        for other in ("turn_radius", "line_radius", "align_radius"):
            if getattr(self, other) > 0 and self.final_radius > 0:
                raise ValueError(
                    f"{other} ({getattr(self, other)!r}) and final_radius "
                    f"({self.final_radius!r}) both take over near the goal: set one of them to 0"
                )
        if self.turn_floor > 0 and self.turn_radius <= 0:
            raise ValueError(
                f"turn_floor ({self.turn_floor!r}) acts on turn_radius's turn in place: set "
                "turn_radius > 0"
            )
        if self.turn_deadband > 0 and self.turn_radius <= 0:
            raise ValueError(
                f"turn_deadband ({self.turn_deadband!r}) acts on turn_radius's turn in place: set "
                "turn_radius > 0"
            )
        if self.align_unblock and self.align_radius <= 0:
            raise ValueError("align_unblock acts on align_radius's blend: set align_radius > 0")
        if self.approach >= 1.0:
            raise ValueError(
                f"approach must be below 1 (the aim behind the goal must close on it), "
                f"got {self.approach!r}"
            )
