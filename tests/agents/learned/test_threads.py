"""A loaded policy computes a small batch on one torch thread and restores the caller's count."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_agents import load
from radial_ibvs_agents.learned.files import threads
from radial_ibvs_agents.learned.files.threads import SMALL_BATCH, threads_for


@pytest.fixture
def caller_threads():
    before = torch.get_num_threads()
    torch.set_num_threads(3)
    yield 3
    torch.set_num_threads(before)


def _observations(policy, n: int) -> dict[str, np.ndarray]:
    envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=n, **policy.env_kwargs)
    obs, _ = envs.reset(seed=0)
    envs.close()
    return obs


@pytest.mark.parametrize("name", ["dagger-student"])
def test_one_observation_runs_on_one_thread_and_the_callers_count_comes_back(
    name: str, caller_threads: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    policy = load(name)
    seen: list[int] = []
    real = torch.set_num_threads
    monkeypatch.setattr(torch, "set_num_threads", lambda n: (seen.append(n), real(n))[1])
    one = {k: v[0] for k, v in _observations(policy, 1).items()}
    action, _ = policy.predict(one)
    assert action.shape == (2,)
    assert seen == [1, caller_threads]  # one thread for the call, then the caller's again
    assert torch.get_num_threads() == caller_threads


def test_a_large_batch_keeps_the_callers_threads(
    caller_threads: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    policy = load("dagger-student")
    seen: list[int] = []
    monkeypatch.setattr(torch, "set_num_threads", seen.append)
    actions, _ = policy.predict(_observations(policy, SMALL_BATCH))
    assert actions.shape == (SMALL_BATCH, 2) and seen == []


def test_the_callers_threads_come_back_after_an_error(caller_threads: int) -> None:
    with pytest.raises(RuntimeError, match="inside"), threads_for(1) as used:
        assert used == 1 and torch.get_num_threads() == 1
        raise RuntimeError("inside")
    assert torch.get_num_threads() == caller_threads
    with threads_for(SMALL_BATCH) as used:
        assert used == caller_threads
    assert threads.__doc__ is not None and "not thread-safe" in threads.__doc__


def test_the_rows_of_an_observation_are_counted_for_dict_and_box_spaces() -> None:
    from gymnasium import spaces

    from radial_ibvs_agents.learned.files.loading import _rows

    points = spaces.Dict({"points": spaces.Box(-1.0, 1.0, (4,))})
    assert _rows({"points": np.zeros(4)}, points) == 1
    assert _rows({"points": np.zeros((7, 4))}, points) == 7
    image = spaces.Box(0, 255, (2, 84, 84), dtype=np.uint8)
    assert _rows(np.zeros((2, 84, 84)), image) == 1
    assert _rows(np.zeros((5, 2, 84, 84)), image) == 5
