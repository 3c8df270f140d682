"""``radial-ibvs record``: a policy's episodes written as a ROS 2 bag (MCAP storage).

Each episode's every control step becomes messages of standard types on the topics of
:data:`~radial_ibvs_agents.bags.messages.TOPICS`, stamped at the control period, so Foxglove
and ``ros2 bag play`` play it at its speed: the frames the detector read (when the env
renders, ``measurement="detected"``), the image points, the command, the true pose and the
goal, the errors and the episode's info. Episodes follow each other in time, one second
apart. The bag is a rosbag2 folder (``metadata.yaml`` and one ``.mcap`` file, which Foxglove
opens); it is written under a temporary name and moved into place when complete.
"""

from __future__ import annotations

import json
import math
import shutil
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from radial_ibvs_agents.bags.messages import FRAMES, TOPICS, Messages

__all__ = ["RecordedEpisode", "record_episodes", "twist_of"]

#: time between two recorded episodes, nanoseconds
EPISODE_GAP_NS = 1_000_000_000


@dataclass(frozen=True)
class RecordedEpisode:
    """What one recorded episode gave (the bag holds the rest)."""

    seed: int
    steps: int
    success: bool
    end: str
    position_error_m: float
    heading_error_deg: float


def twist_of(config: Any, action: Any) -> tuple[float, float]:
    """Return the command an action means: ``(v, omega)``, m/s and rad/s, as the env takes it.

    Parameters
    ----------
    config
        The env's :class:`~radial_ibvs_gym.envs.config.ParkingConfig`.
    action
        ``(2,)`` the policy's action (clipped to [-1, 1] as the env clips it).
    """
    from radial_ibvs_gym.envs import rules

    v, omega = rules.twist_commands(rules.real_actions(action).reshape(1, 2), config)[0]
    return float(v), float(omega)


def _end(info: Mapping[str, Any], truncated: bool) -> str:
    if info.get("is_success"):
        return "success"
    if info.get("collision"):
        return "collision"
    if info.get("lost"):
        return "lost"
    return "time-out" if truncated else "running"


class _Bag:
    """A rosbag2 writer whose connections open at their first message."""

    def __init__(self, writer: Any, messages: Messages) -> None:
        self.writer, self.messages = writer, messages
        self.connections: dict[str, Any] = {}

    def write(self, topic: str, stamp_ns: int, message: Any) -> None:
        if topic not in self.connections:
            msgtype = TOPICS[topic][0]
            self.connections[topic] = self.writer.add_connection(
                topic, msgtype, typestore=self.messages.store
            )
        self.writer.write(self.connections[topic], stamp_ns, self.messages.serialize(message))


