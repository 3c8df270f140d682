"""``radial-ibvs collect``: Minari datasets of a policy's episodes, and DAgger starting from one."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from radial_ibvs_agents.analytic import make_analytic
from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments.collect import DEFAULT_LAYOUT, collect
from radial_ibvs_agents.learned.dagger.datasets import load_collected
from radial_ibvs_agents.rollouts import make_env

pytest.importorskip("minari")
pytest.importorskip("h5py")


@pytest.fixture(scope="module")
def dataset(tmp_path_factory):
    out = tmp_path_factory.mktemp("datasets")
    return collect("planner", "random", 3, out, seed=10_000, progress=False)


def test_round_trip_gives_the_same_transitions(dataset):
    """Write, load: the episodes are those of running the planner again with the same seeds."""
    data = load_collected(dataset)
    assert data.total_episodes == 3
    planner = make_analytic("planner")
    env = make_env(planner, "random", {**DEFAULT_LAYOUT, **planner.env_kwargs})
    for index, episode in enumerate(data.iterate_episodes()):
        obs, _ = env.reset(seed=10_000 + index)
        state, start = None, True
        for t in range(len(episode.actions)):
            for key, value in obs.items():
                np.testing.assert_array_equal(episode.observations[key][t], value, err_msg=key)
            action, state = planner.predict(obs, state, np.array([start]))
            np.testing.assert_array_equal(episode.actions[t], action)
            obs, reward, terminated, truncated, info = env.step(action)
            assert episode.rewards[t] == pytest.approx(reward, rel=1e-6)
            assert episode.infos["position_error_m"][t + 1] == info["position_error_m"]
            assert bool(episode.terminations[t]) == terminated
            start = False
        assert terminated or truncated  # the recorded episode ended where this one does
        assert bool(episode.infos["is_success"][-1]) == info["is_success"]
        assert len(episode.infos["reward_progress"]) == len(episode.actions) + 1
        for key, value in obs.items():
            np.testing.assert_array_equal(episode.observations[key][-1], value, err_msg=key)


def test_cli_collect_and_refuse_to_overwrite(tmp_path, capsys):
    args = ["collect", "--policy", "ibvs", "--scenario", "paper-sim", "--episodes", "2"]
    assert main([*args, "--out", str(tmp_path), "--no-progress"]) == 0
    assert "2 episodes" in capsys.readouterr().out
    assert main([*args, "--out", str(tmp_path), "--no-progress"]) == 2  # exists: an error
    assert "exists" in capsys.readouterr().err


def test_dagger_starts_from_a_dataset(dataset, tmp_path):
    from radial_ibvs_agents.learned.dagger.distill import dagger, dataset_labels, load_dagger_config

    steps = load_collected(dataset).total_steps
    obs, labels = dataset_labels(dataset, ["points", "visible", "c_error"], None)
    assert len(labels) == steps and labels.shape[1] == 6 and len(obs["points"]) == steps
    config = tmp_path / "dagger.yaml"
    config.write_text(
        "dagger:\n"
        "  env_kwargs: {scenario: random, physics: kinematic, obs_mode: features,"
        " goal_depths: true, max_landmarks: 16}\n"
        "  n_envs: 8\n  rounds: 1\n  steps_per_round: 64\n  updates_per_round: 5\n"
        "  batch_size: 32\n  dataset_size: 5000\n  eval_episodes: 2\n"
        f"  initial_dataset: {dataset}\n"
    )
    out = dagger(load_dagger_config(config), tmp_path / "student", progress=False)
    with (out / "progress.csv").open() as handle:
        (row,) = list(csv.DictReader(handle))
    assert int(row["labels"]) == steps + 64


@pytest.mark.slow  # Minari's DataCollector needs jax (minari[create]: the dev extra)
def test_image_episodes_record_with_the_encoding_the_docs_give(tmp_path, monkeypatch):
    """ParkingImage-v0's two-channel images round-trip through Minari, losslessly."""
    import gymnasium as gym
    import minari

    pytest.importorskip("jax")
    monkeypatch.setenv("MINARI_DATASETS_PATH", str(tmp_path))
    env = gym.make(
        "RadialIBVS/ParkingImage-v0",
        physics="kinematic",
        image_layout="channels",  # the current and the goal image: two channels
        max_episode_steps=3,
    )
    collector = minari.DataCollector(env, record_infos=True, jpeg_encoding=False)
    first, _ = collector.reset(seed=0)
    done = False
    while not done:
        _, _, terminated, truncated, _ = collector.step(np.zeros(2, dtype=np.float32))
        done = terminated or truncated
    collector.create_dataset(dataset_id="radial-ibvs/image-test-v0", algorithm_name="zeros")
    episode = next(minari.load_dataset("radial-ibvs/image-test-v0").iterate_episodes())
    assert first.shape[-1] == 2  # what JPEG cannot hold
    np.testing.assert_array_equal(episode.observations[0], first)  # lossless: the same bytes
