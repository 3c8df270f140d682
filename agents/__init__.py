"""Reference and learned policies for the radial IBVS parking tasks.

Every policy will implement stable-baselines3's ``predict(observation, state=None,
episode_start=None, deterministic=True) -> (action, state)``. So far: the smooth control law
(Park & Kuipers 2011, the paper's eq. 38) that the IBVS controller and the pose oracle share.
"""

from agents.smooth_control import SmoothControlLaw, curvature, ego_polar

__all__ = ["SmoothControlLaw", "curvature", "ego_polar"]
