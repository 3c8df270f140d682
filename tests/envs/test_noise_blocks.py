"""Pixel noise drawn ahead in blocks: the bits of one draw a step, the generator left alike."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import radial_ibvs_gym  # noqa: F401  (registers the environments)
from radial_ibvs_gym.envs.camera_rows import CameraRows
from radial_ibvs_gym.envs.noise_blocks import MAX_BLOCK, NOISE_BLOCK_BYTES, NoiseBlocks


@settings(max_examples=40, deadline=None)
@given(
    block=st.integers(1, 9),
    landmarks=st.integers(1, 6),
    steps=st.lists(st.integers(0, 20), min_size=1, max_size=4),
    seed=st.integers(0, 2**32 - 1),
)
def test_blocks_give_the_draws_and_leave_the_generator_as_one_draw_a_step(
    block: int, landmarks: int, steps: list[int], seed: int
) -> None:
    # episodes of `steps` steps each; between them the env's reset reads the generator
    ahead, stepwise = np.random.default_rng(seed), np.random.default_rng(seed)
    blocks = NoiseBlocks(1, landmarks, block)
    env = np.array([0])
    for length in steps:
        for _ in range(length):
            got = blocks.draw(env, [ahead])[0]  # env 0's generator
            np.testing.assert_array_equal(got, stepwise.standard_normal((landmarks, 2)))
        blocks.sync(0, ahead)
        # the reset's own draws: the same stream on both sides
        assert ahead.integers(2**63) == stepwise.integers(2**63)
        assert ahead.random() == stepwise.random()


def test_envs_draw_from_their_own_generators_in_any_subset() -> None:
    rngs = [np.random.default_rng(s) for s in (1, 2, 3)]
    twins = [np.random.default_rng(s) for s in (1, 2, 3)]
    blocks = NoiseBlocks(3, 4, block=3)
    order = [[0, 1, 2], [2], [0, 2], [1], [0, 1, 2], [0, 1, 2], [1, 2]]
    for subset in order:
        idx = np.array(subset)
        got = blocks.draw(idx, rngs)
        want = np.stack([twins[i].standard_normal((4, 2)) for i in subset])
        np.testing.assert_array_equal(got, want)
    for i in range(3):
        blocks.sync(i, rngs[i])
        assert rngs[i].bit_generator.state == twins[i].bit_generator.state


def test_a_dropped_block_leaves_a_new_generator_alone() -> None:
    blocks = NoiseBlocks(1, 2, block=4)
    old = np.random.default_rng(0)
    blocks.draw(np.array([0]), [old])
    new, twin = np.random.default_rng(7), np.random.default_rng(7)
    blocks.drop(0)
    blocks.sync(0, new)  # nothing saved any more: the new generator is not touched
    assert new.bit_generator.state == twin.bit_generator.state
    np.testing.assert_array_equal(
        blocks.draw(np.array([0]), [new])[0], twin.standard_normal((2, 2))
    )


def test_the_blocks_memory_is_bounded() -> None:
    assert NoiseBlocks(4, 16).block == MAX_BLOCK
    big = NoiseBlocks(4096, 64)
    assert big.block * 4096 * 64 * 2 * 8 <= NOISE_BLOCK_BYTES
    assert NoiseBlocks(10**6, 64).block == 1  # never less than one step
    with pytest.raises(ValueError, match="block must be >= 1"):
        NoiseBlocks(1, 2, block=0)


def test_a_block_needs_a_generator() -> None:
    with pytest.raises(ValueError, match="env 0 has no generator"):
        NoiseBlocks(1, 2).draw(np.array([0]), [None])


def _steps(block: int | None, steps: int, **kwargs: Any) -> list[Any]:
    """Observations of a native vector env whose noise blocks hold ``block`` steps."""
    envs = gym.make_vec(
        "RadialIBVS/Parking-v0", num_envs=3, vectorization_mode="vector_entry_point", **kwargs
    )
    env = envs.unwrapped
    env._cameras = CameraRows(3, env.scenario.n_landmarks, block)  # before the first reset
    shared = []
    obs, _ = envs.reset(seed=5)
    out = [obs]
    rng = np.random.default_rng(0)
    for t in range(steps):
        if t == steps // 2:  # a reset without seeds: each generator goes on
            obs, _ = envs.reset()
            out.append(obs)
        obs, *_ = envs.step(rng.uniform(-1, 1, (3, 2)).astype(np.float32))
        out.append(obs)
        shared.append(env._cameras.shared)
    return [out, shared]


def test_the_vector_env_steps_the_same_with_blocks_of_any_size() -> None:
    # each robot's mirror drawn per episode (A or B): the cameras share one reflection at some
    # steps and not at others, so both paths run, and the blocks are synced at every switch
    camera = {
        "mirror": "A",
        "non_central_offset": 0.01,
        "imperfection_ranges": {"principal_point_offset": 2.0, "pixel_noise_std": [0.0, 1.0]},
    }
    kwargs: dict[str, Any] = {
        "scenario": "random", "physics": "kinematic", "camera": camera, "mirrors": ["A", "B"],
        "max_episode_steps": 15, "obs_mode": "features", "max_landmarks": 12,
    }  # fmt: skip
    one, one_shared = _steps(1, 120, **kwargs)
    ahead, ahead_shared = _steps(32, 120, **kwargs)
    assert one_shared == ahead_shared
    assert any(ahead_shared) and not all(ahead_shared)  # both paths ran
    for a, b in zip(one, ahead, strict=True):
        for key in a:
            np.testing.assert_array_equal(a[key], b[key], err_msg=key)
