"""The analytic policies by name: the IBVS variants and the pose oracle (no learning).

:mod:`radial_ibvs_agents.registry` adds the random floor and the learned models to these;
:mod:`radial_ibvs_agents.learned.networks.residual` takes its base policy from here.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from radial_ibvs_agents.analytic.ekf_planner import EKFPlanner
from radial_ibvs_agents.analytic.filtered import FilteredPolicy
from radial_ibvs_agents.analytic.ibvs_policy import IBVSPolicy
from radial_ibvs_agents.analytic.ibvs_straight import StraightIBVSPolicy
from radial_ibvs_agents.analytic.pbvs import PBVSPolicy
from radial_ibvs_agents.analytic.pbvs_ekf import PBVSEKFPolicy
from radial_ibvs_agents.analytic.planner import ImageGoalPlanner, MapPlanner
from radial_ibvs_agents.analytic.pose_oracle import PoseOracle

__all__ = ["ANALYTIC_POLICIES", "DESCRIPTIONS", "EXTRAS", "make_analytic"]

ANALYTIC_POLICIES: dict[str, Callable[..., Any]] = {
    "ibvs": lambda **kw: IBVSPolicy("paper", **kw),
    "ibvs-current": lambda **kw: IBVSPolicy("current", **kw),
    "ibvs-mean": lambda **kw: IBVSPolicy("mean", **kw),
    "ibvs-no-frame-change": lambda **kw: IBVSPolicy("no-frame-change", **kw),
    "oracle": lambda **kw: PoseOracle(**kw),
    "ibvs-backward": lambda **kw: IBVSPolicy("paper", allow_backward=True, **kw),
    "oracle-backward": lambda **kw: PoseOracle(allow_backward=True, **kw),
    "ibvs-straight": lambda **kw: StraightIBVSPolicy(**kw),
    # privileged: the true poses and the map (the limit row of every table)
    "planner": lambda **kw: MapPlanner(**kw),
    # the planner driving to the pose the goal image shows (the limit the images allow)
    "planner-image-goal": lambda **kw: ImageGoalPlanner(**kw),
    # measured in the imperfect suite: a temporal filter and an earlier final approach
    "ibvs-straight-filtered": lambda smoothing=0.85, rotate_radius=0.05, **kw: FilteredPolicy(
        StraightIBVSPolicy(rotate_radius=rotate_radius, **kw), smoothing
    ),
    # position-based: the goal's pose solved from the image, the oracle's law on it
    "pbvs": lambda **kw: PBVSPolicy(**kw),
    "pbvs-ekf": lambda **kw: PBVSEKFPolicy(**kw),
    # the planner's path on the filtered pose, in the room the goal image shows (image-only)
    "ekf-planner": lambda **kw: EKFPlanner(**kw),
}


#: one line per analytic policy, for ``--help`` and the README's table of agents
DESCRIPTIONS: dict[str, str] = {
    "ibvs": "the paper's IBVS (eq. 30, 36-38), forward driving",
    "ibvs-current": "the IBVS with the current interaction matrix",
    "ibvs-mean": "the IBVS with the mean of the current and goal matrices",
    "ibvs-no-frame-change": "the IBVS without the paper's change of frame",
    "oracle": "the paper's control law fed the true poses (privileged)",
    "ibvs-backward": "the paper's IBVS, allowed to drive backward",
    "oracle-backward": "the pose oracle, allowed to drive backward (privileged)",
    "ibvs-straight": "turn, drive straight, turn: the IBVS's estimate of the goal",
    "planner": "plans with the map and the true poses: the task's limit",
    "planner-image-goal": "the planner driving to the pose the goal image shows: the images' limit",
    "ibvs-straight-filtered": "ibvs-straight through a temporal filter of the image points",
    "pbvs": "position-based: the goal's pose solved from the image, eq. 38 on it",
    "pbvs-ekf": "pbvs on the pose filtered with the robot's own motion (an EKF)",
    "ekf-planner": "the planner's path on pbvs-ekf's pose, in the room the goal image shows",
}
#: the ``pip install -e ".[EXTRA]"`` extra a policy needs beyond the core install
EXTRAS: dict[str, str] = {
    "planner": "planning",
    "planner-image-goal": "planning",
    "ekf-planner": "planning",
}


def make_analytic(name: str, **kwargs: Any) -> Any:
    """Build an analytic policy by name (a key of :data:`ANALYTIC_POLICIES`).

    Raises
    ------
    ValueError
        For an unknown name (the message lists the valid ones).
    """
    if name not in ANALYTIC_POLICIES:
        raise ValueError(f"unknown analytic policy {name!r}; valid: {list(ANALYTIC_POLICIES)}")
    return ANALYTIC_POLICIES[name](**kwargs)
