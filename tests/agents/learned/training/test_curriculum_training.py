"""Training with the reverse curriculum (the callback raises ``start_reach``) and with HER."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents.learned.training.curriculum import CurriculumConfig
from radial_ibvs_agents.learned.training.train import train
from radial_ibvs_agents.learned.training.zoo_config import load_train_config

CONFIGS = Path(__file__).resolve().parents[4] / "configs" / "agents"


def test_training_with_the_curriculum_raises_start_reach(tmp_path: Path) -> None:
    config = load_train_config(CONFIGS / "ppo_curriculum.yaml")
    assert config.curriculum == CurriculumConfig(start=0.05, until=0.6)
    small = config.__class__(**{**config.__dict__, "n_envs": 16, "eval_freq": 10**9})
    small.algo_kwargs.update(n_steps=64, batch_size=256, n_epochs=1)
    out = train(small, tmp_path / "m", total_timesteps=16 * 64 * 4, progress=False)
    metadata = json.loads((out / "metadata.json").read_text())
    assert metadata["curriculum"] == {"start": 0.05, "until": 0.6}
    rows = (out / "logs" / "progress.csv").read_text().splitlines()
    column = rows[0].split(",").index("curriculum/start_reach")
    # rows without the column: the final evaluation of a run shorter than eval_freq
    cells = [r.split(",")[column] for r in rows[1:]]
    reach = [float(c) for c in cells if c]
    # 4 rollouts of 1,024 steps: progress 0, 1/4, 1/2, 3/4 at their starts
    expected = [0.05 + 0.95 * min(k / 4 / 0.6, 1.0) for k in range(4)]
    assert reach == pytest.approx(expected) and reach[-1] == 1.0


def test_the_her_config_builds_sac_with_her(tmp_path: Path) -> None:
    from stable_baselines3 import HerReplayBuffer

    config = load_train_config(CONFIGS / "sac_her.yaml")
    assert config.algo_kwargs["replay_buffer_class"] is HerReplayBuffer
    assert config.algo_kwargs["replay_buffer_kwargs"]["goal_selection_strategy"] == "future"
    env_kwargs = {**config.env_kwargs, "max_episode_steps": 20}  # HER samples whole episodes
    small = config.__class__(
        **{**config.__dict__, "n_envs": 2, "eval_freq": 10**9, "env_kwargs": env_kwargs}
    )
    small.algo_kwargs.update(learning_starts=100, buffer_size=2000)
    out = train(small, tmp_path / "sac", algo="sac", total_timesteps=300, progress=False)
    assert (out / "model.zip").is_file()
    # the benchmark runs it in its own env (ParkingGoal-v1), like any other policy
    from radial_ibvs_agents.experiments.jobs import Job, run_job
    from radial_ibvs_agents.experiments.suites import SUITES

    result = run_job(Job(str(out), SUITES["held-out"][0], 2))
    assert result.skipped is None and len(result.rows) == 2
    assert all(row["steps"] <= 20 for row in result.rows)
    bad = tmp_path / "bad.yaml"
    bad.write_text("RadialIBVS/ParkingGoal-v1:\n  replay_buffer_class: Foo\n")
    with pytest.raises(ValueError, match="must be 'HerReplayBuffer', got 'Foo'"):
        load_train_config(bad)
