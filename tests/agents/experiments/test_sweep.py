"""``radial-ibvs sweep`` (multi-seed training, resumable, local or Ray) and the seed statistics."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from radial_ibvs_agents.cli import main
from radial_ibvs_agents.experiments import sweep
from radial_ibvs_agents.stats import iqm, iqm_interval

CONFIG = Path(__file__).resolve().parents[3] / "configs" / "agents" / "ppo_parking.yaml"


@pytest.fixture(scope="module")
def tiny_config(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """configs/agents/ppo_parking.yaml cut down to a few hundred steps and two evaluations."""
    data = yaml.safe_load(CONFIG.read_text())
    section = data["RadialIBVS/Parking-v0"]
    section.update(n_envs=4, n_steps=16, batch_size=32, n_epochs=1, n_timesteps=128)
    data["radial_ibvs_gym"].update(eval_freq=64, eval_episodes=2)
    data["radial_ibvs_gym"]["env_kwargs"]["task"] = 1
    path = tmp_path_factory.mktemp("cfg") / "tiny.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.fixture(scope="module")
def swept(tiny_config: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("sweep")
    argv = [
        "sweep",
        "--config",
        str(tiny_config),
        "--seeds",
        "0",
        "1",
        "--out",
        str(out),
        "--no-progress",
    ]
    assert main(argv) == 0
    return out


@pytest.mark.slow
def test_each_seed_gets_a_train_model_directory_and_a_summary(
    swept: Path, tiny_config: Path
) -> None:
    for seed in (0, 1):
        directory = swept / f"seed-{seed}"
        for name in ("model.zip", "metadata.json", "normalization.npz", "learning_curve.png"):
            assert (directory / name).is_file(), (seed, name)
        metadata = json.loads((directory / "metadata.json").read_text())
        assert metadata["seed"] == seed and "radial-ibvs sweep" in metadata["command"]
        assert metadata["config"]["file"] == str(tiny_config)  # not the worker's scratch copy
        assert len(metadata["learning_curve"]) == 2
    summary = json.loads((swept / "summary.json").read_text())
    assert summary["seeds"] == [0, 1]
    finals = [summary["final_success"][s] for s in ("0", "1")]
    assert summary["success_iqm"] == pytest.approx(np.mean(finals))  # IQM of 2 = their mean
    assert (swept / "learning_curves.png").stat().st_size > 1000
    assert "2 seeds" in (swept / "summary.md").read_text()


@pytest.mark.slow
def test_a_rerun_skips_done_seeds_and_retrains_a_half_done_one(
    swept: Path, tiny_config: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    trained: list[int] = []
    real = sweep._train_seed
    monkeypatch.setattr(sweep, "_train_seed", lambda run: (trained.append(run.seed), real(run))[1])
    (swept / "seed-2").mkdir()
    (swept / "seed-2" / "model.zip").write_bytes(b"half-written")  # stopped before metadata
    said: list[str] = []
    summary = sweep.run_sweep(tiny_config, [0, 1, 2], swept, notify=said.append, progress=False)
    assert trained == [2]
    assert said[0] == f"seeds [0, 1] already done in {swept}, skipping them"
    assert summary["seeds"] == [0, 1, 2] and (swept / "seed-2" / "metadata.json").is_file()
    assert not (swept / "seed-2.partial").exists()


def test_bad_sweep_arguments_are_named(tiny_config: Path, tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"repeated seeds in \[1, 1\]"):
        sweep.run_sweep(tiny_config, [1, 1], tmp_path)
    with pytest.raises(ValueError, match="not found"):
        sweep.run_sweep(tmp_path / "nope.yaml", [0], tmp_path)
    with pytest.raises(ValueError, match="unknown backend 'dask'"):
        sweep.run_sweep(tiny_config, [0], tmp_path, backend="dask")


@pytest.mark.slow
def test_a_ray_sweep_trains_the_same_model_as_a_local_one(
    swept: Path, tiny_config: Path, tmp_path: Path
) -> None:
    if importlib.util.find_spec("ray") is None:  # not importing it: the backend configures it
        pytest.skip("Ray is not installed")
    from radial_ibvs_agents.experiments.backends import RayBackend

    backend = RayBackend(num_cpus=2)  # reused if a Ray instance already runs here
    try:
        sweep.run_sweep(tiny_config, [1], tmp_path, backend="ray", notify=lambda _: None)
    finally:
        backend.close()
    mine = json.loads((tmp_path / "seed-1" / "metadata.json").read_text())
    local = json.loads((swept / "seed-1" / "metadata.json").read_text())
    assert mine["learning_curve"] == local["learning_curve"]  # same seed, same training


# --- statistics ---------------------------------------------------------------------------------
def test_iqm_is_the_mean_of_the_middle_half() -> None:
    assert iqm([0, 1, 2, 3, 4, 5, 6, 7]) == pytest.approx(3.5)
    assert iqm([0.0, 0.5, 0.5, 100.0]) == pytest.approx(0.5)  # outliers cut
    assert math.isnan(iqm([]))


def test_iqm_interval_brackets_the_point_and_is_reproducible() -> None:
    scores = [[0.6, 0.7, 0.8, 0.9, 0.75], [0.2, 0.3, 0.25]]
    point, low, high = iqm_interval(scores, seed=3)
    assert low <= point <= high and 0.0 <= low < high <= 1.0
    assert iqm_interval(scores, seed=3) == (point, low, high)
    assert iqm_interval([[0.5, 0.5, 0.5]]) == (0.5, 0.5, 0.5)
    one = iqm_interval([[0.7]])
    assert one[0] == 0.7 and math.isnan(one[1]) and math.isnan(one[2])


def test_the_bootstrap_is_stratified_by_task() -> None:
    # stratified: every resample keeps 4 scores of each task, so the IQM never leaves the
    # band a pooled resampling (all 8 from the low task) would reach
    _, low, high = iqm_interval([[0.0, 0.0, 0.1, 0.1], [0.9, 0.9, 1.0, 1.0]], n_resamples=500)
    assert low > 0.3 and high < 0.7


@pytest.mark.parametrize(
    ("scores", "kwargs", "match"),
    [([], {}, "at least one score"), ([[]], {}, "at least one score"),
     ([[0.1, 0.2]], {"confidence": 1.5}, r"confidence must be in \(0, 1\), got 1.5")],
)  # fmt: skip
def test_bad_statistics_input_is_named(scores, kwargs, match) -> None:
    with pytest.raises(ValueError, match=match):
        iqm_interval(scores, **kwargs)


DAGGER_TINY = """
dagger:
  env_kwargs: {scenario: random, physics: kinematic, obs_mode: features, goal_depths: true,
               max_landmarks: 16}
  teacher_kwargs: {goal_tolerance: 0.015, waypoint_tolerance: 0.1, hold_radius: 0.0,
                   drive_gate: 1.57, reverse: false, align_radius: 0.04}
  n_envs: 8
  rounds: 2
  steps_per_round: 256
  updates_per_round: 5
  batch_size: 64
  dataset_size: 2000
  net_arch: [32]
  eval_episodes: 2
