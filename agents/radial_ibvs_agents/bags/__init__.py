"""ROS 2 bags (MCAP) in and out, without a ROS installation (the ``[ros]`` extra).

- :func:`~radial_ibvs_agents.bags.record.record_episodes` (``radial-ibvs record``): a
  policy's episodes as a bag of standard messages, which Foxglove and ``ros2 bag play`` open
  (:data:`~radial_ibvs_agents.bags.messages.TOPICS`; the layout in
  :data:`FOXGLOVE_LAYOUT`).
- :func:`~radial_ibvs_agents.bags.replay.replay_bag` (``radial-ibvs replay``): a bag's frames
  through the pixel pipeline and an image-only policy; the commands each frame would send.
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["FOXGLOVE_LAYOUT"]

#: the Foxglove layout that shows a recording: the image, a top view, the errors
FOXGLOVE_LAYOUT = Path(__file__).with_name("foxglove_layout.json")
