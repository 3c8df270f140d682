"""Where a distilled student departs from its teacher: action errors along its own episodes.

Usage: ``python research/diagnostics/student_vs_teacher.py DIR [--episodes 40] [--seed 10000]``.

``DIR`` is a model directory written by ``radial-ibvs distill`` (its metadata names the
teacher and its arguments). The student drives ``--episodes`` held-out rooms (the env of its
metadata, deterministic actions); at every step the teacher, which sees the true poses and
the map, says what it would do in the same state. Printed: the episodes' ends, then per band
of distance to the goal the share of the steps spent there, the mean teacher and student
speeds and turn rates (in units of the robot's limits) and the RMS difference, and the
share of steps where the turn has the wrong sign or less than half the teacher's size, and
where the time-outs stopped in the goal's frame (short of the goal or past it, in the cone of
``MapPlanner``'s docking law or not).
With ``--restart``, the teacher then drives from each time-out's last state (the same room,
the student's final pose as the start): if it cannot park from there either, the student
stopped where its teacher's command field stops too.
"""

from __future__ import annotations

import argparse
import collections
import itertools
from pathlib import Path

import gymnasium as gym
import numpy as np

from radial_ibvs_agents import load
from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.analytic.docking import goal_frame, in_docking_cone
from radial_ibvs_agents.learned.dagger.distill_config import PRIVILEGED
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env
from radial_ibvs_agents.rollouts import run_episode

BANDS = (0.0, 0.05, 0.15, 0.3, 0.6, 1.2, 2.5, np.inf)


def _wrap(angle: np.ndarray) -> np.ndarray:
    return (angle + np.pi) % (2 * np.pi) - np.pi


