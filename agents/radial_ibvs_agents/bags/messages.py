"""ROS 2 messages of standard types, built with ``rosbags``' type store (no ROS installation).

Every topic a recording holds (:data:`TOPICS`), with its message type, and one builder per
kind of message. The types are those of ROS 2 Humble and later, the same in every release
since: ``sensor_msgs/Image``, ``geometry_msgs/Twist``, ``nav_msgs/Odometry``,
``tf2_msgs/TFMessage``, ``std_msgs/Float64MultiArray``, ``std_msgs/String``,
``geometry_msgs/PoseArray`` and ``geometry_msgs/PolygonStamped``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["FRAMES", "TOPICS", "Messages"]

#: topic -> (message type, what it holds); the recording's contract (the docs' table)
TOPICS: dict[str, tuple[str, str]] = {
    "/camera/image": (
        "sensor_msgs/msg/Image",
        "the omnidirectional frame the detector read (mono8), when the env renders",
    ),
    "/camera/goal_image": (
        "sensor_msgs/msg/Image",
        "the goal image the detector read, at each episode's start",
    ),
    "/image_points": (
        "std_msgs/msg/Float64MultiArray",
        "the normalised image points (eq. 7), (N, 2), NaN where a landmark is not seen",
    ),
    "/goal_image_points": (
        "std_msgs/msg/Float64MultiArray",
        "the goal image's normalised points, (N, 2), NaN where not seen; at each start",
    ),
    "/goal_image_frames": (
        "std_msgs/msg/Float64MultiArray",
        "each noisy frame the goal image averaged (goal_image_frames > 1), at each start",
    ),
    "/cmd_vel": (
        "geometry_msgs/msg/Twist",
        "the command (m/s, rad/s), stamped when issued, held for one control period",
    ),
    "/odom": (
        "nav_msgs/msg/Odometry",
        "the robot's true pose in the map frame and the constant (v, omega) that moved it there "
        "over the last period",
    ),
    "/tf": ("tf2_msgs/msg/TFMessage", "map -> base_link (the robot), map -> goal"),
    "/errors": (
        "std_msgs/msg/Float64MultiArray",
        "the pose errors: [position (m), heading (deg)]",
    ),
    "/episode_info": (
        "std_msgs/msg/String",
        "JSON: episode, seed, step, position_error_m, heading_error_deg, reached, is_success, "
        "collision, lost, end",
    ),
    "/landmarks": (
        "geometry_msgs/msg/PoseArray",
        "the landmark map (positions, metres, map frame), at each start",
    ),
    "/room": ("geometry_msgs/msg/PolygonStamped", "the room's walls (map frame), at each start"),
}

#: frame ids
FRAMES = {"map": "map", "robot": "base_link", "goal": "goal", "camera": "camera"}


class Messages:
    """Builders of serialised (CDR) messages, over one ``rosbags`` type store.

    Parameters
    ----------
    typestore
        A ``rosbags.typesys`` type store (default: ROS 2 Humble's).
    """

    def __init__(self, typestore: Any = None) -> None:
        from rosbags.typesys import Stores, get_typestore

        self.store = typestore if typestore is not None else get_typestore(Stores.ROS2_HUMBLE)

    def _new(self, msgtype: str, **values: Any) -> Any:
        """Build a ``msgtype`` with ``values``; every other field zero, empty or default."""
        names, fields = self.store.fielddefs[msgtype]
        del names
        args = {}
        for name, (kind, spec) in fields:
            if name in values:
                args[name] = values[name]
            else:
                args[name] = self._default(kind.value, spec)
        return self.store.types[msgtype](**args)

    def _default(self, kind: int, spec: Any) -> Any:
        if kind == 1:  # a base type
            base = spec[0]
            return "" if base == "string" else (False if base == "bool" else 0)
        if kind == 2:  # a message
            return self._new(spec)
        if kind == 3:  # a fixed array
            (inner_kind, inner), length = spec
            if inner_kind.value == 1 and inner[0] != "string":
                return np.zeros(length, dtype=_NUMPY[inner[0]])
            return [self._default(inner_kind.value, inner) for _ in range(length)]
        inner_kind, inner = spec[0]  # a sequence: empty
        if inner_kind.value == 1 and inner[0] != "string":
            return np.zeros(0, dtype=_NUMPY[inner[0]])
        return []

    def serialize(self, message: Any) -> bytes:
        """CDR bytes of ``message``."""
        return bytes(self.store.serialize_cdr(message, message.__msgtype__))

    def _header(self, stamp_ns: int, frame: str) -> Any:
        sec, nanosec = divmod(int(stamp_ns), 1_000_000_000)
        stamp = self._new("builtin_interfaces/msg/Time", sec=sec, nanosec=nanosec)
        return self._new("std_msgs/msg/Header", stamp=stamp, frame_id=frame)

    def image(self, stamp_ns: int, image: NDArray[np.uint8]) -> Any:
        """``sensor_msgs/Image``, mono8, from ``(H, W)`` uint8 grey levels."""
        pixels = np.ascontiguousarray(image, dtype=np.uint8)
        if pixels.ndim != 2:
            raise ValueError(f"a mono8 image is (H, W), got shape {pixels.shape}")
        height, width = pixels.shape
        return self._new(
            "sensor_msgs/msg/Image",
            header=self._header(stamp_ns, FRAMES["camera"]),
            height=height,
            width=width,
            encoding="mono8",
            step=width,
            data=pixels.reshape(-1),
        )

    def points(self, points: NDArray[np.float64], visible: NDArray[np.bool_]) -> Any:
        """``std_msgs/Float64MultiArray`` ``(N, 2)`` (row-major), NaN where not ``visible``."""
        xy = np.where(np.asarray(visible, bool)[:, None], np.asarray(points, np.float64), np.nan)
        n = len(xy)
        dims = [
            self._new("std_msgs/msg/MultiArrayDimension", label="landmark", size=n, stride=2 * n),
            self._new("std_msgs/msg/MultiArrayDimension", label="xy", size=2, stride=2),
        ]
        layout = self._new("std_msgs/msg/MultiArrayLayout", dim=dims, data_offset=0)
        return self._new("std_msgs/msg/Float64MultiArray", layout=layout, data=xy.reshape(-1))

    def values(self, values: list[float], labels: str) -> Any:
        """``std_msgs/Float64MultiArray`` of a few named numbers (``labels``: the dim's label)."""
        dim = self._new(
            "std_msgs/msg/MultiArrayDimension", label=labels, size=len(values), stride=len(values)
        )
        layout = self._new("std_msgs/msg/MultiArrayLayout", dim=[dim], data_offset=0)
        data = np.asarray(values, dtype=np.float64)
        return self._new("std_msgs/msg/Float64MultiArray", layout=layout, data=data)

    def twist(self, v: float, omega: float) -> Any:
        """``geometry_msgs/Twist``: ``v`` m/s forward, ``omega`` rad/s about z."""
        return self._new(
            "geometry_msgs/msg/Twist",
            linear=self._new("geometry_msgs/msg/Vector3", x=float(v)),
            angular=self._new("geometry_msgs/msg/Vector3", z=float(omega)),
        )

    def _pose(self, x: float, y: float, yaw: float, z: float = 0.0) -> Any:
        position = self._new("geometry_msgs/msg/Point", x=float(x), y=float(y), z=float(z))
        q = self._new("geometry_msgs/msg/Quaternion", z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))
        return self._new("geometry_msgs/msg/Pose", position=position, orientation=q)

    def odometry(self, stamp_ns: int, pose: NDArray[np.float64], v: float, omega: float) -> Any:
        """``nav_msgs/Odometry``: ``pose`` ``(x, y, yaw)`` (m, rad) in the map frame.

        The velocity ``v``, ``omega`` (m/s, rad/s) is in the robot frame.
        """
        pose_cov = self._new("geometry_msgs/msg/PoseWithCovariance", pose=self._pose(*pose))
        twist_cov = self._new("geometry_msgs/msg/TwistWithCovariance", twist=self.twist(v, omega))
        return self._new(
            "nav_msgs/msg/Odometry",
            header=self._header(stamp_ns, FRAMES["map"]),
            child_frame_id=FRAMES["robot"],
            pose=pose_cov,
            twist=twist_cov,
        )

    def tf(self, stamp_ns: int, frames: dict[str, NDArray[np.float64]]) -> Any:
        """``tf2_msgs/TFMessage``: map -> each child frame, at its ``(x, y, yaw)``."""
        transforms = []
        for child, (x, y, yaw) in frames.items():
            translation = self._new("geometry_msgs/msg/Vector3", x=float(x), y=float(y))
            rotation = self._pose(x, y, yaw).orientation
            transform = self._new(
                "geometry_msgs/msg/Transform", translation=translation, rotation=rotation
            )
            transforms.append(
                self._new(
                    "geometry_msgs/msg/TransformStamped",
                    header=self._header(stamp_ns, FRAMES["map"]),
                    child_frame_id=child,
                    transform=transform,
                )
            )
        return self._new("tf2_msgs/msg/TFMessage", transforms=transforms)

    def text(self, text: str) -> Any:
        """``std_msgs/String``."""
        return self._new("std_msgs/msg/String", data=text)

    def landmarks(self, stamp_ns: int, landmarks: NDArray[np.float64]) -> Any:
        """``geometry_msgs/PoseArray``: the landmarks ``(N, 3)`` (metres), map frame."""
        poses = [self._pose(x, y, 0.0, z) for x, y, z in np.asarray(landmarks, float).tolist()]
        return self._new(
            "geometry_msgs/msg/PoseArray", header=self._header(stamp_ns, FRAMES["map"]), poses=poses
        )

    def room(self, stamp_ns: int, room: NDArray[np.float64]) -> Any:
        """``geometry_msgs/PolygonStamped``: the room's floor ``(width, depth)`` (metres)."""
        w, d = (float(v) for v in room[:2])
        corners = [
            self._new("geometry_msgs/msg/Point32", x=x, y=y)
            for x, y in ((0.0, 0.0), (w, 0.0), (w, d), (0.0, d))
        ]
        polygon = self._new("geometry_msgs/msg/Polygon", points=corners)
        return self._new(
            "geometry_msgs/msg/PolygonStamped",
            header=self._header(stamp_ns, FRAMES["map"]),
            polygon=polygon,
        )


_NUMPY = {
    "bool": np.bool_,
    "byte": np.uint8,
    "char": np.uint8,
    "int8": np.int8,
    "uint8": np.uint8,
    "int16": np.int16,
    "uint16": np.uint16,
    "int32": np.int32,
    "uint32": np.uint32,
    "int64": np.int64,
    "uint64": np.uint64,
    "float32": np.float32,
    "float64": np.float64,
}
