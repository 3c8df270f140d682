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
A dropped frame (an interval of 1.5 periods or more) is measured as nothing seen: the tracked
landmarks coast, as after a frame without beacons; a gap of more than :data:`MAX_DROPPED`
frames is an error. Frames out of order, a missing topic, another message type or encoding
than ``sensor_msgs/Image`` in ``mono8`` are named errors.

The bag is data a user hands over, read by :class:`~radial_ibvs_agents.bags.bag_reader.BagReader`
(every record and chunk bounded, its decompression too, the messages decoded with the trusted
ROS 2 types); the images' size is bounded (:data:`MAX_FRAME_PIXELS`) and the frames counted
(:data:`MAX_FRAMES`). The frames are read twice, once for their time stamps and once, one at a
time, for the replay: a long recording is never held in memory. Nothing in a bag is run.

About 460 lines: ``replay_bag`` and the readers of the few topics it needs (frames, poses, the
map, the executed commands), which share its bounds (``MAX_FRAME_PIXELS``, ``MAX_FRAMES``); the
bag's bytes are read in :mod:`~radial_ibvs_agents.bags.bag_reader`.
"""

from __future__ import annotations

import csv
import inspect
import io
import json
import math
import shutil
import tempfile
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_agents.bags.bag_reader import BagError, BagReader, mcap_path
from radial_ibvs_agents.bags.labels import read_goal_image, read_labels
from radial_ibvs_agents.bags.messages import TOPICS, Messages
from radial_ibvs_agents.bags.record import twist_of

__all__ = [
    "MAX_DROPPED",
    "MAX_FRAMES",
    "MAX_FRAME_PIXELS",
    "BagError",
    "Replay",
    "replay_bag",
]

#: the largest frame, pixels (the env's largest rendered frame is 2048 x 2048)
MAX_FRAME_PIXELS = 2048 * 2048
#: frames of one replay (each read twice, never held all at once)
MAX_FRAMES = 100_000
#: an interval this many periods long or more drops the frames between
DROPPED = 1.5
#: the most frames a gap may drop: a longer one is a break in the recording, an error
MAX_DROPPED = 100
#: the outputs' topics beside /cmd_vel, /image_points and /goal_image_points
DETECTION_TOPIC = "/detection"
IMAGE = "sensor_msgs/msg/Image"


@dataclass
class Replay:
    """What a replay gave, frame by frame (the output bag and CSV hold the same)."""

    stamps_ns: NDArray[np.int64]
    commands: NDArray[np.float64]  # (K, 2): v (m/s), omega (rad/s)
    points: NDArray[np.float64]  # (K, N, 2)
    visible: NDArray[np.bool_]  # (K, N)
    statuses: list[str] = field(default_factory=list)
    dropped: int = 0


@dataclass(frozen=True)
class _Frame:
    """A frame of a topic: its index there, its header stamp and log time, nanoseconds."""

    index: int
    stamp_ns: int
    log_ns: int
    shape: tuple[int, int]


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
    data = np.asarray(message.data, dtype=np.uint8).reshape(-1)
    if step < width or len(data) != height * step:
        raise BagError(f"{where}: {len(data)} bytes for {height} rows of step {step}")
    return np.ascontiguousarray(data.reshape(height, step)[:, :width])


def _frames(reader: BagReader, topic: str) -> list[_Frame]:
    """Every frame of ``topic``, checked, in the file's order (the pixels are not kept)."""
    frames: list[_Frame] = []
    for k, log_ns, message in reader.messages(topic, IMAGE):
        if k >= MAX_FRAMES:
            raise BagError(f"{reader.path}: {topic} holds over {MAX_FRAMES} frames")
        shape = _image(reader.path, topic, k, message).shape
        frame = _Frame(k, _stamp(message.header), log_ns, (shape[0], shape[1]))
        if frames and frame.stamp_ns <= frames[-1].stamp_ns:
            raise BagError(
                f"{reader.path}: {topic}[{k}] is stamped {frame.stamp_ns} ns, not after the "
                f"frame before it ({frames[-1].stamp_ns} ns): frames out of order"
            )
        frames.append(frame)
    return frames


