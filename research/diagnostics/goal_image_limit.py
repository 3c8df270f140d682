"""Where the goal image puts the goal: the limit of a policy that settles where images match.

Usage::

    python research/diagnostics/goal_image_limit.py [--episodes 100] \
        [--variants ideal "noise 1 px" ...] [--teacher-of configs/agents/CONFIG.yaml] \
        [--pose-noise 0.01]

An image-based policy knows the goal only through the goal image, taken once per episode through the
episode's camera. With pixel noise that image is one noisy draw, and the pose it shows is not quite
the goal: the *image goal* is the pose whose noise-free image through the same camera matches the
goal image best. Found here by a fixed point: from the true goal, solve the goal image's pose
relative to the current noise-free image
(:func:`radial_ibvs_agents.learned.networks.pose_layer.solve_one`, the student's first layer), move
there, and repeat until the step is under a micrometre. A calibration error alone moves no goal (the
goal image goes through the same camera, so the error cancels there); noise does.

For the ``imperfect`` suite's variants (``ideal``: the same rooms through the ideal camera),
on its held-out seeds, this prints how far the image goal lies from the true one, how often
it lies within the success tolerance (2 cm / 2 deg), and how many episodes the ``planner``
parks when it is handed the true poses and the map but drives to the image goal: the limit
of a policy that settles where the images match. It is not a bound on every policy: one that
keeps moving near the image goal may cross the true tolerance, since the episode ends at the
first step within it. ``--teacher-of CONFIG`` drives with a DAgger config's teacher instead
of the planner, and ``--pose-noise M`` adds that much Gaussian noise to the position the
driver is handed every step: what a policy that does not settle may gain. It calls the env's camera
model at chosen poses (``env.unwrapped.image``): a diagnostic, not something a policy could
do.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
from _common import imperfect_cameras, solve_one  # research/diagnostics/_common.py

from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.experiments.suites import HELD_OUT_SEED
from radial_ibvs_agents.learned.dagger.distill_config import PRIVILEGED, load_dagger_config
from radial_ibvs_agents.rollouts import run_episode
from radial_ibvs_gym.geometry import relative_pose


def compose(pose: np.ndarray, relative: np.ndarray) -> np.ndarray:
    """The world pose of a frame at ``relative`` ``(t_x, t_y, cos, sin)`` from ``pose``.

    ``pose`` is ``(x, y, yaw)`` (metres, radians); ``relative`` the frame's position in the
    robot's frame and its heading relative to the robot's (what :func:`solve_one` returns).
    """
    x, y, yaw = (float(v) for v in pose)
    tx, ty, c, s = (float(v) for v in relative)
    return np.array(
        [
            x + math.cos(yaw) * tx - math.sin(yaw) * ty,
            y + math.sin(yaw) * tx + math.cos(yaw) * ty,
            yaw + math.atan2(s, c),
        ]
    )


def image_goal(env: gym.Env, iterations: int = 20) -> np.ndarray | None:
    """The pose ``(x, y, yaw)`` whose noise-free image matches the episode's goal image.

    ``env`` is a ``Parking-v0`` env just reset. ``None`` where the pose cannot be solved.
    """
    u: Any = env.unwrapped
    setup = u._setup
    pose = np.array(setup.episode.goal, dtype=np.float64)
    for _ in range(iterations):
        points, visible = u.image(setup, pose, "current", None)  # no rng: no noise
        relative, valid = solve_one(
            points, visible, setup.goal_points, setup.goal_visible, setup.goal_depths
        )
        if not valid:
            return None
        pose = compose(pose, relative)
        if math.hypot(relative[0], relative[1]) < 1e-6 and abs(relative[3]) < 1e-6:
            break
    return pose


class ToImageGoal:
    """A privileged policy (true poses, the map) driving to the image goal instead of the goal.

    ``planner`` defaults to the ``planner`` (the limit policy); ``pose_noise`` (metres, >= 0)
    adds Gaussian noise to the position it is handed at every step (seeded by ``seed``).
    """

    env_kwargs = PRIVILEGED

    def __init__(self, planner: Any = None, pose_noise: float = 0.0, seed: int = 0) -> None:
        if not (math.isfinite(pose_noise) and pose_noise >= 0.0):
            raise ValueError(f"pose_noise must be a finite number >= 0 m, got {pose_noise!r}")
        self.planner = make_analytic("planner") if planner is None else planner
        self.pose_noise = float(pose_noise)
        self.rng = np.random.default_rng(seed)
        self.goal: np.ndarray | None = None

    def predict(
        self, obs: dict[str, Any], state: Any, episode_start: Any, deterministic: bool = True
    ) -> tuple[np.ndarray, Any]:
        """The planner's action towards :attr:`goal` (the true goal where ``None``)."""
        seen = dict(obs)
        if self.goal is not None:
            seen["goal_pose"] = self.goal
        if self.pose_noise > 0.0:
            pose = np.array(obs["robot_pose"], dtype=np.float64)
            pose[:2] += self.rng.normal(0.0, self.pose_noise, 2)
            seen["robot_pose"] = pose
        return self.planner.predict(seen, state, episode_start, deterministic)


