"""PPO fine-tuning of a DAgger student (``train(init_from=...)``,
``radial_ibvs_agents.learned.training.fine_tune``):
what it takes from the student, the exploration noise, the critic's warm-up."""

from __future__ import annotations

import json

import numpy as np
import torch
from dagger_setup import ENV, fine_tune_config

from radial_ibvs_agents import load
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env


def test_ppo_fine_tuning_starts_from_the_student(student, tmp_path):
    """train(init_from=DIR) takes the student's architecture, weights, history, statistics."""
    from radial_ibvs_agents.learned.training.train import train
    from radial_ibvs_agents.learned.training.zoo_config import load_train_config

    _, out = student
    config_path = tmp_path / "ppo.yaml"
    config_path.write_text(
        "RadialIBVS/Parking-v0:\n  n_envs: 4\n  policy: MultiInputPolicy\n"
        '  normalize: "dict(norm_obs=True, norm_reward=True, gamma=0.99)"\n'
        "  n_steps: 16\n  batch_size: 32\n  n_epochs: 1\n  learning_rate: 0.0\n"
        f"radial_ibvs_gym:\n  env_kwargs: {json.dumps(ENV)}\n  eval_freq: 1000000\n"
        "  eval_episodes: 1\n"
    )
    tuned_dir = train(
        load_train_config(config_path), tmp_path / "tuned", total_timesteps=64,
        init_from=out, progress=False,
    )  # fmt: skip
    tuned, original = load(tuned_dir), load(out)
    assert type(tuned).__name__ == "HistoryPolicy"  # the history came along
    assert tuned.metadata["init_from"] == str(out)
    venv = make_vec_env("RadialIBVS/Parking-v0", 3, seed=11, monitor=False, **ENV)
    obs, state_a, state_b = venv.reset(), None, None
    starts = np.ones(3, dtype=bool)
    for _ in range(6):  # learning rate 0: the same weights; the statistics moved a little
        a, state_a = tuned.predict(obs, state_a, starts)  # (256 more samples in them)
        b, state_b = original.predict(obs, state_b, starts)
        np.testing.assert_allclose(a, b, atol=0.03)
        assert np.abs(b).max() > 0.3  # not a fresh network's near-zero actions
        obs, _, starts, _ = venv.step(a)


def _fine_tuned(student, tmp_path, fine_tune: str, steps: int):
    """Fine-tune the student for ``steps`` env steps; return the directory, the tuned policy
    and the student's parameters by name."""
    from radial_ibvs_agents.learned.files.loading import load_policy
    from radial_ibvs_agents.learned.training.train import train

    _, out = student
    config = fine_tune_config(tmp_path, f"  fine_tune: {fine_tune}\n")
    tuned_dir = train(
        config, tmp_path / "tuned", total_timesteps=steps, init_from=out, progress=False
    )
    tuned, _ = load_policy(tuned_dir)
    original, _ = load_policy(out)
    return tuned_dir, tuned, dict(original.named_parameters())


def test_fine_tuning_sets_the_noise_and_trains_the_critic_alone_first(student, tmp_path):
    """fine_tune.log_std sets the exploration noise; during critic_warmup the actor's weights
    (and the features it shares with the critic) stay bit for bit the student's, the critic's
    move."""
    from radial_ibvs_agents.learned.training.fine_tune import critic_parameters

    tuned_dir, tuned, before = _fine_tuned(
        student, tmp_path, "{log_std: -2.0, critic_warmup: 128}", 128
    )
    critic = critic_parameters(tuned)
    assert critic and "log_std" not in critic
    for name, parameter in tuned.named_parameters():
        if name == "log_std":
            assert torch.all(parameter == -2.0)
        elif name in critic:
            continue
        else:
            assert torch.equal(parameter, before[name]), name
    assert any(not torch.equal(p, before[n]) for n, p in tuned.named_parameters() if n in critic)
    assert load(tuned_dir).metadata["fine_tune"] == {"log_std": -2.0, "critic_warmup": 128}


def test_after_the_warmup_the_actor_learns(student, tmp_path):
    """Past critic_warmup the actor's own layers move too."""
    _, tuned, before = _fine_tuned(student, tmp_path, "{critic_warmup: 64}", 192)
    moved = [n for n, p in tuned.named_parameters() if not torch.equal(p, before[n])]
    assert any(n.startswith("mlp_extractor.policy_net") for n in moved)