def _images(
    reader: BagReader, topic: str, wanted: list[_Frame]
) -> Iterator[tuple[_Frame, NDArray[np.uint8]]]:
    """Yield the pixels of the ``wanted`` frames of ``topic``, one at a time, in file order."""
    pending = iter(wanted)
    frame = next(pending, None)
    for k, _, message in reader.messages(topic, IMAGE):
        if frame is None:
            return
        if k == frame.index:
            yield frame, _image(reader.path, topic, k, message)
            frame = next(pending, None)


def _image_of(reader: BagReader, topic: str, frame: _Frame) -> NDArray[np.uint8]:
    return next(_images(reader, topic, [frame]))[1]


def _pose_at(reader: BagReader, log_ns: int, what: str, within_ns: int) -> NDArray[np.float64]:
    """Return the robot's or the goal's pose in the bag nearest ``log_ns``, within ``within_ns``.

    The robot's from ``/odom``, the goal's from ``/tf`` (frame ``goal``).
    """
    best: tuple[int, NDArray[np.float64]] | None = None
    if what == "robot":
        for _, t, odom in reader.messages("/odom", "nav_msgs/msg/Odometry"):
            p, q = odom.pose.pose.position, odom.pose.pose.orientation
            if abs(t - log_ns) <= within_ns and (best is None or abs(t - log_ns) < best[0]):
                best = (abs(t - log_ns), np.array([p.x, p.y, 2.0 * math.atan2(q.z, q.w)]))
    else:
        for _, t, tf in reader.messages("/tf", "tf2_msgs/msg/TFMessage"):
            if abs(t - log_ns) > within_ns or (best is not None and abs(t - log_ns) >= best[0]):
                continue
            for transform in tf.transforms:
                if transform.child_frame_id == "goal":
                    tr, q = transform.transform.translation, transform.transform.rotation
                    best = (abs(t - log_ns), np.array([tr.x, tr.y, 2.0 * math.atan2(q.z, q.w)]))
    if best is None or not np.isfinite(best[1]).all():
        topic = "/odom" if what == "robot" else "/tf (frame goal)"
        raise BagError(
            f"{reader.path}: no {topic} within {within_ns} ns of {log_ns} ns; give the {what} "
            f"pose (--start, --goal) or labels instead"
        )
    return best[1]


def _landmarks_at(reader: BagReader, log_ns: int) -> NDArray[np.float64]:
    found = None
    for _, t, poses in reader.messages("/landmarks", "geometry_msgs/msg/PoseArray"):
        if t <= log_ns:
            found = np.array([[p.position.x, p.position.y, p.position.z] for p in poses.poses])
    if found is None or found.ndim != 2 or len(found) == 0 or not np.isfinite(found).all():
        raise BagError(f"{reader.path}: no /landmarks before {log_ns} ns; give labels instead")
    return found


