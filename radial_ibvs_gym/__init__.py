"""radial_ibvs_gym: visual servoing of mobile robots with (non-)central catadioptric cameras.

Implements Aliakbarpour, Tahri and Araujo, "Visual servoing of mobile robots using non-central
catadioptric cameras", Robotics and Autonomous Systems, 2014.

Layers (imports flow one way): ``geometry`` -> ``camera`` -> ``features`` -> physics -> envs.
"""

__version__ = "0.1.0"

from radial_ibvs_gym.envs import register_envs

register_envs()

__all__ = ["__version__"]
