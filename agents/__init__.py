"""Reference and learned policies for the radial IBVS parking tasks.

Every policy will implement stable-baselines3's ``predict(observation, state=None,
episode_start=None, deterministic=True) -> (action, state)``. So far: the smooth control law
(Park & Kuipers 2011, the paper's eq. 38) and the pose oracle built on it.
"""

from agents.oracle import PoseOracle
from agents.smooth_control import SmoothControlLaw, curvature, ego_polar

__all__ = ["PoseOracle", "SmoothControlLaw", "curvature", "ego_polar"]