def _executed(reader: BagReader, topic: str, frames_ns: list[int]) -> NDArray[np.float64]:
    """Return the command in effect at each frame: the last ``topic`` message, ``(K, 2)``."""
    stamps, twists = [], []
    for _, t, twist in reader.messages(topic, "geometry_msgs/msg/Twist"):
        stamps.append(t)
        twists.append((float(twist.linear.x), float(twist.angular.z)))
    if not stamps:
        raise BagError(f"{reader.path}: {topic} holds no command")
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
    if goal_at is not None and not (math.isfinite(goal_at) and goal_at >= 0):
        raise ValueError(f"goal_at must be a time in seconds, 0 or more, got {goal_at!r}")
    labelled = read_labels(labels) if labels is not None else None
    reader = BagReader(mcap_path(bag))
    staging: Path | None = None
    try:
        frames = _frames(reader, image_topic)
        if not frames:
            raise BagError(f"{reader.path}: {image_topic} holds no frame")
        goal_log_ns: int | None = None  # where the goal image was taken, if from the bag
        if goal_image is not None:  # a file: every frame of the topic is replayed
            goal_pixels = read_goal_image(goal_image, MAX_FRAME_PIXELS)
        elif goal_at is not None:  # the frame nearest that time, seconds after the first
            wanted = frames[0].stamp_ns + round(goal_at * 1e9)
            nearest = min(frames, key=lambda f: abs(f.stamp_ns - wanted))
            goal_pixels, goal_log_ns = _image_of(reader, image_topic, nearest), nearest.log_ns
        else:
            goals = _frames(reader, goal_image_topic)
            if not 0 <= episode < len(goals):
                raise BagError(f"{reader.path}: episode {episode}, but {goal_image_topic} "
                               f"holds {len(goals)} goal images")  # fmt: skip
            goal_pixels = _image_of(reader, goal_image_topic, goals[episode])
            end = goals[episode + 1].log_ns if episode + 1 < len(goals) else math.inf
            frames = [f for f in frames if goals[episode].log_ns <= f.log_ns < end]
            if not frames:
                raise BagError(f"{reader.path}: no {image_topic} frame after goal image {episode}")
        size = frames[0].shape[0]
        if any(f.shape != (size, size) for f in frames) or goal_pixels.shape != (size, size):
            raise BagError(f"{reader.path}: the frames and the goal image must be square and "
                           f"of one size")  # fmt: skip
        kwargs = env_kwargs_for(policy, scenario, env_kwargs)
        kwargs.update(measurement="detected", image_size=size)
        config = ParkingConfig.from_kwargs(owner="radial-ibvs replay", **kwargs)
        if config.privileged or config.obs_mode != "points" or config.privileged_map:
            needs = "the true pose" if config.privileged else "obs_mode=" + repr(config.obs_mode)
            raise ValueError(
                f"replay runs image-only policies on image points; {policy_name!r} needs {needs}"
            )
        period = config.control_dt
        half = round(period * 5e8)  # a pose within half a period of an image's time
        first = frames[0]
        if labelled is None:  # labels from the map and the two images' poses
            if landmarks is None:
                landmarks = _landmarks_at(reader, first.log_ns)
            if start is None:
                start = _pose_at(reader, first.log_ns, "robot", half)
            if goal is None:
                if goal_log_ns is None and goal_image is not None:
                    raise ValueError("a goal image from a file needs its pose (goal) or labels")
                goal = (  # a goal frame of the image topic: where the robot stood then
                    _pose_at(reader, goal_log_ns, "robot", half)
                    if goal_log_ns is not None
                    else _pose_at(reader, goals[episode].log_ns, "goal", half)
                )
        executed = None
        if motion == "recorded":
            executed = _executed(reader, command_topic, [f.log_ns for f in frames])
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
        images = _images(reader, image_topic, frames)
        _, first_pixels = next(images)
        goal_points, goal_visible = detector.start(
            goal_pixels, goal_labels, first_pixels, first_labels
        )
        n = len(goal_labels)
        messages = Messages()
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
        with (
            bar,
            Writer(staging / out.name, version=9, storage_plugin=StoragePlugin.MCAP) as writer,
        ):
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
                    _, pixels = next(images)
                    gap = (frame.stamp_ns - frames[k - 1].stamp_ns) / 1e9
                    missing = max(round(gap / period) - 1, 0) if gap >= DROPPED * period else 0
                    if missing > MAX_DROPPED:
                        raise BagError(
                            f"{reader.path}: {image_topic}[{frame.index}] comes {gap:.3g} s after "
                            f"the frame before it: {missing} frames dropped, more than "
                            f"{MAX_DROPPED} (a break in the recording: replay each part alone)"
                        )
                    for _ in range(missing):  # dropped frames: nothing seen, the tracks coast
                        detector.observe_image(None)
                    result.dropped += missing
                    points, visible = detector.observe_image(pixels)
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
        reader.close()
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)
    return result
