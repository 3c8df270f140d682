"""PPO training throughput, and the wall-clock the shipped models took to reach their target.

Usage: ``python benchmarks/bench_training.py`` (or ``make bench``). Part 1 trains PPO with the
shipped config (``configs/agents/ppo_parking.yaml``) for a few thousand steps with 1 and 4
envs and prints env steps per second while training. Part 2 reads each shipped model's
training log (``agents/models/<name>/progress.csv``) and prints when its held-out success rate
first reached the paper's IBVS on the same scenario.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import platform
import tempfile
import time
from pathlib import Path

import numpy as np

from agents.learned import MODELS_DIR, shipped_models
from agents.training import train
from agents.zoo import load_train_config

ROOT = Path(__file__).resolve().parents[1]
#: the paper's IBVS success rate on the models' scenarios (2 cm / 2 deg; `radial-ibvs benchmark`:
#: the `paper` suite, and the 200 episodes of the `random` suite)
TARGETS = {"paper-sim": 1.0, "random": 0.6}


def throughput(n_envs: int, steps: int = 8192) -> float:
    """Env steps per second while training PPO with ``n_envs`` envs (DummyVecEnv)."""
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
    print(f"# PPO training throughput: {platform.machine()}, one torch thread")
    for n_envs in (1, 4):
        print(f"  {n_envs} env(s): {throughput(n_envs):,.0f} env steps/s while training")
    for model in shipped_models():
        print(f"# {model}: {time_to_target(model)}")


if __name__ == "__main__":
    main()
