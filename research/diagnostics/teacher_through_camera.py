"""A DAgger teacher steering by the pose the image gives: a student's ceiling through a camera.

Usage::

    python research/diagnostics/teacher_through_camera.py \
        configs/agents/dagger_student.yaml [--episodes 100] \
        [--variants ideal "noise 1 px" ...] [--teacher-kwargs '{"line_lateral_gain": 225}']

A student with the ``landmark_pose`` extractor sees the goal's pose solved from the landmarks'
bearings (:func:`radial_ibvs_agents.learned.networks.pose_layer.solve_goal_pose`), and it learns its
teacher's law on the true pose. This runs that teacher (the config's ``teacher`` and
``teacher_kwargs``, with ``--teacher-kwargs`` on top) on the solved pose instead of the true one:
the robot's pose it is handed is the goal's pose composed with the solved relative pose. The map and
the goal's pose stay privileged (its path far from the goal); near the goal, where the episodes are
decided, it sees what the student sees, exactly, through the camera's imperfections. It runs the
``imperfect`` suite's variants (``ideal``: the same rooms through the ideal camera) on the suite's
held-out seeds and prints how many park (2 cm / 2 deg) and where the failures stopped. A memoryless
student of the teacher inherits those failures, so this is a ceiling of sorts: what distilling that
law can reach through that camera. ``research/diagnostics/pose_layer_errors.py`` shows how far the
solved pose is off through the same cameras.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from _common import imperfect_cameras, solve_one  # research/diagnostics/_common.py

from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.experiments.suites import HELD_OUT_SEED
from radial_ibvs_agents.learned.dagger.distill_config import PRIVILEGED, load_dagger_config
from radial_ibvs_agents.rollouts import run_episode


def solved_robot_pose(obs: dict[str, Any]) -> np.ndarray | None:
    """Return the robot's world pose ``(x, y, yaw)`` the image gives, or ``None``.

    The goal's pose (privileged) composed with the inverse of the relative pose solved from
    the current and goal bearings and the goal depths (metres, radians).
    """
    goal_points = np.asarray(obs["goal_points"]).reshape(-1, 2)
    pose, valid = solve_one(
        obs["points"], obs["visible"], goal_points, np.linalg.norm(goal_points, axis=1),
        obs["goal_depths"],
    )  # fmt: skip
    if not valid:
        return None
    tx, ty, c, s = (float(v) for v in pose)
    gx, gy, gyaw = (float(v) for v in obs["goal_pose"])
    yaw = gyaw - math.atan2(s, c)  # the goal's heading relative to the robot's is atan2(s, c)
    return np.array(
        [
            gx - (math.cos(yaw) * tx - math.sin(yaw) * ty),
            gy - (math.sin(yaw) * tx + math.cos(yaw) * ty),
            yaw,
        ]
    )


class ImageTeacher:
    """The teacher, handed the robot's pose solved from the image (the true one if unsolved)."""

    env_kwargs = PRIVILEGED

    def __init__(self, teacher: Any) -> None:
        self.teacher = teacher

    def predict(
        self, obs: dict[str, Any], state: Any, episode_start: Any, deterministic: bool = True
    ) -> tuple[np.ndarray, Any]:
        """The teacher's action for ``obs`` with the robot's pose replaced by the solved one."""
        seen = dict(obs)
        solved = solved_robot_pose(obs)
        if solved is not None:
            seen["robot_pose"] = solved
        return self.teacher.predict(seen, state, episode_start, deterministic)


def _mapping(text: str) -> dict[str, Any]:
    """``--teacher-kwargs``: a JSON object."""
    try:
        value = json.loads(text)
    except json.JSONDecodeError as error:
        raise argparse.ArgumentTypeError(f"not JSON ({error}): {text!r}") from None
    if not isinstance(value, dict):
        raise argparse.ArgumentTypeError(f"expected a JSON object, got {text!r}")
    return value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("config", type=Path)
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument(
        "--variants", nargs="+", choices=list(imperfect_cameras()),
        default=["ideal", "noise 1 px", "pp (2, -1) px, fy +1 %", "all together"],
    )  # fmt: skip
    parser.add_argument("--teacher-kwargs", type=_mapping, default={})
    args = parser.parse_args()
    config = load_dagger_config(args.config)
    kwargs = {**config.teacher_kwargs, **args.teacher_kwargs}
    env_kwargs = {**config.env_kwargs, "physics": "kinematic"}
    chosen = imperfect_cameras(args.variants)
    print(f"teacher {config.teacher} {kwargs}")
    for label, overrides in chosen.items():
        env = gym.make(config.env_id, **{**env_kwargs, **overrides, **PRIVILEGED})
        policy = ImageTeacher(make_analytic(config.teacher, **kwargs))
        parked, stops = 0, []
        for k in range(args.episodes):
            info = run_episode(policy, env, seed=HELD_OUT_SEED + k).info
            if info["is_success"]:
                parked += 1
            else:
                stops.append((info["position_error_m"] * 100.0, info["heading_error_deg"]))
        env.close()
        where = ""
        if stops:
            cm, deg = np.median(np.asarray(stops), axis=0)
            where = f"; the others stop a median {cm:.1f} cm and {deg:.0f} deg off"
        print(f"{label}: {parked} / {args.episodes} park{where}")


if __name__ == "__main__":
    main()
