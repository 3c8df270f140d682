"""Every size a config can ask for has a bound, checked before anything is built.

The bounds are in :mod:`radial_ibvs_gym.limits`; each refusal names the file or argument,
the key and the limit. The values here would otherwise allocate terabytes (a network of
``[1000000, 1000000]``, a DAgger dataset of ``1e12`` transitions) or take a minute a frame.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import pytest
import yaml

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents.learned.dagger.distill_config import load_dagger_config
from radial_ibvs_agents.learned.training.zoo_config import load_train_config
from radial_ibvs_gym import limits

ROOT = Path(__file__).resolve().parents[2]
TRAIN = ROOT / "configs" / "agents" / "ppo_parking.yaml"
DAGGER = ROOT / "configs" / "agents" / "dagger_student.yaml"


def _write(tmp_path: Path, data: Any) -> Path:
    path = tmp_path / "asks-too-much.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


@pytest.mark.parametrize(
    ("changes", "named"),
    [
        ({"net_arch": [1_000_000, 1_000_000]}, "MAX_LAYER_WIDTH"),
        ({"net_arch": [64] * 65}, "MAX_LAYERS"),
        ({"dataset_size": 1e12}, "MAX_DATASET_SIZE"),
        ({"batch_size": 1 << 30}, "MAX_BATCH_SIZE"),
        ({"n_envs": 1_000_000}, "MAX_NUM_ENVS"),
        ({"eval_episodes": 10**9}, "MAX_EPISODES"),
        ({"steps_per_round": 1 << 40}, "MAX_ROLLOUT_SIZE"),
        ({"history": {"frames": 100_000, "keys": ["points"]}}, "MAX_HISTORY_FRAMES"),
    ],
)
def test_a_dagger_config_that_asks_too_much_is_refused(
    tmp_path: Path, changes: dict[str, Any], named: str
) -> None:
    data = yaml.safe_load(DAGGER.read_text())
    data["dagger"].update(changes)
    with pytest.raises(ValueError, match=named) as error:
        load_dagger_config(_write(tmp_path, data))
    assert "asks-too-much.yaml" in str(error.value)
    assert next(iter(changes)) in str(error.value)


@pytest.mark.parametrize(
    ("changes", "named"),
    [
        ({"policy_kwargs": "dict(net_arch=[1000000, 1000000])"}, "MAX_LAYER_WIDTH"),
        ({"policy_kwargs": "dict(net_arch=dict(pi=[64], vf=[10000000]))"}, "MAX_LAYER_WIDTH"),
        ({"n_envs": 1_000_000}, "MAX_NUM_ENVS"),
        ({"n_steps": 1 << 30}, "MAX_ROLLOUT_SIZE"),
        ({"n_envs": 4096, "n_steps": 8192}, "MAX_ROLLOUT_SIZE"),  # each fine, not together
        ({"batch_size": 1 << 30}, "MAX_BATCH_SIZE"),
    ],
)
def test_a_training_config_that_asks_too_much_is_refused(
    tmp_path: Path, changes: dict[str, Any], named: str
) -> None:
    data = yaml.safe_load(TRAIN.read_text())
    data["RadialIBVS/Parking-v0"].update(changes)
    with pytest.raises(ValueError, match=named) as error:
        load_train_config(_write(tmp_path, data))
    assert "asks-too-much.yaml" in str(error.value)


def test_a_replay_buffer_has_a_bound(tmp_path: Path) -> None:
    source = ROOT / "configs" / "agents" / "sac_her.yaml"
    data = yaml.safe_load(source.read_text())
    (section,) = [v for k, v in data.items() if k.startswith("RadialIBVS/")]
    section["buffer_size"] = 1 << 40
    with pytest.raises(ValueError, match="buffer_size"):
        load_train_config(_write(tmp_path, data))
    assert limits.MAX_BUFFER_SIZE == 1 << 24


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"image_blur": 1e6}, "image_blur"),
        ({"image_blur": float("nan")}, "image_blur"),
        ({"image_noise": 1e9}, "image_noise"),
        ({"image_size": 100_000}, "image_size"),
        ({"image_size": 8}, "image_size"),
        ({"goal_image_frames": 10_000_000}, "goal_image_frames"),
    ],
)
def test_the_envs_image_arguments_are_bounded(kwargs: dict[str, Any], named: str) -> None:
    with pytest.raises(ValueError, match=named):
        gym.make("RadialIBVS/Parking-v0", physics="kinematic", **kwargs)


def test_the_image_env_bounds_its_frames_too() -> None:
    with pytest.raises(ValueError, match="blur_sigma"):
        gym.make("RadialIBVS/ParkingImage-v0", physics="kinematic", image_blur=1e6)
    with pytest.raises(ValueError, match="size must be an integer"):
        gym.make("RadialIBVS/ParkingImage-v0", physics="kinematic", image_size=100_000)
