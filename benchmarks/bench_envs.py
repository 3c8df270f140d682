"""Environment throughput (a script that prints figures, not a timed test).

Usage: ``python benchmarks/bench_envs.py [--quick]`` (or ``make bench``);
``python benchmarks/bench_envs.py --rounds 15`` for the scalar envs against CartPole-v1 alone;
``python benchmarks/bench_envs.py --parts`` for where one scalar step's time goes;
``python benchmarks/bench_envs.py --vector-rounds 5`` for the pymunk vector env against the
scalar pymunk env.

1. The scalar envs: each registered id and physics backend through ``gym.make`` with random
   actions (resetting at episode end), with Gymnasium's CartPole-v1 and Pendulum-v1 as
   yardsticks measured in the same run.
2. The native vector env (``gym.make_vec(..., vectorization_mode="vector_entry_point")``) at
   N = 1, 16, 256, 1024 and 4096 for both backends, beside Gymnasium's ``CartPoleVectorEnv``
   at the same N in the same run, and the scalar pymunk env. Figures are env steps per second
   (N per vector step); ratios matter, absolute numbers move about 30 % between runs here.
3. With ``--rounds K``, only the scalar ``RadialIBVS/Parking-v0`` (default arguments: paper-sim,
   pymunk; and kinematic) against ``CartPole-v1`` in K interleaved rounds of one second each
   (CartPole, then each env, then CartPole again...), and the median of the rounds' ratios:
   what the machine's load does to one round it does to its neighbours.
4. With ``--parts``, the cost of each part of one scalar ``RadialIBVS/Parking-v0`` step
   (pymunk, paper-sim), each called alone many times at one mid-episode state (``timeit``, the
   best of 7 repeats: the cost without the machine's noise). The parts are the env's own
   private steps, so this mode follows the env's code, not its API.
5. With ``--vector-rounds K``, only the native vector env with pymunk at N = 256 (random
   actions) against the scalar pymunk env through ``gym.make``, default arguments, in K
   interleaved rounds (scalar, vector, scalar), the median of the rounds' ratios; then where a
   vector step's time goes: Chipmunk's ``space.step`` (ten sub-steps), the rest of the
   fleet's step (the bodies read and written in bulk around each sub-step), and the env's
   own work (observation, rules, resets).
"""

from __future__ import annotations

import argparse
import platform
import time
import timeit
from collections.abc import Callable

import gymnasium as gym
import numpy as np

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.envs import rules
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


def interleaved_ratios(rounds: int, seconds: float = 1.0) -> dict[str, list[float]]:
    """Each scalar Parking-v0's steps/s over CartPole-v1's, one ratio per interleaved round."""
    envs = {
        "pymunk": gym.make("RadialIBVS/Parking-v0"),
        "kinematic": gym.make("RadialIBVS/Parking-v0", physics="kinematic"),
    }
    cartpole = gym.make("CartPole-v1")
    ratios: dict[str, list[float]] = {name: [] for name in envs}
    for _ in range(rounds):
        for name, env in envs.items():
            before = steps_per_second(cartpole, seconds / 2)
            ours = steps_per_second(env, seconds)
            after = steps_per_second(cartpole, seconds / 2)
            ratios[name].append(ours / (0.5 * (before + after)))
    return ratios


def vector_rounds(rounds: int, n: int = 256, seconds: float = 1.0) -> list[float]:
    """The pymunk vector env's steps/s over the scalar pymunk env's, one ratio per round."""
    scalar = gym.make("RadialIBVS/Parking-v0")
    vector = gym.make_vec("RadialIBVS/Parking-v0", num_envs=n)
    ratios = []
    for _ in range(rounds):
        before = steps_per_second(scalar, seconds / 2)
        ours = vector_steps_per_second(vector, seconds)
        after = steps_per_second(scalar, seconds / 2)
        ratios.append(ours / (0.5 * (before + after)))
    return ratios


def vector_step_parts(n: int = 256, steps: int = 160) -> dict[str, float]:
    """Milliseconds per vector step (pymunk, N robots): Chipmunk, the fleet, the env."""
    import pymunk

    from radial_ibvs_gym.physics.fleet import PymunkFleet

    spent = {"chipmunk": 0.0, "fleet": 0.0}
    space_step, fleet_step = pymunk.Space.step, PymunkFleet.step

    def timed_space(self: pymunk.Space, dt: float) -> None:
        start = time.perf_counter()
        space_step(self, dt)
        spent["chipmunk"] += time.perf_counter() - start

    def timed_fleet(self: PymunkFleet, *args: object) -> object:
        start = time.perf_counter()
        out = fleet_step(self, *args)  # type: ignore[arg-type]
        spent["fleet"] += time.perf_counter() - start
        return out

    envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=n)
    envs.reset(seed=0)
    rng = np.random.default_rng(0)
    actions = rng.uniform(-1, 1, (steps, n, 2)).astype(np.float32)
    for a in actions[:16]:
        envs.step(a)
    pymunk.Space.step, PymunkFleet.step = timed_space, timed_fleet  # type: ignore[method-assign]
    try:
        start = time.perf_counter()
        for a in actions:
            envs.step(a)
        total = time.perf_counter() - start
    finally:
        pymunk.Space.step, PymunkFleet.step = space_step, fleet_step  # type: ignore[method-assign]
    ms = 1e3 / steps
    return {
        "the whole step": total * ms,
        "Chipmunk's space.step (10 sub-steps)": spent["chipmunk"] * ms,
        "the fleet's step around it": (spent["fleet"] - spent["chipmunk"]) * ms,
        "the env's own work": (total - spent["fleet"]) * ms,
    }


