"""Environment throughput (a script that prints figures, not a timed test).

Usage: ``python benchmarks/bench_envs.py [--quick]`` (or ``make bench``).

1. The scalar envs: each registered id and physics backend through ``gym.make`` with random
   actions (resetting at episode end), with Gymnasium's CartPole-v1 and Pendulum-v1 as
   yardsticks measured in the same run.
2. The native vector env (``gym.make_vec(..., vectorization_mode="vector_entry_point")``) at
   N = 1, 16, 256, 1024 and 4096 for both backends, beside Gymnasium's ``CartPoleVectorEnv``
   at the same N in the same run, and the scalar pymunk env. Figures are env steps per second
   (N per vector step); ratios matter, absolute numbers move about 30 % between runs here.
"""

from __future__ import annotations

import argparse
import platform
import time

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.registration import ENV_IDS

SIZES = (1, 16, 256, 1024, 4096)


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


def vector_steps_per_second(envs: gym.vector.VectorEnv, seconds: float = 2.0) -> float:
    """Env steps per second (``num_envs`` per call) with random actions; autoreset included."""
    envs.reset(seed=0)
    rng = np.random.default_rng(0)
    actions = [rng.uniform(-1, 1, (envs.num_envs, 2)).astype(np.float32) for _ in range(16)]
    if isinstance(envs.single_action_space, gym.spaces.Discrete):
        actions = [rng.integers(0, 2, envs.num_envs) for _ in range(16)]
    calls, start = 0, time.perf_counter()
    while time.perf_counter() - start < seconds:
        for a in actions:
            envs.step(a)
        calls += len(actions)
    return calls * envs.num_envs / (time.perf_counter() - start)


def main() -> None:
    """Print the throughput tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="shorter timings, N up to 1024")
    args = parser.parse_args()
    seconds = 1.0 if args.quick else 3.0
    print(f"# env throughput: {platform.machine()}, gymnasium {gym.__version__}")
    yardsticks = {
        name: steps_per_second(gym.make(name), seconds) for name in ("CartPole-v1", "Pendulum-v1")
    }
    print(f"{'env':<34}{'physics':<11}{'steps/s':>10}{'/CartPole':>11}{'/Pendulum':>11}")
    rows = [(name, "", sps) for name, sps in yardsticks.items()]
    scalar = {}
    for env_id in ENV_IDS:
        for physics in ("pymunk", "kinematic"):
            env = gym.make(env_id, scenario="paper-sim", physics=physics)
            rows.append((env_id, physics, steps_per_second(env, seconds)))
            if env_id == "RadialIBVS/Parking-v0":
                scalar[physics] = rows[-1][2]
    for name, physics, sps in rows:
        print(
            f"{name:<34}{physics:<11}{sps:>10,.0f}"
            f"{sps / yardsticks['CartPole-v1']:>11.2f}{sps / yardsticks['Pendulum-v1']:>11.2f}"
        )

    print("\n# native vector env, RadialIBVS/Parking-v0 (paper-sim), env steps/s")
    print(
        f"{'N':>6}{'CartPoleVec':>13}{'kinematic':>12}{'/CartPole':>11}{'pymunk':>12}"
        f"{'/CartPole':>11}{'pymunk/scalar':>15}"
    )
    sizes = [n for n in SIZES if not args.quick or n <= 1024]
    for n in sizes:
        cartpole = vector_steps_per_second(
            gym.make_vec("CartPole-v1", num_envs=n, vectorization_mode="vector_entry_point"),
            seconds,
        )
        ours = {}
        for physics in ("kinematic", "pymunk"):
            envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=n, physics=physics)
            ours[physics] = vector_steps_per_second(envs, seconds)
            envs.close()
        print(
            f"{n:>6}{cartpole:>13,.0f}{ours['kinematic']:>12,.0f}"
            f"{ours['kinematic'] / cartpole:>11.3f}{ours['pymunk']:>12,.0f}"
            f"{ours['pymunk'] / cartpole:>11.3f}{ours['pymunk'] / scalar['pymunk']:>15.1f}"
        )


if __name__ == "__main__":
    main()
