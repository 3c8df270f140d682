"""A model folder is written all at once: no half-written model, no stale file of an older one."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from radial_ibvs_agents import load, make_vec_env, save_model_dir
from radial_ibvs_agents.learned.files.model_dir import BEST_FILES, replace_model_files


def _leftovers(parent: Path) -> list[str]:
    return sorted(p.name for p in parent.iterdir() if p.name.startswith("."))


def test_a_new_folder_gets_the_files_and_no_staging_is_left(tmp_path: Path) -> None:
    out = tmp_path / "runs" / "model"
    with replace_model_files(out) as staging:
        assert staging.parent == out.parent and not any(staging.iterdir())
        (staging / "policy.json").write_text("{}")
    assert sorted(p.name for p in out.iterdir()) == ["policy.json"]
    assert _leftovers(out.parent) == []
    assert out.stat().st_mode & 0o777 == 0o777 & ~_umask()  # not mkdtemp's 0700


def test_owned_files_the_new_model_lacks_go_and_the_rest_stays(tmp_path: Path) -> None:
    out = tmp_path / "model"
    (out / "best").mkdir(parents=True)
    (out / "best" / "best_model.zip").write_bytes(b"zip")
    (out / "normalization.npz").write_bytes(b"old statistics")  # owned: a normalised model's
    (out / "policy.json").write_text("old")
    (out / "progress.csv").write_text("steps\n1\n")  # not owned: a run's log
    with replace_model_files(out) as staging:
        (staging / "policy.json").write_text("new")
        (staging / "metadata.json").write_text("{}")
    names = sorted(p.name for p in out.iterdir())
    assert names == ["best", "metadata.json", "policy.json", "progress.csv"]
    assert (out / "policy.json").read_text() == "new"
    assert (out / "progress.csv").read_text() == "steps\n1\n"
    assert (out / "best" / "best_model.zip").read_bytes() == b"zip"
    assert _leftovers(tmp_path) == []


def test_a_failed_writer_leaves_the_old_model_as_it_was(tmp_path: Path) -> None:
    out = tmp_path / "model"
    out.mkdir()
    (out / "policy.json").write_text("old")
    (out / "normalization.npz").write_bytes(b"old")
    with pytest.raises(RuntimeError, match="disk full"), replace_model_files(out) as staging:
        (staging / "policy.json").write_text("half")
        raise RuntimeError("disk full")
    assert sorted(p.name for p in out.iterdir()) == ["normalization.npz", "policy.json"]
    assert (out / "policy.json").read_text() == "old"
    assert _leftovers(tmp_path) == []


def test_the_best_folder_keeps_the_zip_that_sb3_writes_there(tmp_path: Path) -> None:
    best = tmp_path / "best"
    best.mkdir()
    (best / "best_model.zip").write_bytes(b"zip")
    with replace_model_files(best, BEST_FILES) as staging:
        (staging / "policy.json").write_text("{}")
    assert sorted(p.name for p in best.iterdir()) == ["best_model.zip", "policy.json"]


@pytest.mark.parametrize("kind", ["file", "symlink"])
def test_a_target_that_is_not_a_folder_is_refused(tmp_path: Path, kind: str) -> None:
    out = tmp_path / "model"
    if kind == "file":
        out.write_text("x")
    else:
        (tmp_path / "elsewhere").mkdir()
        out.symlink_to(tmp_path / "elsewhere")
    with pytest.raises(ValueError, match="not a folder"), replace_model_files(out):
        pass
    assert _leftovers(tmp_path) == []


def test_save_model_dir_over_a_normalised_model_leaves_no_statistics(tmp_path: Path) -> None:
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecNormalize

    venv = make_vec_env("RadialIBVS/Parking-v0", 2, seed=0, physics="kinematic")
    normalised = VecNormalize(venv)
    out = tmp_path / "model"
    save_model_dir(PPO("MultiInputPolicy", normalised, n_steps=8, batch_size=8), out)
    assert (out / "normalization.npz").is_file()
    plain = PPO("MultiInputPolicy", venv, n_steps=8, batch_size=8, seed=1)
    save_model_dir(plain, out)
    assert not (out / "normalization.npz").exists()  # the loaded policy is the saved one
    obs = venv.reset()
    one = {k: v[:1] for k, v in obs.items()}
    want, _ = plain.predict(one, deterministic=True)
    np.testing.assert_allclose(load(out).predict(one)[0], want, atol=1e-6)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
