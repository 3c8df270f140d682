"""Fine-tuning with PPO (``radial_ibvs_agents.learned.training.fine_tune``) without a student: the
critic's warm-up, the config's errors. The tests that fine-tune a student are in
``training/test_fine_tune_students.py``."""

from __future__ import annotations

import pytest
from dagger_setup import ENV, fine_tune_config

from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env


def test_the_warmup_freezes_the_actor_and_releases_it_at_the_end():
    """CriticWarmup freezes every parameter but the critic's for its steps, and a run that
    ends inside the warm-up still leaves the policy wholly trainable."""
    from stable_baselines3 import PPO

    from radial_ibvs_agents.learned.training.fine_tune import CriticWarmup, critic_parameters

    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=0, monitor=False, **ENV)
    model = PPO("MultiInputPolicy", venv, n_steps=16, batch_size=32, n_epochs=1, device="cpu")
    warmup = CriticWarmup(1_000)
    seen: list[set[str]] = []

    class Spy(CriticWarmup):
        def _on_rollout_start(self) -> None:
            names = model.policy.named_parameters()
            seen.append({n for n, p in names if p.requires_grad})

    model.learn(64, callback=[warmup, Spy(0)])
    assert seen and all(trainable == critic_parameters(model.policy) for trainable in seen)
    assert not warmup.frozen and all(p.requires_grad for p in model.policy.parameters())


@pytest.mark.parametrize(
    ("fine_tune", "match"),
    [
        ("{log_std: nan}", "log_std must be a number"),
        ("{log_std: 5}", "log_std must be a number"),
        ("{critic_warmup: -1}", "critic_warmup must be an integer"),
        ("{noise: 1}", r"unknown key\(s\) \['noise'\]"),
        ("3", "must be a mapping"),
    ],
)
def test_fine_tune_errors_name_the_value(tmp_path, fine_tune, match):
    with pytest.raises(ValueError, match=match):
        fine_tune_config(tmp_path, f"  fine_tune: {fine_tune}\n")


def test_fine_tune_without_a_student_is_refused(tmp_path):
    from radial_ibvs_agents.learned.training.train import train

    config = fine_tune_config(tmp_path, "  fine_tune: {log_std: -2.0}\n")
    with pytest.raises(ValueError, match="fine_tune starts from a student"):
        train(config, tmp_path / "run", total_timesteps=64, progress=False)
