"""Resuming training never unpickles: neither a payload in the resumed ``model.zip``'s data nor a
``vecnormalize.pkl`` runs (``pickle_payloads``), and a pickled weights file is refused."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from pickle_payloads import payload, poison_zip

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents.cli import main

CONFIG = Path(__file__).resolve().parents[4] / "configs" / "agents" / "ppo_parking.yaml"


@pytest.fixture(scope="module")
def trained(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("train") / "ppo"
    argv = ["train", "--config", str(CONFIG), "--total-timesteps", "256", "--out", str(out)]
    assert main([*argv, "--no-progress", "--env-kwarg", "task=1"]) == 0
    return out


def _resume_argv(source: Path, out: Path) -> list[str]:
    argv = ["train", "--config", str(CONFIG), "--total-timesteps", "256", "--resume", str(source)]
    return [*argv, "--out", str(out), "--no-progress", "--env-kwarg", "task=1"]


def test_resume_never_unpickles(trained: Path, tmp_path: Path) -> None:
    source = tmp_path / "source"
    shutil.copytree(trained, source)
    marker = tmp_path / "marker"
    poison_zip(source / "model.zip", marker)
    (source / "vecnormalize.pkl").write_bytes(payload(marker))
    assert main(_resume_argv(source, tmp_path / "more")) == 0
    steps = json.loads((tmp_path / "more" / "metadata.json").read_text())["total_timesteps"]
    assert steps > json.loads((trained / "metadata.json").read_text())["total_timesteps"]
    # a weights file that is a pickle: torch's weights-only reader refuses it
    poison_zip(source / "model.zip", marker, member="policy.pth")
    assert main(_resume_argv(source, tmp_path / "again")) == 2
    assert not marker.exists()
