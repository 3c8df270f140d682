"""PPO training throughput, and the wall-clock the shipped models took to reach their target.

Usage: ``python benchmarks/bench_training.py [--quick]`` (or ``make bench``).

1. ``radial-ibvs train`` with the shipped config (``configs/agents/ppo_parking.yaml``) for a
   few thousand steps with 1 and 4 envs: env steps per second while training.
2. The native vector env against the learner's ceiling: the same PPO (net [64, 64], batch
   4096, 5 epochs, one torch thread, rollouts of 16,384 steps) on
   ``radial_ibvs_agents.make_vec_env`` with 64 and 256 envs, on SB3's ``DummyVecEnv`` of scalar
   envs, and on a no-op ``VecEnv`` with the same spaces (an env that costs nothing: the fastest this
   PPO can go).
3. Each shipped model's training log
   (``agents/radial_ibvs_agents/learned/models/<name>/progress.csv``): when its held-out success
   rate first reached the paper's IBVS on the same scenario.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import platform
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from stable_baselines3.common.vec_env import VecEnv

from radial_ibvs_agents.learned import MODELS_DIR, shipped_models
from radial_ibvs_agents.learned.training.train import train
from radial_ibvs_agents.learned.training.zoo_config import load_train_config

ROOT = Path(__file__).resolve().parents[1]
#: the paper's IBVS success rate on the models' scenarios (2 cm / 2 deg; `radial-ibvs benchmark`:
#: the `paper` suite, and the 200 episodes of the `random` suite)
TARGETS = {"paper-sim": 1.0, "random": 0.6}
#: env steps per PPO rollout in the learner-ceiling comparison
ROLLOUT = 16_384


def throughput(n_envs: int, steps: int = 8192) -> float:
    """Env steps per second of ``radial-ibvs train`` (the native vector env) with ``n_envs``."""
    config = load_train_config(ROOT / "configs" / "agents" / "ppo_parking.yaml")
    config = dataclasses.replace(
        config,
        n_envs=n_envs,
        algo_kwargs={**config.algo_kwargs, "n_steps": 4096 // n_envs, "batch_size": 512},
        eval_freq=10**9,  # no evaluation inside the timing
    )
    with tempfile.TemporaryDirectory() as tmp:
        start = time.perf_counter()
        train(config, tmp, total_timesteps=steps, progress=False)
        return steps / (time.perf_counter() - start)


class NoOpVecEnv(VecEnv):
    """A ``VecEnv`` that costs nothing: zero observations, zero rewards, 600-step episodes."""

    def __init__(self, like: VecEnv) -> None:
        super().__init__(like.num_envs, like.observation_space, like.action_space)
        space = like.observation_space
        self._obs = {k: np.zeros((self.num_envs, *v.shape), v.dtype) for k, v in space.items()}
        self._t = 0

    def reset(self) -> Any:
        return {k: v.copy() for k, v in self._obs.items()}

    def step_async(self, actions: np.ndarray) -> None:
        self._t += 1

    def step_wait(self) -> Any:
        done = self._t % 600 == 0
        dones = np.full(self.num_envs, done)
        infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
        if done:
            for info in infos:
                info["terminal_observation"] = {k: v[0] for k, v in self._obs.items()}
        obs = {k: v.copy() for k, v in self._obs.items()}
        return obs, np.zeros(self.num_envs, np.float32), dones, infos

    def close(self) -> None:
        pass

    def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
        return [None] * self.num_envs

    def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
        pass

    def env_method(self, method_name: str, *args: Any, indices: Any = None, **kw: Any) -> Any:
        return [None] * self.num_envs

    def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
        return [False] * self.num_envs


def ppo_steps_per_second(venv: VecEnv, rollouts: int = 2) -> float:
    """Env steps per second of PPO (net [64, 64], batch 4096, 5 epochs) on ``venv``."""
    import torch
    from stable_baselines3 import PPO

    torch.set_num_threads(1)
    n_steps = ROLLOUT // venv.num_envs
    model = PPO(
        "MultiInputPolicy",
        venv,
        n_steps=n_steps,
        batch_size=4096,
        n_epochs=5,
        policy_kwargs={"net_arch": [64, 64]},
        device="cpu",
        seed=0,
    )
    model.learn(n_steps * venv.num_envs)  # warm-up: the first rollout and update
    steps = rollouts * n_steps * venv.num_envs
    start = time.perf_counter()
    model.learn(steps, reset_num_timesteps=False)
    return steps / (time.perf_counter() - start)


def learner_ceiling_table(sizes: tuple[int, ...], rollouts: int) -> None:
    """Print PPO steps/s on the native vector env, DummyVecEnv and a no-op VecEnv."""
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env

    from radial_ibvs_agents import make_vec_env

    config = load_train_config(ROOT / "configs" / "agents" / "ppo_parking.yaml")
    kwargs = dict(config.env_kwargs)
    print(f"# PPO steps/s: native vector env vs the learner's ceiling ({kwargs})")
    print(f"{'n_envs':>7}{'no-op':>10}{'native':>10}{'/no-op':>8}{'DummyVecEnv':>13}{'/no-op':>8}")
    for n in sizes:
        native = make_vec_env(config.env_id, n, seed=0, **kwargs)
        ceiling = ppo_steps_per_second(NoOpVecEnv(native), rollouts)
        ours = ppo_steps_per_second(native, rollouts)
        dummy = sb3_make_vec_env(config.env_id, n_envs=n, seed=0, env_kwargs=kwargs)
        scalar = ppo_steps_per_second(dummy, rollouts)
        print(
            f"{n:>7}{ceiling:>10,.0f}{ours:>10,.0f}{ours / ceiling:>8.2f}"
            f"{scalar:>13,.0f}{scalar / ceiling:>8.2f}"
        )


def time_to_target(model: str) -> str:
    """When the model's held-out success rate first reached its target (from its log)."""
    directory = MODELS_DIR / model
    metadata = json.loads((directory / "metadata.json").read_text())
    target = TARGETS.get(metadata["env_kwargs"].get("scenario", ""), None)
    log = directory / "progress.csv"
    if target is None or not log.is_file():
        return "no target for its scenario"
    with log.open() as handle:
        rows = list(csv.DictReader(handle))
    timed = [
        (float(r["time/total_timesteps"]), float(r["time/time_elapsed"]))
        for r in rows
        if r.get("time/time_elapsed")
    ]
    steps, elapsed = np.array(timed).T
    for row in rows:
        rate = row.get("eval/success_rate")
        if rate and float(rate) >= target:
            t = float(row["time/total_timesteps"])
            seconds = float(np.interp(t, steps, elapsed))
            minutes = seconds / 60
            return f"success {float(rate):.0%} >= {target:.0%} at {t:,.0f} steps, {minutes:.1f} min"
    return f"never reached {target:.0%} in {steps[-1]:,.0f} steps"


def main() -> None:
    """Print the figures."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one rollout per measurement")
    args = parser.parse_args()
    print(f"# PPO training throughput: {platform.machine()}, one torch thread")
    for n_envs in (1, 4):
        print(f"  {n_envs} env(s): {throughput(n_envs):,.0f} env steps/s while training")
    learner_ceiling_table((64, 256), rollouts=1 if args.quick else 2)
    for model in shipped_models():
        print(f"# {model}: {time_to_target(model)}")


if __name__ == "__main__":
    main()