def record_episodes(
    policy_name: str,
    out: Path | str,
    scenario: str = "paper-sim",
    *,
    episodes: int = 1,
    seed: int = 0,
    task: int | None = None,
    env_kwargs: Mapping[str, Any] | None = None,
    max_steps: int = 600,
    trust_model: bool = False,
    progress: bool = True,
) -> list[RecordedEpisode]:
    """Run ``episodes`` episodes of a policy and write them as one ROS 2 bag at ``out``.

    Parameters
    ----------
    policy_name
        A policy name or model directory (:func:`radial_ibvs_agents.make_policy`).
    out
        The bag's folder (a rosbag2 bag with MCAP storage); it must not exist.
    scenario, task, env_kwargs
        The env (``RadialIBVS/Parking-v0``); ``env_kwargs`` ``measurement="detected"``
        records the rendered frames the detector read.
    episodes, seed
        Episode ``k`` is reset with ``seed + k``.
    max_steps
        Step budget per episode.
    trust_model
        Allow a pickled ``model.zip`` (:func:`radial_ibvs_agents.learned.load`).
    progress
        A progress bar over the steps.

    Returns
    -------
    list of RecordedEpisode
        One per episode.

    Raises
    ------
    ModuleNotFoundError
        Without the ``[ros]`` extra (``rosbags``).
    ValueError
        For an existing ``out``, a bad count, or an env that is not ``Parking-v0``.
    """
    try:
        from rosbags.rosbag2 import StoragePlugin, Writer
    except ModuleNotFoundError as error:  # pragma: no cover - the extra is missing
        raise ModuleNotFoundError(
            "recording ROS 2 bags needs the [ros] extra: pip install 'radial_ibvs_gym[ros]'"
        ) from error
    from tqdm.auto import tqdm

    from radial_ibvs_agents import make_policy
    from radial_ibvs_agents.rollouts import make_env
    from radial_ibvs_gym.geometry import wrap_angle

    out = Path(out)
    if out.exists():
        raise ValueError(f"--out {str(out)!r} exists: a bag is written into a new folder")
    if episodes < 1 or max_steps < 1:
        raise ValueError(f"episodes and max_steps must be positive, got {episodes}, {max_steps}")
    policy = make_policy(policy_name, trust_pickle=trust_model)
    overrides = {**(env_kwargs or {}), **({"task": task} if task is not None else {})}
    env = make_env(policy, scenario, overrides)
    base: Any = env.unwrapped
    if not hasattr(base, "episode_setup"):
        env.close()
        raise ValueError(f"record runs RadialIBVS/Parking-v0 policies; {policy_name!r} runs {env}")
    config = base.config
    dt_ns = round(config.control_dt * 1e9)
    messages = Messages()
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.", dir=out.parent))
    partial = staging / out.name  # the .mcap inside is named after the bag
    summary: list[RecordedEpisode] = []
    bar = tqdm(total=episodes * max_steps, desc="record", unit="step", disable=not progress)
    try:
        with Writer(partial, version=9, storage_plugin=StoragePlugin.MCAP) as writer:
            bag = _Bag(writer, messages)
            meta = {
                "policy": policy_name,
                "scenario": scenario,
                "env_kwargs": json.dumps(dict(overrides), sort_keys=True, default=str),
                "control_dt": repr(config.control_dt),
                "seed": str(seed),
            }
            for key, value in meta.items():
                writer.set_custom_data(f"radial_ibvs.{key}", value)
            start_ns = 0
            for k in range(episodes):
                episode_seed = seed + k
                obs, info = env.reset(seed=episode_seed)
                setup = base.episode_setup
                ep = setup.episode
                bag.write("/landmarks", start_ns, messages.landmarks(start_ns, ep.landmarks))
                bag.write("/room", start_ns, messages.room(start_ns, np.asarray(ep.room)))
                frames = base.detected_frames
                if "goal" in frames:
                    goal_image = messages.image(start_ns, frames["goal"])
                    bag.write("/camera/goal_image", start_ns, goal_image)
                goal_points = messages.points(setup.goal_points, setup.goal_visible)
                bag.write("/goal_image_points", start_ns, goal_points)
                if setup.goal_frames is not None:  # the goal image averaged noisy frames
                    for shot, seen in zip(*setup.goal_frames, strict=True):
                        bag.write("/goal_image_frames", start_ns, messages.points(shot, seen))
                poses = [np.asarray(info["robot_pose"], dtype=np.float64)]
                state, episode_start = None, np.ones(1, dtype=bool)
                step, terminated, truncated = 0, False, False
                while True:
                    t = start_ns + step * dt_ns
                    pose = poses[-1]
                    if step == 0:
                        v = omega = 0.0
                    else:  # the unicycle's constant (v, omega) that moves the last pose here
                        d = pose - poses[-2]
                        turn = float(wrap_angle(d[2]))
                        middle = poses[-2][2] + 0.5 * turn  # a chord along the mid heading
                        along = math.cos(middle) * d[0] + math.sin(middle) * d[1]
                        sinc = math.sin(0.5 * turn) / (0.5 * turn) if turn else 1.0
                        v = along / (sinc * config.control_dt)
                        omega = turn / config.control_dt
                    frames = base.detected_frames
                    if "current" in frames:
                        bag.write("/camera/image", t, messages.image(t, frames["current"]))
                    bag.write("/image_points", t, messages.points(*base.image_points))
                    bag.write("/odom", t, messages.odometry(t, pose, v, omega))
                    goal = np.asarray(info["goal_pose"], dtype=np.float64)
                    tf = messages.tf(t, {FRAMES["robot"]: pose, FRAMES["goal"]: goal})
                    bag.write("/tf", t, tf)
                    errors = [float(info["position_error_m"]), float(info["heading_error_deg"])]
                    bag.write("/errors", t, messages.values(errors, "position_m,heading_deg"))
                    ending = terminated or truncated or step >= max_steps
                    end = _end(info, truncated or step >= max_steps) if ending else "running"
                    record = {
                        "episode": k, "seed": episode_seed, "step": step,
                        "position_error_m": errors[0], "heading_error_deg": errors[1],
                        "reached": bool(info.get("reached", False)),
                        "is_success": bool(info.get("is_success", False)),
                        "collision": bool(info.get("collision", False)),
                        "lost": bool(info.get("lost", False)), "end": end,
                    }  # fmt: skip
                    bag.write("/episode_info", t, messages.text(json.dumps(record)))
                    if ending:
                        break
                    action, state = policy.predict(obs, state, episode_start, deterministic=True)
                    episode_start = np.zeros(1, dtype=bool)
                    bag.write("/cmd_vel", t, messages.twist(*twist_of(config, action)))
                    obs, _, terminated, truncated, info = env.step(action)
                    poses.append(np.asarray(info["robot_pose"], dtype=np.float64))
                    step += 1
                    bar.update(1)
                summary.append(
                    RecordedEpisode(
                        seed=episode_seed, steps=step, success=bool(info.get("is_success")),
                        end=end, position_error_m=errors[0], heading_error_deg=errors[1],
                    )
                )  # fmt: skip
                start_ns = t + EPISODE_GAP_NS
        partial.rename(out)
    finally:
        bar.close()
        env.close()
        shutil.rmtree(staging, ignore_errors=True)
    return summary
