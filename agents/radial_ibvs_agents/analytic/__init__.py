"""The analytic policies: everything that needs no training.

- :mod:`~radial_ibvs_agents.analytic.smooth_control`: the smooth control law of Park and Kuipers
  (eq. 38).
- :mod:`~radial_ibvs_agents.analytic.ibvs_maths`: the paper's IBVS for one robot (Section 3.3, eq.
  27-37).
- :mod:`~radial_ibvs_agents.analytic.ibvs_maths_batch`: the same maths over a batch of robots.
- :mod:`~radial_ibvs_agents.analytic.ibvs_policy`: :class:`IBVSPolicy`, the IBVS variants as
  policies.
- :mod:`~radial_ibvs_agents.analytic.pose_oracle`: :class:`PoseOracle`, the control law fed true
  poses.
- :mod:`~radial_ibvs_agents.analytic.registry`: the analytic policies by name
  (:func:`make_analytic`).

This package imports neither torch nor stable-baselines3, and never imports
:mod:`radial_ibvs_agents.learned`, the experiments or the CLI.
"""

from radial_ibvs_agents.analytic.ibvs_policy import VARIANTS, IBVSPolicy
from radial_ibvs_agents.analytic.pose_oracle import PoseOracle
from radial_ibvs_agents.analytic.registry import ANALYTIC_POLICIES, make_analytic
from radial_ibvs_agents.analytic.smooth_control import SmoothControlLaw, curvature, ego_polar

__all__ = [
    "ANALYTIC_POLICIES",
    "VARIANTS",
    "IBVSPolicy",
    "PoseOracle",
    "SmoothControlLaw",
    "curvature",
    "ego_polar",
    "make_analytic",
]
