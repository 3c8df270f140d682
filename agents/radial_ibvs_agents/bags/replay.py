"""``radial-ibvs replay``: a recording's frames through the pixel pipeline and a policy.

What a robot's owner runs before closing the loop: each frame of a bag's image topic goes
through the pipeline of ``measurement="detected"`` (the mirror border fitted once on the goal
image, beacon detection, tracking, matching,
:class:`~radial_ibvs_gym.vision.pipeline.DetectedPoints`), the observation is built as the
env builds it (:func:`radial_ibvs_gym.envs.observation.observation`), and an image-only policy
gives the command that frame would send. The commands are written beside the detections, as a
ROS 2 bag and a CSV.

A recording has no true pose: the landmarks of the goal image and of the first frame are
labelled from a landmark map and the poses of those two images (the bag's ``/landmarks``,
``/odom`` and ``/tf`` where ``radial-ibvs record`` wrote them, or the caller's), and the goal
depths come from the same map. A policy that predicts from the robot's motion (``pbvs-ekf``)
predicts over each interval to the next frame's stamp (its ``control_dt``), not a fixed period.
A dropped frame (an interval over 1.5 periods) is measured as nothing seen: the tracked
landmarks coast, as after a frame without beacons. Frames out of order, a missing topic or
another encoding than ``mono8`` are named errors.

The bag is data a user hands over: read with the ``mcap`` library from its index, every
record and chunk bounded (:data:`MAX_RECORD_BYTES`), the images' size bounded
(:data:`MAX_FRAME_PIXELS`), the frames counted (:data:`MAX_FRAMES`); nothing in it is run.
"""

from __future__ import annotations

import csv
import inspect
import io
import json
import math
import shutil
import struct
import tempfile
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_agents.bags.labels import read_goal_image, read_labels
from radial_ibvs_agents.bags.messages import TOPICS, Messages
from radial_ibvs_agents.bags.record import twist_of

__all__ = [
    "MAX_FRAMES",
    "MAX_FRAME_PIXELS",
    "MAX_RECORD_BYTES",
    "BagError",
    "Replay",
    "replay_bag",
]

#: the largest record or chunk (uncompressed) a bag may hold, bytes
MAX_RECORD_BYTES = 256 * 2**20
#: the largest frame, pixels (the env's largest rendered frame is 2048 x 2048)
MAX_FRAME_PIXELS = 2048 * 2048
#: frames of one replay
MAX_FRAMES = 100_000
#: an interval this many periods long or more drops the frames between
DROPPED = 1.5
#: the outputs' topics beside /cmd_vel, /image_points and /goal_image_points
DETECTION_TOPIC = "/detection"


class BagError(ValueError):
    """A bag that cannot be replayed; the message names the file, topic and value."""


@dataclass
class Replay:
    """What a replay gave, frame by frame (the output bag and CSV hold the same)."""

    stamps_ns: NDArray[np.int64]
    commands: NDArray[np.float64]  # (K, 2): v (m/s), omega (rad/s)
    points: NDArray[np.float64]  # (K, N, 2)
    visible: NDArray[np.bool_]  # (K, N)
    statuses: list[str] = field(default_factory=list)
    dropped: int = 0


@dataclass
class _Frame:
    stamp_ns: int
    log_ns: int
    image: NDArray[np.uint8]


def _mcap_path(bag: Path) -> Path:
    if bag.is_file():
        return bag
    if not bag.is_dir():
        raise BagError(f"{bag}: no such bag (a rosbag2 folder or an .mcap file)")
    files = sorted(bag.glob("*.mcap"))
    if len(files) != 1:
        raise BagError(f"{bag}: a rosbag2 folder with one .mcap file, found {len(files)}")
    return files[0]


def _stamp(header: Any) -> int:
    return int(header.stamp.sec) * 1_000_000_000 + int(header.stamp.nanosec)


