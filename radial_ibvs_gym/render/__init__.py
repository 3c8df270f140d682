"""Rendered omnidirectional images (numpy) and their measurement (OpenCV)."""

from radial_ibvs_gym.render.omni import ImageQuality, OmniRenderer, RoomScene

__all__ = ["ImageQuality", "OmniRenderer", "RoomScene"]
