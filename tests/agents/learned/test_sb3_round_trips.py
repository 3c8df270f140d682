"""Every stable-baselines3 algorithm round-trips through ``save_model_dir``, ``load`` and the CLI.

Each model is trained a few hundred steps, saved with :func:`save_model_dir`, loaded, and run
beside SB3's own ``predict`` on the model's own ``VecEnv`` (its frame stack and channels-first
images included): the loaded policy, fed the plain env's observations, acts the same, action
for action. Then ``radial-ibvs evaluate`` runs the folder. The image models render every step
and are marked slow.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest

import radial_ibvs_gym  # noqa: F401
from radial_ibvs_agents import load, make_vec_env, save_model_dir
from radial_ibvs_agents.cli import main

sb3 = pytest.importorskip("stable_baselines3")
contrib = pytest.importorskip("sb3_contrib")

WORLD = {"physics": "kinematic", "scenario": "random"}
STEPS = 25  # compared steps, or until a robot's episode ends


def _parking(n: int = 2) -> Any:
    return make_vec_env("RadialIBVS/Parking-v0", n, seed=0, **WORLD)


def _goal(n: int = 1) -> Any:
    return make_vec_env("RadialIBVS/ParkingGoal-v1", n, seed=0, **WORLD)


def _images(layout: str = "channels", stack: int = 0) -> Any:
    from stable_baselines3.common.env_util import make_vec_env as sb3_make_vec_env
    from stable_baselines3.common.vec_env import VecFrameStack

    kwargs = {"image_layout": layout, "image_size": 48, **WORLD}
    venv = sb3_make_vec_env("RadialIBVS/ParkingImage-v0", n_envs=2, seed=0, env_kwargs=kwargs)
    return VecFrameStack(venv, stack) if stack else venv


def _her() -> dict[str, Any]:
    from stable_baselines3 import HerReplayBuffer

    # learning starts after the first episode ends (600 steps), where HER can sample
    return {"replay_buffer_class": HerReplayBuffer, "learning_starts": 610}


def _model(case: str) -> tuple[Any, int]:
    """Return a model of ``case`` and the steps to train it."""
    from sb3_contrib import TQC, RecurrentPPO
    from stable_baselines3 import A2C, PPO, SAC, TD3

    small = {"net_arch": [32, 32]}
    on = {"n_steps": 32, "policy_kwargs": small, "seed": 0}
    off = {"learning_starts": 100, "policy_kwargs": small, "seed": 0}
    image = {"n_steps": 16, "batch_size": 32, "seed": 0}
    her = {**_her(), "seed": 0}
    models = {
        "ppo": lambda: (PPO("MultiInputPolicy", _parking(), batch_size=64, **on), 256),
        "a2c": lambda: (A2C("MultiInputPolicy", _parking(), **on), 256),
        "sac": lambda: (SAC("MultiInputPolicy", _parking(), **off), 300),
        "td3": lambda: (TD3("MultiInputPolicy", _parking(), **off), 300),
        "tqc": lambda: (TQC("MultiInputPolicy", _parking(), **off), 300),
        "sac-her": lambda: (SAC("MultiInputPolicy", _goal(), policy_kwargs=small, **her), 640),
        "td3-her": lambda: (TD3("MultiInputPolicy", _goal(), policy_kwargs=small, **her), 640),
        "tqc-her": lambda: (TQC("MultiInputPolicy", _goal(), policy_kwargs=small, **her), 640),
        "recurrent-ppo": lambda: (
            RecurrentPPO("MultiInputLstmPolicy", _parking(), n_steps=32, batch_size=64, seed=0),
            256,
        ),
        "cnn": lambda: (PPO("CnnPolicy", _images(), **image), 64),
        "cnn-frame-stack": lambda: (PPO("CnnPolicy", _images(stack=3), **image), 64),
        "image-dict": lambda: (PPO("MultiInputPolicy", _images("dict"), **image), 64),
    }
    return models[case]()


def _compare(model: Any, folder: Path) -> None:
    """SB3's ``predict`` on the model's VecEnv equals the loaded policy's on plain envs."""
    venv = model.get_env()
    n = venv.num_envs
    meta = json.loads((folder / "metadata.json").read_text())
    envs = [gym.make(meta["env_id"], **meta["env_kwargs"]) for _ in range(n)]
    venv.seed(1000)
    sb3_obs = venv.reset()
    raw = [env.reset(seed=1000 + i)[0] for i, env in enumerate(envs)]
    policy = load(folder)
    sb3_state, state = None, None
    starts = np.ones(n, dtype=bool)
    for step in range(STEPS):
        batch = (
            {k: np.stack([o[k] for o in raw]) for k in raw[0]}
            if isinstance(raw[0], dict)
            else np.stack(raw)
        )
        expected, sb3_state = model.predict(sb3_obs, sb3_state, starts, deterministic=True)
        actions, state = policy.predict(batch, state, starts, deterministic=True)
        np.testing.assert_allclose(actions, expected, rtol=0, atol=1e-6, err_msg=f"step {step}")
        sb3_obs, _, dones, _ = venv.step(expected)
        if dones.any():  # a robot's episode ended (a collision): SB3 has reset it, stop here
            break
        raw = [env.step(a)[0] for env, a in zip(envs, expected, strict=True)]
        starts[:] = False
    assert step >= 2, "compare more than the first steps"
    for env in envs:
        env.close()