def _image(path: Path, topic: str, k: int, message: Any) -> NDArray[np.uint8]:
    """Return a ``sensor_msgs/Image``'s grey levels, checked before any copy."""
    where = f"{path}: {topic}[{k}]"
    if message.encoding not in ("mono8", "8UC1"):
        raise BagError(f"{where}: encoding {message.encoding!r}; replay reads mono8 frames")
    height, width, step = int(message.height), int(message.width), int(message.step)
    if not (0 < height and 0 < width and height * width <= MAX_FRAME_PIXELS):
        raise BagError(f"{where}: a {height} x {width} frame (at most {MAX_FRAME_PIXELS} pixels)")
    data = np.frombuffer(bytes(message.data), dtype=np.uint8)
    if step < width or len(data) != height * step:
        raise BagError(f"{where}: {len(data)} bytes for {height} rows of step {step}")
    return np.ascontiguousarray(data.reshape(height, step)[:, :width])


class _Reader:
    """An indexed MCAP file, its records bounded, its messages decoded (ROS 2 CDR)."""

    def __init__(self, path: Path) -> None:
        try:
            from mcap.exceptions import McapError
            from mcap.reader import SeekingReader
            from mcap_ros2.decoder import DecoderFactory
        except ModuleNotFoundError as error:  # pragma: no cover - the extra is missing
            raise ModuleNotFoundError(
                "replaying ROS 2 bags needs the [ros] extra: pip install 'radial_ibvs_gym[ros]'"
            ) from error
        self.path = path
        self._stream = path.open("rb")
        try:
            self._reader = SeekingReader(
                self._stream,
                validate_crcs=True,
                decoder_factories=[DecoderFactory()],
                record_size_limit=MAX_RECORD_BYTES,
            )
            summary = self._reader.get_summary()
        except (McapError, struct.error, EOFError, ValueError) as error:
            self._stream.close()
            raise BagError(f"{path}: not a readable MCAP file ({error})") from None
        if summary is None:
            self._stream.close()
            raise BagError(f"{path}: the MCAP file has no index (summary); re-index it first")
        for chunk in summary.chunk_indexes:
            if chunk.uncompressed_size > MAX_RECORD_BYTES:
                self._stream.close()
                raise BagError(
                    f"{path}: a chunk of {chunk.uncompressed_size} bytes uncompressed (at most "
                    f"{MAX_RECORD_BYTES})"
                )
        self.topics = {c.topic for c in summary.channels.values()}
        self.counts = {
            summary.channels[cid].topic: n
            for cid, n in (
                summary.statistics.channel_message_counts if summary.statistics else {}
            ).items()
        }

    def close(self) -> None:
        self._stream.close()

    def messages(self, topic: str) -> Iterator[tuple[int, Any]]:
        """``(log time, decoded message)`` of ``topic``, in the file's order."""
        if topic not in self.topics:
            raise BagError(f"{self.path}: no topic {topic!r}; the bag has {sorted(self.topics)}")
        if self.counts.get(topic, 0) > MAX_FRAMES:
            raise BagError(f"{self.path}: {topic} holds {self.counts[topic]} messages (at most "
                           f"{MAX_FRAMES})")  # fmt: skip
        for _, _, message, decoded in self._reader.iter_decoded_messages(
            topics=[topic], log_time_order=False
        ):
            yield message.log_time, decoded


def _frames(reader: _Reader, topic: str) -> list[_Frame]:
    frames: list[_Frame] = []
    for k, (log_ns, message) in enumerate(reader.messages(topic)):
        frame = _Frame(_stamp(message.header), log_ns, _image(reader.path, topic, k, message))
        if frames and frame.stamp_ns <= frames[-1].stamp_ns:
            raise BagError(
                f"{reader.path}: {topic}[{k}] is stamped {frame.stamp_ns} ns, not after the "
                f"frame before it ({frames[-1].stamp_ns} ns): frames out of order"
            )
        frames.append(frame)
    return frames


def _pose_at(reader: _Reader, log_ns: int, what: str) -> NDArray[np.float64]:
    """Return the robot's (``what="robot"``) or the goal's pose of the bag at ``log_ns``."""
    if what == "robot":
        for t, odom in reader.messages("/odom"):
            if t == log_ns:
                p, q = odom.pose.pose.position, odom.pose.pose.orientation
                return np.array([p.x, p.y, 2.0 * math.atan2(q.z, q.w)])
    else:
        for t, tf in reader.messages("/tf"):
            if t != log_ns:
                continue
            for transform in tf.transforms:
                if transform.child_frame_id == "goal":
                    tr, q = transform.transform.translation, transform.transform.rotation
                    return np.array([tr.x, tr.y, 2.0 * math.atan2(q.z, q.w)])
    topic = "/odom" if what == "robot" else "/tf (frame goal)"
    raise BagError(f"{reader.path}: no {topic} at {log_ns} ns; give the {what} pose instead")