def main() -> None:
    """Print the tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model", type=Path)
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--seed", type=int, default=10_000)
    parser.add_argument("--restart", action="store_true", help="the teacher from the time-outs")
    args = parser.parse_args()
    student = load(args.model)
    meta = student.metadata
    teacher = make_analytic(meta["teacher"], **meta.get("teacher_kwargs", {}))
    n = args.episodes
    venv = make_vec_env(
        meta["env_id"], n, seed=args.seed, monitor=False, **student.env_kwargs, **PRIVILEGED
    )
    plain = make_vec_env(meta["env_id"], 1, seed=0, monitor=False, **student.env_kwargs)
    keys = list(plain.observation_space.spaces)  # what the student sees (no privileged keys)
    plain.close()
    obs = venv.reset()
    starts = np.ones(n, dtype=bool)
    done = np.zeros(n, dtype=bool)
    s_state = t_state = None
    rows: list[tuple[float, float, float, float, float]] = []
    ends: collections.Counter[str] = collections.Counter()
    stalls: list[tuple[float, float]] = []  # (distance, heading error) of stalled time-outs
    timeouts: list[tuple[int, np.ndarray, np.ndarray]] = []  # (env, final pose, goal pose)
    pose = goal = np.zeros((n, 3))
    while not done.all():
        own = {k: obs[k] for k in keys}
        action, s_state = student.predict(own, s_state, starts, deterministic=True)
        label, t_state = teacher.predict(obs, t_state, starts)
        distance = np.hypot(*(obs["goal_pose"][:, :2] - obs["robot_pose"][:, :2]).T)
        for i in np.flatnonzero(~done):
            rows.append((distance[i], *label[i], *action[i]))
        heading = np.degrees(np.abs(_wrap(obs["goal_pose"][:, 2] - obs["robot_pose"][:, 2])))
        pose, goal = obs["robot_pose"].copy(), obs["goal_pose"].copy()
        obs, _, starts, infos = venv.step(action)
        for i in np.flatnonzero(starts & ~done):
            info = infos[i]
            end = [k for k in ("is_success", "collision", "lost") if info.get(k)]
            ends[end[0] if end else "timeout"] += 1
            if not end:  # the pose before the last step: close enough for a restart
                timeouts.append((int(i), pose[i], goal[i]))
            still = np.abs(action[i]).max() < 0.02 and np.abs(label[i]).max() >= 0.02
            if not end and still:
                stalls.append((float(distance[i]), float(heading[i])))
        done |= starts
    venv.close()
    table = np.array(rows)
    print(f"# {args.model}: {n} episodes from seed {args.seed}; ends: {dict(ends)}")
    near = [s for s in stalls if s[0] < 0.1]
    far = [s for s in stalls if s[0] >= 0.1]
    print(
        f"stalled time-outs: {len(near)} within 10 cm of the goal (median heading error "
        f"{np.median([s[1] for s in near]) if near else float('nan'):.0f} deg), {len(far)} "
        f"farther (median distance {np.median([s[0] for s in far]) if far else float('nan'):.2f} m)"
    )
    print("| distance to goal (m) | steps | teacher v, w | student v, w | RMS diff v, w |"
          " w wrong sign | w < half |")  # fmt: skip
    print("|---|---:|---|---|---|---:|---:|")
    for lo, hi in itertools.pairwise(BANDS):
        band = table[(table[:, 0] >= lo) & (table[:, 0] < hi)]
        if not len(band):
            continue
        tv, tw, sv, sw = band[:, 1], band[:, 2], band[:, 3], band[:, 4]
        turning = np.abs(tw) > 0.05
        wrong = np.mean(np.sign(sw[turning]) != np.sign(tw[turning])) if turning.any() else 0.0
        small = np.mean(np.abs(sw[turning]) < 0.5 * np.abs(tw[turning])) if turning.any() else 0
        rms = np.sqrt(np.mean((band[:, 1:3] - band[:, 3:5]) ** 2, axis=0))
        print(
            f"| {lo:g}-{hi:g} | {len(band) / len(table):.1%} | {tv.mean():+.2f}, {tw.mean():+.2f}"
            f" | {sv.mean():+.2f}, {sw.mean():+.2f} | {rms[0]:.3f}, {rms[1]:.3f}"
            f" | {wrong:.0%} | {small:.0%} |"
        )
    if timeouts:
        print(where(timeouts, teacher))
    if args.restart and timeouts:
        print(restart(meta, student.env_kwargs, teacher, args.seed, timeouts))


def where(timeouts: list[tuple[int, np.ndarray, np.ndarray]], teacher: object) -> str:
    """Return a line: where the time-outs stopped, in the goal's frame.

    The docking cone is the teacher's (``MapPlanner``'s ``line_cone`` and ``goal_tolerance``
    band), whether or not its ``line_radius`` switches the docking law on.
    """
    frames = np.array([goal_frame(pose, goal) for _, pose, goal in timeouts])
    x_g, y_g, phi = frames.T
    angle, band = float(teacher.rules.line_cone), float(teacher.goal_tolerance)  # type: ignore[attr-defined]
    cone = sum(in_docking_cone(x, y, angle, band) for x, y in zip(x_g, y_g, strict=True))
    return (
        f"the {len(timeouts)} time-outs in the goal's frame: {int((x_g < 0).sum())} short of the "
        f"goal, {cone} in the docking cone ({angle:g} rad, {band * 100:g} cm band); median |x| "
        f"{np.median(np.abs(x_g)) * 100:.1f} cm, |y| {np.median(np.abs(y_g)) * 100:.1f} cm, "
        f"|heading error| {np.degrees(np.median(np.abs(phi))):.0f} deg"
    )


def restart(
    meta: dict,
    env_kwargs: dict,
    teacher: object,
    seed: int,
    timeouts: list[tuple[int, np.ndarray, np.ndarray]],
) -> str:
    """Return a line: how the teacher ends from each time-out's final pose, in the same room."""
    env = gym.make(meta["env_id"], **env_kwargs, **PRIVILEGED)
    ends: collections.Counter[str] = collections.Counter()
    for i, pose, goal in timeouts:
        _, info = env.reset(seed=seed + i)
        if not np.allclose(info["goal_pose"], goal):  # the vector env seeds env i with seed + i
            raise RuntimeError(f"env {i}: the room of seed {seed + i} is not the student's")
        ends[run_episode(teacher, env, seed=seed + i, options={"start": pose}).end] += 1
    env.close()
    return f"the teacher from the student's {len(timeouts)} time-outs' last poses: {dict(ends)}"


if __name__ == "__main__":
    main()