"""


@pytest.mark.slow
def test_a_dagger_config_sweeps_as_distill_does(tmp_path: Path) -> None:
    """A config with a ``dagger:`` section trains each seed as ``radial-ibvs distill``; the
    summary takes each student's kept round."""
    config = tmp_path / "dagger.yaml"
    config.write_text(DAGGER_TINY)
    out = tmp_path / "sweep"
    assert main(["sweep", "--config", str(config), "--seeds", "0", "1", "--out", str(out),
                 "--no-progress"]) == 0  # fmt: skip
    summary = json.loads((out / "summary.json").read_text())
    for seed in (0, 1):
        metadata = json.loads((out / f"seed-{seed}" / "metadata.json").read_text())
        assert metadata["trained_by"] == "dagger" and metadata["seed"] == seed
        assert metadata["config"]["file"] == str(config)  # not the worker's scratch copy
        assert (out / f"seed-{seed}" / "rounds" / "round_1").is_dir()
        kept = metadata["learning_curve"][metadata["best_round"]]["success_rate"]
        assert summary["final_success"][str(seed)] == kept
    assert (out / "learning_curves.png").stat().st_size > 1000
    with pytest.raises(ValueError, match=r"DAgger config: it takes no \['total_timesteps'\]"):
        sweep.run_sweep(config, [0], out, total_timesteps=100)