def microseconds(call: Callable[[], object], number: int = 2000) -> float:
    """Best of 7 repeats of ``number`` calls, microseconds per call."""
    return min(timeit.repeat(call, number=number, repeat=7)) / number * 1e6


def step_parts() -> list[tuple[str, float]]:
    """Microseconds per call of each part of one scalar pymunk step, at one mid-episode state."""
    wrapped = gym.make("RadialIBVS/Parking-v0")
    env = wrapped.unwrapped
    wrapped.reset(seed=0)
    for _ in range(5):  # the world's first step takes pymunk's public path: leave it behind
        wrapped.step(np.array([0.3, 0.1], dtype=np.float32))
    # then a robot at rest: each repeated step costs what a step without contacts costs
    config, world = env.config, env.world
    action, command = np.zeros(2, dtype=np.float32), (0.0, 0.0)
    for _ in range(10):  # brake to rest within the robot's acceleration limits
        wrapped.step(action)
    pose = world.pose
    now = rules.pose_errors(pose.tolist(), env._goal)
    terms = rules.reward_terms(now, now, False, False, False, config.weights)

    def end() -> object:
        return rules.episode_end(
            *now,
            env._n_visible,
            False,
            success_position_m=config.success_position_m,
            success_heading_rad=config.success_heading_rad,
            min_visible=config.min_visible,
            terminate_on_collision=config.terminate_on_collision,
            held=0,
            hold_steps=config.success_hold_steps,
        )

    parts = [
        ("gym.make's env.step (wrappers included)", lambda: wrapped.step(action)),
        ("the env's own step", lambda: env.step(action)),
        ("  world.step (10 pymunk sub-steps)", lambda: world.step(command, config.control_dt)),
        ("  the image (_observe)", lambda: env._observe(pose)),
        ("  the observation dict (_obs)", env._obs),
        ("  info (_info)", lambda: env._info(pose, now, False, False, False)),
        ("  reward terms into info (reward_info)", lambda: rules.reward_info(terms, np.float64)),
        ("  the episode's end (episode_end)", end),
        (
            "  the reward terms (reward_terms)",
            lambda: rules.reward_terms(now, now, False, False, False, config.weights),
        ),
        ("  the pose errors (pose_errors)", lambda: rules.pose_errors(pose.tolist(), env._goal)),
    ]
    return [(name, microseconds(call)) for name, call in parts]


def main() -> None:
    """Print the throughput tables."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="shorter timings, N up to 1024")
    parser.add_argument(
        "--rounds", type=int, help="only the scalar env against CartPole-v1, interleaved"
    )
    parser.add_argument(
        "--parts", action="store_true", help="only where one scalar pymunk step's time goes"
    )
    parser.add_argument(
        "--vector-rounds", type=int, help="only the pymunk vector env against the scalar one"
    )
    args = parser.parse_args()
    if args.vector_rounds is not None:
        if args.vector_rounds < 1:
            parser.error(f"--vector-rounds must be a positive integer, got {args.vector_rounds}")
        print(f"# pymunk: native vector env (N = 256) / scalar env, {args.vector_rounds} rounds")
        values = vector_rounds(args.vector_rounds)
        q1, median, q3 = np.percentile(values, [25, 50, 75])
        each = ", ".join(f"{v:.2f}" for v in values)
        print(f"median {median:.2f}x (quartiles {q1:.2f}-{q3:.2f}; rounds: {each})")
        print("\n# one vector step at N = 256, ms")
        for name, ms in vector_step_parts().items():
            print(f"{name:<40}{ms:>8.3f}")
        return
    if args.parts:
        print(f"# one scalar RadialIBVS/Parking-v0 step (pymunk), {platform.machine()}")
        for name, us in step_parts():
            print(f"{name:<44}{us:>8.2f} us")
        return
    if args.rounds is not None:
        if args.rounds < 1:
            parser.error(f"--rounds must be a positive integer, got {args.rounds}")
        print(f"# scalar RadialIBVS/Parking-v0 / CartPole-v1, {args.rounds} interleaved rounds")
        for name, values in interleaved_ratios(args.rounds).items():
            q1, median, q3 = np.percentile(values, [25, 50, 75])
            print(f"{name:<10} median {median:.3f}x CartPole-v1 (quartiles {q1:.3f}-{q3:.3f})")
        return
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
