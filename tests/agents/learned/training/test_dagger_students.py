"""DAgger (``radial_ibvs_agents.learned.dagger.distill``) that trains a student: the model it
writes, what the loaded policy sees, determinism under a seed, the landmark-set students, the
exported student."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest
from dagger_setup import ENV, SMALL

from radial_ibvs_agents import load
from radial_ibvs_agents.learned.dagger.distill import dagger, load_dagger_config
from radial_ibvs_agents.learned.networks.history import HistoryStack
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env


def test_dagger_writes_a_model_agents_load_runs(student):
    config, out = student
    rows = (out / "progress.csv").read_text().splitlines()
    assert len(rows) == 1 + config.rounds
    assert (out / "learning_curve.png").stat().st_size > 0
    policy = load(out)
    assert type(policy).__name__ == "HistoryPolicy"
    meta = policy.metadata
    assert meta["trained_by"] == "dagger" and meta["teacher"] == "planner"
    assert policy.env_kwargs == ENV and meta["algo"] == "ppo"  # what evaluate makes the env with
    assert meta["best_round"] in range(config.rounds)
    assert "residual" not in meta  # no analytic policy inside at deployment
    import gymnasium as gym

    env = gym.make("RadialIBVS/Parking-v0", **ENV)
    policy.check_observation_space(env.observation_space)
    obs, _ = env.reset(seed=1)
    state = None
    for step in range(5):
        action, state = policy.predict(obs, state, np.array([step == 0]))
        assert env.action_space.contains(action)
        obs, *_ = env.step(action)
    assert set(state) == set(config.history.keys)


def test_history_policy_sees_what_training_saw(student):
    """Step by step with its state, the loaded policy acts as on the training-side stack."""
    config, out = student
    policy = load(out)
    n = 3
    venv = make_vec_env("RadialIBVS/Parking-v0", n, seed=7, monitor=False, **ENV)
    stack = HistoryStack(config.history, n)
    obs = venv.reset()
    stacked = stack.reset(obs)
    state, starts = None, np.ones(n, dtype=bool)
    for _ in range(12):
        action, state = policy.predict(obs, state, starts)
        direct, _ = policy.learned.predict(stacked)
        np.testing.assert_array_equal(action, direct)
        obs, _, starts, _ = venv.step(action)
        stacked = stack.step(obs, starts)


def test_dagger_is_deterministic_under_a_seed(student, tmp_path):
    config, out = student
    again = dagger(config, tmp_path / "again", seed=3, progress=False)
    assert (again / "policy.safetensors").read_bytes() == (out / "policy.safetensors").read_bytes()
    assert (again / "normalization.npz").read_bytes() == (out / "normalization.npz").read_bytes()


def test_a_round_depends_only_on_the_rounds_before_it(student, tmp_path):
    """A shorter run's rounds are the longer run's first rounds, bit for bit (so a config's
    fewer-rounds twin shares its seeds' checkpoints)."""
    config, out = student
    fewer = replace(config, rounds=config.rounds - 1)
    shorter = dagger(fewer, tmp_path / "short", seed=3, progress=False)
    for k in range(config.rounds - 1):
        for name in ("policy.safetensors", "normalization.npz"):
            a = (shorter / "rounds" / f"round_{k}" / name).read_bytes()
            assert a == (out / "rounds" / f"round_{k}" / name).read_bytes(), (k, name)
    assert not (shorter / "rounds" / f"round_{config.rounds - 1}").exists()


@pytest.mark.parametrize(
    ("extractor", "cls"),
    [
        ("landmark_set", "LandmarkSetExtractor"),
        ("landmark_pose", "LandmarkPoseExtractor"),
        ("landmark_pose\n  pose_history: true", "LandmarkPoseExtractor"),
    ],
)
def test_a_landmark_set_student_is_stored_without_a_pickle_and_loads(tmp_path, extractor, cls):
    path = tmp_path / "config.yaml"
    history = "  history: {frames: 3}\n"
    small = SMALL.replace(history, "" if "history" not in extractor else history)
    path.write_text(small.replace("rounds: 2", "rounds: 1") + f"  extractor: {extractor}\n")
    config = load_dagger_config(path)
    assert config.extractor == extractor.split()[0]
    out = dagger(config, tmp_path / "student", seed=0, progress=False)
    policy = load(out)
    assert cls in (out / "policy.json").read_text()
    files = np.load(out / "normalization.npz").files
    normalised = {k.split("/", 1)[1] for k in files if k.startswith("mean/")}
    assert "landmark_mask" in normalised  # the extractor reads the landmark keys raw:
    assert not normalised & {"points", "goal_points", "goal_depths", "visible"}
    if config.pose_history:  # the past frames' points are solved for poses: read raw too
        assert not any(k.startswith(("points@", "visible@")) for k in normalised)
    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=5, monitor=False, **ENV)
    action, _ = policy.predict(venv.reset())
    assert action.shape == (2, 2) and np.isfinite(action).all()


def test_an_exported_student_ships_as_an_sb3_ppo_model(student, tmp_path):
    """export_model ships a student with its kept round noted, and a stable-baselines3 PPO
    model.zip (for SB3 users; radial_ibvs_agents.load never reads it) that acts as
    radial_ibvs_agents.load's policy."""
    from stable_baselines3 import PPO

    from radial_ibvs_agents.learned.files.loading import load_policy
    from radial_ibvs_agents.learned.training.train import export_model

    _, out = student
    shipped = export_model(out, tmp_path / "dagger-student")
    meta = json.loads((shipped / "metadata.json").read_text())
    assert meta["shipped"].startswith(f"round {meta['best_round']}:")
    policy, _ = load_policy(shipped)
    model = PPO.load(shipped / "model.zip", device="cpu")  # our own file: a test may unpickle
    obs = {
        k: np.stack([v.sample() for _ in range(4)])
        for k, v in policy.observation_space.spaces.items()
    }
    ours, _ = policy.predict(obs, deterministic=True)
    theirs, _ = model.predict(obs, deterministic=True)
    np.testing.assert_array_equal(ours, theirs)
    assert isinstance(model, PPO) and load(shipped).metadata["best_round"] == meta["best_round"]


def test_the_metadata_names_the_revision_the_run_started_from(tmp_path, monkeypatch):
    # a run lasts long enough for the checkout to move on: the revision read at its start
    from dagger_setup import SMALL

    from radial_ibvs_agents.learned.files import provenance as origin

    revisions = iter(["where-it-started"])
    monkeypatch.setattr(origin, "git_revision", lambda: next(revisions, "a-later-commit"))
    path = tmp_path / "config.yaml"
    path.write_text(SMALL.replace("rounds: 2", "rounds: 1"))
    out = dagger(load_dagger_config(path), tmp_path / "student", seed=3, progress=False)
    assert json.loads((out / "metadata.json").read_text())["git_revision"] == "where-it-started"
