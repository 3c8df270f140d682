"""How well a DAgger teacher parks from its own states, and from states a student would visit.

Usage::

    python research/diagnostics/teacher_check.py research/configs/dagger_planner_set_align.yaml \
        [--episodes 64] [--seed 10000] [--perturb 0.0 0.02] [--near 0.025 0.04 0.08 0.15]

Runs the config's teacher (its ``teacher`` and ``teacher_kwargs``) in the config's env with the
privileged observation, on validation seeds. With ``--perturb p`` each robot, at each step with
probability ``p``, drives a random command for 10 steps (uniform in the action box, seeded),
then the teacher takes over again from wherever it is: a crude stand-in for a student's
mistakes, which DAgger asks the teacher to label. Prints how the episodes end, the median
episode length, the median heading error (to the goal heading) when a robot first comes
within 5 cm of the goal, and how far from the goal the time-outs stopped.

With ``--near d ...`` it also starts the teacher ``d`` metres from the goal (a random bearing,
the heading up to 180 deg off the goal heading, seeded), once per validation room, where a
student that arrived misaligned would hand it the state, and prints how those episodes end.
"""

from __future__ import annotations

import argparse
import collections
from pathlib import Path

import gymnasium as gym
import numpy as np

from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.learned.dagger.distill_config import PRIVILEGED, load_dagger_config
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env
from radial_ibvs_agents.rollouts import run_episode

BURST = 10  # steps of a random command


def run(config_path: Path, episodes: int, seed: int, perturb: float) -> str:
    """Return one line: the ends of ``episodes`` teacher episodes under ``perturb``."""
    config = load_dagger_config(config_path)
    teacher = make_analytic(config.teacher, **config.teacher_kwargs)
    venv = make_vec_env(
        config.env_id, episodes, seed=seed, monitor=False, **config.env_kwargs, **PRIVILEGED
    )
    rng = np.random.default_rng(seed)
    obs = venv.reset()
    starts, done = np.ones(episodes, dtype=bool), np.zeros(episodes, dtype=bool)
    state = None
    burst, command = np.zeros(episodes, dtype=int), np.zeros((episodes, 2), dtype=np.float32)
    steps = np.zeros(episodes)
    ends: collections.Counter[str] = collections.Counter()
    stopped: list[float] = []
    arrival = np.full(episodes, np.nan)  # heading error when first within 5 cm of the goal
    while not done.all():
        action, state = teacher.predict(obs, state, starts)
        new = (burst == 0) & (rng.random(episodes) < perturb)
        command[new] = rng.uniform(-1.0, 1.0, (int(new.sum()), 2))
        burst[new] = BURST
        action = np.where((burst > 0)[:, None], command, action)
        burst = np.maximum(burst - 1, 0)
        distance = np.hypot(*(obs["goal_pose"][:, :2] - obs["robot_pose"][:, :2]).T)
        heading = np.abs(
            (obs["goal_pose"][:, 2] - obs["robot_pose"][:, 2] + np.pi) % (2 * np.pi) - np.pi
        )
        first = ~done & np.isnan(arrival) & (distance < 0.05)
        arrival[first] = np.degrees(heading[first])
        obs, _, starts, infos = venv.step(action)
        steps += ~done
        for i in np.flatnonzero(starts & ~done):
            end = [k for k in ("is_success", "collision", "lost") if infos[i].get(k)]
            ends[end[0] if end else "timeout"] += 1
            if not end:
                stopped.append(float(distance[i]))
        done |= starts
    venv.close()
    away = f", time-outs at {np.round(sorted(stopped), 3).tolist()} m" if stopped else ""
    return (
        f"| {config_path.name} | {perturb:g} | {dict(ends)} | {np.median(steps):.0f} steps{away}"
        f" | {np.nanmedian(arrival):.0f} deg |"
    )


def near(config_path: Path, distance: float, episodes: int, seed: int) -> str:
    """Return one line: the ends of teacher episodes started ``distance`` m from the goal."""
    config = load_dagger_config(config_path)
    env = gym.make(config.env_id, **config.env_kwargs, **PRIVILEGED)
    rng = np.random.default_rng(seed)
    ends: collections.Counter[str] = collections.Counter()
    stopped: list[tuple[float, float]] = []  # (distance in cm, largest last action component)
    for k in range(episodes):
        teacher = make_analytic(config.teacher, **config.teacher_kwargs)
        _, info = env.reset(seed=seed + k)
        goal = np.asarray(info["goal_pose"], dtype=np.float64)
        bearing, error = rng.uniform(-np.pi, np.pi, 2)
        offset = np.array([distance * np.cos(bearing), distance * np.sin(bearing), error])
        log = run_episode(teacher, env, seed=seed + k, options={"start": goal + offset})
        ends[log.end] += 1
        if log.end == "time-out":
            stopped.append(
                (100 * float(log.info["position_error_m"]), float(np.abs(log.actions[-1]).max()))
            )
    env.close()
    away = ""
    if stopped:
        cm, command = np.array(stopped).T
        away = (
            f", time-outs {cm.min():.1f}-{cm.max():.1f} cm from the goal, their last command"
            f" at most {command.max():.3f}"
        )
    where = f"start {100 * distance:g} cm off the goal"
    return f"| {config_path.name} | {where} | {dict(ends)}{away} | | |"


def main() -> None:
    """Print one row per perturbation."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("config", type=Path, nargs="+", help="DAgger config(s)")
    parser.add_argument("--episodes", type=int, default=64)
    parser.add_argument("--seed", type=int, default=10_000)
    parser.add_argument("--perturb", type=float, nargs="*", default=[0.0, 0.02])
    parser.add_argument("--near", type=float, nargs="*", default=[], help="start distances, m")
    args = parser.parse_args()
    print("| config | perturbation | ends | median length | heading error at 5 cm |")
    print("|---|---:|---|---|---:|")
    for path in args.config:
        for p in args.perturb:
            print(run(path, args.episodes, args.seed, p), flush=True)
        for d in args.near:
            print(near(path, d, args.episodes, args.seed), flush=True)


if __name__ == "__main__":
    main()
