"""SE(2)/SE(3) helpers and angle wrapping (pure numpy)."""

from radial_ibvs_gym.geometry.angles import wrap_angle, wrap_angle_scalar
from radial_ibvs_gym.geometry.se2 import pose_in_frame, relative_pose, world_to_camera
from radial_ibvs_gym.geometry.transforms import (
    apply_twist_to_points,
    rot2,
    rot_x,
    rot_y,
    rot_z,
    se3_exp,
    skew,
    so3_exp,
)

__all__ = [
    "apply_twist_to_points",
    "pose_in_frame",
    "relative_pose",
    "rot2",
    "rot_x",
    "rot_y",
    "rot_z",
    "se3_exp",
    "skew",
    "so3_exp",
    "world_to_camera",
    "wrap_angle",
    "wrap_angle_scalar",
]
