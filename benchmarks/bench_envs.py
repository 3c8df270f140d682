"""Environment throughput (a script that prints figures, not a timed test).

Usage: ``python benchmarks/bench_envs.py`` (or ``make bench``). Steps each registered id and
physics backend through ``gym.make`` with random actions (resetting at episode end), with
Gymnasium's CartPole-v1 and Pendulum-v1 as yardsticks measured in the same run.
"""

from __future__ import annotations

import platform
import time

import gymnasium as gym

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.envs import ENV_IDS


def steps_per_second(env: gym.Env, seconds: float = 3.0) -> float:
    """Random-action steps per second, resets included."""
    env.reset(seed=0)
    env.action_space.seed(0)
    actions = [env.action_space.sample() for _ in range(1000)]
    n, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        for a in actions:
            _, _, terminated, truncated, _ = env.step(a)
            if terminated or truncated:
                env.reset()
        n += len(actions)
    return n / (time.perf_counter() - start)


def main() -> None:
    """Print the throughput table."""
    print(f"# env throughput: {platform.machine()}, gymnasium {gym.__version__}")
    yardsticks = {name: steps_per_second(gym.make(name)) for name in ("CartPole-v1", "Pendulum-v1")}
    print(f"{'env':<34}{'physics':<11}{'steps/s':>10}{'/CartPole':>11}{'/Pendulum':>11}")
    rows = [(name, "", sps) for name, sps in yardsticks.items()]
    for env_id in ENV_IDS:
        for physics in ("pymunk", "kinematic"):
            env = gym.make(env_id, scenario="paper-sim", physics=physics)
            rows.append((env_id, physics, steps_per_second(env)))
    for name, physics, sps in rows:
        print(
            f"{name:<34}{physics:<11}{sps:>10,.0f}"
            f"{sps / yardsticks['CartPole-v1']:>11.2f}{sps / yardsticks['Pendulum-v1']:>11.2f}"
        )


if __name__ == "__main__":
    main()