def measure(
    overrides: dict[str, Any], episodes: int, policy: ToImageGoal | None = None
) -> dict[str, Any]:
    """Image goals of ``episodes`` held-out rooms through a variant's camera, and the planner.

    Returns the offsets ``off_m`` and ``off_rad`` ``(episodes,)`` (metres, radians; ``inf``
    where unsolved), ``inside`` (within the success tolerance) and ``parked``: how many the
    planner (or ``policy``) parks driving to the image goal.
    """
    env = gym.make("RadialIBVS/Parking-v0", **{**overrides, **PRIVILEGED})
    u: Any = env.unwrapped
    policy = ToImageGoal() if policy is None else policy
    off_m, off_rad, parked = [], [], 0
    for k in range(episodes):
        env.reset(seed=HELD_OUT_SEED + k)
        found = image_goal(env)
        if found is None:
            off_m.append(math.inf)
            off_rad.append(math.inf)
        else:
            off = relative_pose(u._setup.episode.goal, found)
            off_m.append(math.hypot(off[0], off[1]))
            off_rad.append(abs(off[2]))
        policy.goal = found
        parked += bool(run_episode(policy, env, seed=HELD_OUT_SEED + k).info["is_success"])
    env.close()
    m, rad = np.asarray(off_m), np.asarray(off_rad)
    inside = int(np.sum((m <= u.success_position_m) & (rad <= u.success_heading_rad)))
    return {"off_m": m, "off_rad": rad, "inside": inside, "parked": parked}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=100)
    parser.add_argument(
        "--variants", nargs="+", choices=list(imperfect_cameras()),
        default=["ideal", *(v for v in imperfect_cameras() if v != "ideal")],
    )  # fmt: skip
    parser.add_argument(
        "--teacher-of", type=Path, metavar="CONFIG",
        help="drive with this DAgger config's teacher instead of the planner",
    )  # fmt: skip
    parser.add_argument(
        "--pose-noise", type=float, default=0.0, metavar="M",
        help="Gaussian noise (metres) added to the driver's position every step",
    )  # fmt: skip
    args = parser.parse_args()
    if args.episodes < 1:
        raise SystemExit(f"--episodes must be at least 1, got {args.episodes}")
    chosen = imperfect_cameras(args.variants)
    driver = None
    if args.teacher_of is not None:
        config = load_dagger_config(args.teacher_of)
        driver = make_analytic(config.teacher, **config.teacher_kwargs)
    print(f"driver: {'planner' if driver is None else f'the teacher of {args.teacher_of}'}")
    try:
        ToImageGoal(driver, args.pose_noise)
    except ValueError as error:
        raise SystemExit(str(error)) from None
    print(f"{args.episodes} held-out rooms (seeds from {HELD_OUT_SEED}), 2 cm / 2 deg")
    print(
        "| variant | image goal off: median / 90th pct | heading off: median / 90th pct "
        "| image goal within tolerance | driven to the image goal, parked |"
    )
    print("|---|---|---|---|---|")
    for label, overrides in chosen.items():
        start = time.perf_counter()
        r = measure(overrides, args.episodes, ToImageGoal(driver, args.pose_noise))
        m, deg = r["off_m"] * 100.0, np.degrees(r["off_rad"])
        print(
            f"| {label} | {np.median(m):.2f} / {np.percentile(m, 90):.2f} cm "
            f"| {np.median(deg):.2f} / {np.percentile(deg, 90):.2f} deg "
            f"| {r['inside']} / {args.episodes} | {r['parked']} / {args.episodes} |"
            f"  ({time.perf_counter() - start:.0f} s)"
        )


if __name__ == "__main__":
    main()