def _landmarks_at(reader: _Reader, log_ns: int) -> NDArray[np.float64]:
    found = None
    for t, poses in reader.messages("/landmarks"):
        if t <= log_ns:
            found = np.array([[p.position.x, p.position.y, p.position.z] for p in poses.poses])
    if found is None or found.ndim != 2 or len(found) == 0:
        raise BagError(f"{reader.path}: no /landmarks before {log_ns} ns; give a map instead")
    return found


def _executed(reader: _Reader, topic: str, frames_ns: list[int]) -> NDArray[np.float64]:
    """Return the command in effect at each frame: the last ``topic`` message, ``(K, 2)``."""
    stamps, twists = [], []
    for t, twist in reader.messages(topic):
        stamps.append(t)
        twists.append((float(twist.linear.x), float(twist.angular.z)))
    order = np.argsort(np.asarray(stamps, dtype=np.int64), kind="stable")
    times = np.asarray(stamps, dtype=np.int64)[order]
    values = np.asarray(twists, dtype=np.float64).reshape(-1, 2)[order]
    at = np.searchsorted(times, np.asarray(frames_ns, dtype=np.int64), side="right") - 1
    commands = np.where((at >= 0)[:, None], values[np.maximum(at, 0)], 0.0)
    if not np.isfinite(commands).all():
        raise BagError(f"{reader.path}: {topic} holds a command that is not finite")
    return commands