def _round_trip(case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> dict:
    model, steps = _model(case)
    model.learn(steps)
    folder = save_model_dir(model, tmp_path / case)
    meta = json.loads((folder / "metadata.json").read_text())
    _compare(model, folder)
    assert main(["evaluate", "--policy", str(folder), "--scenario", "random", "--episodes", "1",
                 "--env-kwarg", "physics=kinematic"]) == 0  # fmt: skip
    assert "ends: success" in capsys.readouterr().out  # one episode run to its end
    return meta


@pytest.mark.parametrize(
    "case",
    [
        "ppo",
        "a2c",
        "sac",
        "td3",
        "tqc",
        pytest.param("sac-her", marks=pytest.mark.slow),  # HER trains past a 600-step episode
        pytest.param("td3-her", marks=pytest.mark.slow),
        pytest.param("tqc-her", marks=pytest.mark.slow),
        "recurrent-ppo",
    ],
)
def test_each_algorithm_round_trips(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    meta = _round_trip(case, tmp_path, capsys)
    assert "observation_wrappers" not in meta  # the env's observations, as they are


@pytest.mark.slow
@pytest.mark.parametrize(
    ("case", "wrappers"),
    [
        ("cnn", ["transpose_image"]),
        ("cnn-frame-stack", ["frame_stack", "transpose_image"]),
        ("image-dict", ["transpose_image"]),
    ],
)
def test_image_models_round_trip_with_their_wrappers(
    case: str, wrappers: list[str], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    meta = _round_trip(case, tmp_path, capsys)
    assert [w["name"] for w in meta["observation_wrappers"]] == wrappers


@pytest.mark.parametrize("algo", ["ppo", "a2c", "sac", "td3", "tqc", "recurrent_ppo"])
def test_a_bare_sb3_zip_is_told_by_its_algorithm(algo: str, tmp_path: Path) -> None:
    """``--trust-model`` with only SB3's model.zip: PPO and A2C share policies, as do
    PPO and its recurrent form's settings; each is told apart from plain JSON."""
    from radial_ibvs_agents.learned.files.model_files import algorithms
    from radial_ibvs_agents.learned.files.sb3_zip import algo_of_zip

    policy = "MultiInputLstmPolicy" if algo == "recurrent_ppo" else "MultiInputPolicy"
    model = algorithms()[algo](policy, _parking(), policy_kwargs={"net_arch": [8]})
    model.save(tmp_path / "model.zip")
    assert algo_of_zip(tmp_path / "model.zip", "m") == algo


def test_a_wrapper_that_cannot_be_replayed_is_refused_by_name(tmp_path: Path) -> None:
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecExtractDictObs

    model = PPO("MlpPolicy", VecExtractDictObs(_parking(), "points"), n_steps=8, batch_size=8)
    with pytest.raises(ValueError, match="VecExtractDictObs changes what the model sees"):
        save_model_dir(model, tmp_path / "m")
    assert not (tmp_path / "m").exists()


def _stacked(tmp_path: Path) -> Path:
    from stable_baselines3 import PPO
    from stable_baselines3.common.vec_env import VecFrameStack

    venv = VecFrameStack(_parking(), 3)
    model = PPO("MultiInputPolicy", venv, n_steps=8, batch_size=8, policy_kwargs={"net_arch": [8]})
    return save_model_dir(model, tmp_path / "stacked")


def test_a_frame_stack_of_points_is_replayed_and_starts_anew_with_each_episode(
    tmp_path: Path,
) -> None:
    """Zeros before an episode's first frame, as SB3's ``VecFrameStack`` after a ``done``."""
    folder = _stacked(tmp_path)
    policy = load(folder)
    assert [w["name"] for w in policy.wrappers] == ["frame_stack"]
    env = gym.make("RadialIBVS/Parking-v0", **WORLD)
    obs, _ = env.reset(seed=3)
    first, state = policy.predict(obs, None, np.ones(1, dtype=bool))
    for _ in range(4):
        obs, *_ = env.step(first)
        _, state = policy.predict(obs, state, np.zeros(1, dtype=bool))
    obs, _ = env.reset(seed=3)
    again, _ = policy.predict(obs, state, np.ones(1, dtype=bool))  # a new episode, same stack
    np.testing.assert_array_equal(again, first)
    with pytest.raises(ValueError, match=r"becomes .* not the model's"):
        policy.check_observation_space(gym.make("RadialIBVS/Parking-v0", max_landmarks=12,
                                                **WORLD).observation_space)  # fmt: skip


@pytest.mark.parametrize(
    ("entry", "match"),
    [
        ("not a list", "observation_wrappers must be a list"),
        ([{"name": "exec"}], r"observation_wrappers\[0\] must be an object whose name"),
        ([{"name": "frame_stack", "n_stack": 10**9, "channels_order": "last"}], r".*\]: n_stack"),
        ([{"name": "frame_stack", "n_stack": 3, "channels_order": "up"}], r".*\]: channels_order"),
    ],
)
def test_hostile_wrapper_entries_are_refused_naming_the_file(
    entry: Any, match: str, tmp_path: Path
) -> None:
    folder = _stacked(tmp_path)
    meta = json.loads((folder / "metadata.json").read_text())
    (folder / "metadata.json").write_text(json.dumps({**meta, "observation_wrappers": entry}))
    with pytest.raises(ValueError, match=f"metadata.json: {match}"):
        load(folder)


def test_a_model_that_runs_in_no_variant_fails_the_benchmark(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A variant a model cannot take is a designed skip; a model that runs in none is an error."""
    folder = _stacked(tmp_path)  # 8 landmarks: the lab's 9 beacons do not fit
    argv = ["benchmark", "--policies", str(folder), "--episodes", "2", "--workers", "1",
            "--no-progress"]  # fmt: skip
    assert main([*argv, "--suites", "paper-lab", "--out", str(tmp_path / "lab")]) == 1
    captured = capsys.readouterr()
    assert f"{folder} ran in no variant of paper-lab" in captured.err
    assert f"skipped {folder} on paper-lab" in captured.out
    assert main([*argv, "--suites", "paper-lab", "held-out", "--out", str(tmp_path / "two")]) == 0


@pytest.mark.parametrize("shape", [[100_000, 100_000], [-1, 4]])
def test_a_space_described_by_one_number_cannot_ask_for_any_size(
    shape: list[int], tmp_path: Path
) -> None:
    """A bound stored as one number is spread over the shape: the shape is bounded first."""
    from radial_ibvs_agents.learned.files.model_files import space_from_json

    described = {"type": "Box", "shape": shape, "dtype": "float32", "low": 0.0, "high": 1.0}
    with pytest.raises(ValueError, match="MAX_SPACE_ELEMENTS"):
        space_from_json(described, "observation_space")
    folder = _stacked(tmp_path)
    meta = json.loads((folder / "metadata.json").read_text())
    (folder / "metadata.json").write_text(json.dumps({**meta, "env_observation_space": described}))
    with pytest.raises(ValueError, match=r"env_observation_space.*MAX_SPACE_ELEMENTS"):
        load(folder)


def test_an_image_model_saved_with_its_plain_env_records_the_transposition(tmp_path: Path) -> None:
    """SB3 transposes channel-last images itself: saved with ``env=`` the env as made (no
    wrapper to read), the model still records it, and evaluates on that env's images."""
    from stable_baselines3 import PPO

    env = gym.make("RadialIBVS/ParkingImage-v0", image_layout="channels", image_size=48, **WORLD)
    model = PPO("CnnPolicy", env, n_steps=8, batch_size=8, seed=0)
    folder = save_model_dir(model, tmp_path / "cnn", env=env)
    policy = load(folder)
    assert [w["name"] for w in policy.wrappers] == ["transpose_image"]
    policy.check_observation_space(env.observation_space)
    obs, _ = env.reset(seed=0)
    expected, _ = model.predict(np.transpose(obs, (2, 0, 1)), deterministic=True)
    np.testing.assert_allclose(policy.predict(obs)[0], expected, rtol=0, atol=1e-6)
    env.close()
