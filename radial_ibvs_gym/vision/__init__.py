"""Rendered omnidirectional images (numpy) and their measurement (OpenCV).

OpenCV is set to one thread on import: the images are small, the environments run in parallel
processes, and OpenCV's idle worker threads otherwise spin and slow down numpy and torch in
the same process (measured: PPO's ``predict`` 10.8 ms with the default threads, 2.5 ms with one).
"""

import cv2

from radial_ibvs_gym.vision.omni import ImageQuality, OmniRenderer, RoomScene

cv2.setNumThreads(1)

__all__ = ["ImageQuality", "OmniRenderer", "RoomScene"]