def replay_bag(
    bag: Path | str,
    policy_name: str,
    out: Path | str,
    scenario: str = "paper-lab",
    *,
    env_kwargs: Mapping[str, Any] | None = None,
    image_topic: str = "/camera/image",
    goal_image_topic: str = "/camera/goal_image",
    episode: int = 0,
    landmarks: NDArray[np.float64] | None = None,
    start: NDArray[np.float64] | None = None,
    goal: NDArray[np.float64] | None = None,
    goal_image: Path | str | None = None,
    goal_at: float | None = None,
    labels: Path | str | None = None,
    motion: str = "policy",
    command_topic: str = "/cmd_vel",
    trust_model: bool = False,
    progress: bool = True,
) -> Replay:
    """Replay a bag's frames through the pixel pipeline and a policy; write the commands.

    Parameters
    ----------
    bag
        A rosbag2 folder with one ``.mcap`` file, or the ``.mcap`` file.
    policy_name
        An image-only policy (name or model directory).
    out
        The output bag's folder (new): ``/cmd_vel``, the detections, and ``commands.csv``.
    scenario, env_kwargs
        The env the policy's observation follows (its camera, beacons, slots, goal depths).
    image_topic, goal_image_topic
        The frames, and the goal images (one per recorded episode).
    episode
        Which goal image, and the frames from it to the next.
    landmarks, start, goal
        The map ``(N, 3)`` (metres), the first frame's pose and the goal image's pose
        ``(x, y, yaw)``; default: the bag's ``/landmarks``, ``/odom`` and ``/tf``.
    goal_image, goal_at
        The goal image from a file (a grey PNG or a ``.npy``), or the frame of
        ``image_topic`` nearest ``goal_at`` seconds after its first; then every frame of
        ``image_topic`` is replayed. Default: ``goal_image_topic``.
    labels
        A labels file (:mod:`~radial_ibvs_agents.bags.labels`): the landmarks' pixels in the
        goal image and the first frame, and the goal depths, instead of a map and poses.
    motion
        What a policy that predicts the robot's motion (``pbvs-ekf``, ``ekf-planner``)
        predicts it from: ``"policy"``, its own commands; ``"recorded"``, the command the
        robot executed, the bag's last ``command_topic`` message at each frame (a robot
        driven by something else).
    command_topic
        The executed commands (``geometry_msgs/Twist``), for ``motion="recorded"``.
    trust_model
        Allow a pickled ``model.zip``.
    progress
        A progress bar over the frames.

    Returns
    -------
    Replay
        The commands, detections and statuses, frame by frame.

    Raises
    ------
    BagError
        For a bag that cannot be replayed (named file, topic and value).
    ValueError
        For an existing ``out`` or a policy that needs more than the images.
    """
    from rosbags.rosbag2 import StoragePlugin, Writer
    from tqdm.auto import tqdm

    from radial_ibvs_agents import make_policy
    from radial_ibvs_agents.rollouts.envs import env_kwargs_for
    from radial_ibvs_gym.envs import observation as seen
    from radial_ibvs_gym.envs.config import ParkingConfig
    from radial_ibvs_gym.geometry import world_to_camera
    from radial_ibvs_gym.vision.pipeline import DetectedPoints

    bag, out = Path(bag), Path(out)
    if motion not in ("policy", "recorded"):
        raise ValueError(f"motion must be 'policy' or 'recorded', got {motion!r}")
    if out.exists():
        raise ValueError(f"--out {str(out)!r} exists: the commands are written into a new folder")
    policy = make_policy(policy_name, trust_pickle=trust_model)
    if motion == "recorded" and "executed" not in inspect.signature(policy.predict).parameters:
        raise ValueError(
            f"motion='recorded' feeds the executed commands to a policy that predicts the "
            f"robot's motion (pbvs-ekf, ekf-planner); {policy_name!r} does not"
        )
    if goal_image is not None and goal_at is not None:
        raise ValueError("give the goal image as a file or as a time, not both")
    labelled = read_labels(labels) if labels is not None else None
    reader = _Reader(_mcap_path(bag))
    try:
        frames = _frames(reader, image_topic)
        if not frames:
            raise BagError(f"{reader.path}: {image_topic} holds no frame")
        if goal_image is not None:  # a file: every frame of the topic is replayed
            goal_frame = _Frame(-1, -1, read_goal_image(goal_image, MAX_FRAME_PIXELS))
        elif goal_at is not None:  # the frame nearest that time, seconds after the first
            wanted = frames[0].stamp_ns + round(goal_at * 1e9)
            goal_frame = min(frames, key=lambda f: abs(f.stamp_ns - wanted))
        else:
            goals = _frames(reader, goal_image_topic)
            if not 0 <= episode < len(goals):
                raise BagError(f"{reader.path}: episode {episode}, but {goal_image_topic} "
                               f"holds {len(goals)} goal images")  # fmt: skip
            goal_frame = goals[episode]
            end = goals[episode + 1].log_ns if episode + 1 < len(goals) else math.inf
            frames = [f for f in frames if goal_frame.log_ns <= f.log_ns < end]
            if not frames:
                raise BagError(f"{reader.path}: no {image_topic} frame after goal image {episode}")
        size = frames[0].image.shape[0]
        if any(f.image.shape != (size, size) for f in (*frames, goal_frame)):
            raise BagError(f"{reader.path}: the frames and the goal image must be square and "
                           f"of one size")  # fmt: skip
        first = frames[0]
        if labelled is None:  # labels from the map and the two images' poses
            if landmarks is None:
                landmarks = _landmarks_at(reader, first.log_ns)
            if start is None:
                start = _pose_at(reader, first.log_ns, "robot")
            if goal is None:
                if goal_frame.log_ns < 0:
                    raise ValueError("a goal image from a file needs its pose (goal) or labels")
                goal = _pose_at(reader, goal_frame.log_ns, "goal")
        executed = None
        if motion == "recorded":
            executed = _executed(reader, command_topic, [f.log_ns for f in frames])
    finally:
        reader.close()
    kwargs = env_kwargs_for(policy, scenario, env_kwargs)
    kwargs.update(measurement="detected", image_size=size)
    config = ParkingConfig.from_kwargs(owner="radial-ibvs replay", **kwargs)
    if config.privileged or config.obs_mode != "points" or config.privileged_map:
        raise ValueError(
            f"replay runs image-only policies on image points; {policy_name!r} needs "
            f"{'the true pose' if config.privileged else 'obs_mode=' + repr(config.obs_mode)}"
        )
    scene_config = config.scenario.config
    height = scene_config.fixed_camera_height("radial-ibvs replay")
    detector = DetectedPoints(
        config.scenario.camera, config.scenario.goal_camera, height, size,
        beacon_radius=config.beacon_radius,
    )  # fmt: skip
    if labelled is not None:
        goal_labels, first_labels = labelled.goal, labelled.first
        goal_depths = labelled.goal_depths
        if config.goal_depths and goal_depths is None:
            raise ValueError(f"{labels}: {policy_name!r} needs the goal depths (goal_depths)")
    else:
        assert start is not None and goal is not None  # read from the bag above
        landmarks = np.asarray(landmarks, dtype=np.float64).reshape(-1, 3)
        goal_labels = detector.predicted(goal, "goal", landmarks)
        first_labels = detector.predicted(start, "current", landmarks)
        p = world_to_camera(landmarks, goal, height, validate=False)
        goal_depths = scene_config.depth_scale * np.hypot(p[:, 0], p[:, 1])
    goal_points, goal_visible = detector.start(
        goal_frame.image, goal_labels, first.image, first_labels
    )
    n = len(goal_labels)
    messages = Messages()
    period = config.control_dt
    limits = np.array([config.robot.max_linear_speed, config.robot.max_angular_speed])
    result = Replay(
        stamps_ns=np.array([f.stamp_ns for f in frames], dtype=np.int64),
        commands=np.zeros((len(frames), 2)),
        points=np.zeros((len(frames), n, 2)),
        visible=np.zeros((len(frames), n), dtype=bool),
    )
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    bar = tqdm(total=len(frames), desc="replay", unit="frame", disable=not progress)
    try:
        with Writer(staging / out.name, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
            connections = {
                topic: writer.add_connection(topic, TOPICS[topic][0], typestore=messages.store)
                for topic in ("/cmd_vel", "/image_points", "/goal_image_points")
            }
            connections[DETECTION_TOPIC] = writer.add_connection(
                DETECTION_TOPIC, "std_msgs/msg/String", typestore=messages.store
            )
            writer.set_custom_data("radial_ibvs.replay_of", str(bag))
            writer.set_custom_data("radial_ibvs.policy", policy_name)

            def write(topic: str, stamp: int, message: Any) -> None:
                writer.write(connections[topic], stamp, messages.serialize(message))

            write("/goal_image_points", first.stamp_ns, messages.points(goal_points, goal_visible))
            state, episode_start = None, np.ones(1, dtype=bool)
            points, visible = detector.initial()
            for k, frame in enumerate(frames):
                if k:
                    dt = (frame.stamp_ns - frames[k - 1].stamp_ns) / 1e9
                    missing = max(round(dt / period) - 1, 0) if dt >= DROPPED * period else 0
                    for _ in range(missing):  # dropped frames: nothing seen, the tracks coast
                        detector.observe_image(None)
                    result.dropped += missing
                    points, visible = detector.observe_image(frame.image)
                if hasattr(policy, "control_dt") and k + 1 < len(frames):
                    # a policy that predicts the motion until the next frame: that interval
                    policy.control_dt = (frames[k + 1].stamp_ns - frame.stamp_ns) / 1e9
                obs = seen.observation(
                    points.reshape(-1), goal_points.reshape(-1), visible,
                    goal_depths=goal_depths if config.goal_depths else None,
                    slots=config.slots,
                )  # fmt: skip
                extra = {}
                if executed is not None:
                    extra["executed"] = executed[k] / limits
                action, state = policy.predict(
                    obs, state, episode_start, deterministic=True, **extra
                )
                episode_start = np.zeros(1, dtype=bool)
                v, omega = twist_of(config, action)
                result.commands[k] = (v, omega)
                result.points[k], result.visible[k] = points, visible
                result.statuses.append(detector.status)
                write("/cmd_vel", frame.stamp_ns, messages.twist(v, omega))
                write("/image_points", frame.stamp_ns, messages.points(points, visible))
                info = {"status": detector.status, "n_tracked": int(visible.sum())}
                write(DETECTION_TOPIC, frame.stamp_ns, messages.text(json.dumps(info)))
                bar.update(1)
        table = io.StringIO()
        rows = csv.writer(table, lineterminator="\n")
        rows.writerow(["stamp_ns", "v_m_s", "omega_rad_s", "n_tracked", "status"])
        for k, stamp in enumerate(result.stamps_ns.tolist()):
            v, omega = result.commands[k].tolist()
            rows.writerow([stamp, repr(v), repr(omega), int(result.visible[k].sum()),
                           result.statuses[k]])  # fmt: skip
        (staging / out.name / "commands.csv").write_text(table.getvalue())
        (staging / out.name).rename(out)
    finally:
        bar.close()
        shutil.rmtree(staging, ignore_errors=True)
    return result
