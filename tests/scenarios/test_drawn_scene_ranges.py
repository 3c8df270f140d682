"""Scenarios that draw their landmark count and camera height per episode.

An episode that draws fewer landmarks than the scenario's most is observed as that episode's
own scene: the filled-in landmarks are never visible, and every other value is the one an env
of that fixed scene gives.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import radial_ibvs_gym
from radial_ibvs_gym.config import ConfigError
from radial_ibvs_gym.scenarios import Episode, load_scenario

CONFIGS = Path(radial_ibvs_gym.__file__).resolve().parents[1] / "configs"
RANGES: dict[str, Any] = {
    "random_landmarks": {"count": [4, 9], "height": [0.2, 2.4]},
    "camera_height": [1.3, 2.2],
}
#: the ranges, and the mirror drawn per episode too
DRAWN: dict[str, Any] = {**RANGES, "mirrors": ["A", "B"]}


def test_a_range_of_width_zero_draws_nothing_more() -> None:
    fixed = load_scenario("random")
    ranged = load_scenario(
        "random",
        random_landmarks={"count": [8, 8], "height": [0.2, 2.4]},
        camera_height=[1.8, 1.8],
    )
    for seed in range(10):
        a = fixed.sample(np.random.default_rng(seed))
        b = ranged.sample(np.random.default_rng(seed))
        for x, y in zip(a, b, strict=True):
            np.testing.assert_array_equal(x, y)
        assert a.camera_height == 1.8


def test_counts_and_heights_are_drawn_over_their_ranges() -> None:
    s = load_scenario("random", **RANGES)
    assert s.n_landmarks == 9
    rng = np.random.default_rng(0)
    episodes = [s.sample(rng) for _ in range(300)]
    counts = {len(e.landmarks) for e in episodes}
    assert counts == set(range(4, 10))
    heights = np.array([e.camera_height for e in episodes])
    assert 1.3 <= heights.min() < 1.4 and 2.1 < heights.max() <= 2.2
    for e in episodes[:30]:  # each episode's visibility checks used its own height
        seen = s.visible(e.goal, e.landmarks, camera_height=e.camera_height)
        assert seen.sum() >= s.config.min_visible_at_goal


@pytest.mark.parametrize(
    ("overrides", "match"),
    [
        ({"random_landmarks": {"count": [9, 4]}}, r"count must be >= 3 landmarks \(low <= high\)"),
        ({"random_landmarks": {"count": [2, 5]}}, r"count must be >= 3"),
        ({"random_landmarks": {"count": [5, 257]}}, r"count must be at most MAX_LANDMARKS"),
        ({"random_landmarks": {"count": [5.5, 7]}}, r"random_landmarks.count"),
        ({"camera_height": [2.0, 1.0]}, r"camera_height must be a finite range"),
        ({"camera_height": [0.0, 1.0]}, r"camera_height must be positive"),
        ({"camera_height": "high"}, r"camera_height"),
    ],
)
def test_bad_ranges_are_named(overrides: dict[str, Any], match: str) -> None:
    with pytest.raises((ConfigError, ValueError), match=match):
        load_scenario("random", **overrides)


def test_a_scenario_that_draws_its_height_has_no_single_one() -> None:
    s = load_scenario("random", **RANGES)
    with pytest.raises(ValueError, match=r"draws camera_height per episode \(\[1.3, 2.2\] m\)"):
        s.visible(np.zeros(3), np.ones((4, 3)))
    with pytest.raises(ValueError, match=r"ParkingImage-v0's renderer needs one fixed height"):
        gym.make("RadialIBVS/ParkingImage-v0", scenario="random", camera_height=[1.3, 2.2])
    with pytest.raises(ValueError, match=r"measurement='detected' labels a fixed number"):
        gym.make("RadialIBVS/Parking-v0", scenario="random", measurement="detected", **RANGES)


def _fixed_scene(episode: Episode, camera: dict[str, Any]) -> dict[str, Any]:
    """The gym.make overrides of a scenario that holds only this episode's scene and camera."""
    spec = {"mirror": "A", "non_central_offset": 0.01, **camera.get("camera", {})}
    if episode.mirror is not None:
        spec["mirror"] = episode.mirror
    return {
        "camera": spec,
        "random_room": None,
        "room": episode.room.tolist(),
        "random_landmarks": None,
        "landmarks": episode.landmarks.tolist(),
        "camera_height": episode.camera_height,
        "tasks": [{"start": episode.start.tolist(), "goal": episode.goal.tolist()}],
    }


def _rollout(env: gym.Env, seed: int, actions: np.ndarray) -> list[dict[str, np.ndarray]]:
    obs, _ = env.reset(seed=seed)
    out = [obs]
    for action in actions:
        obs, _, terminated, truncated, _ = env.step(action)
        out.append(obs)
        if terminated or truncated:
            break
    return out


CAMERAS: dict[str, dict[str, Any]] = {
    "ideal": {},
    "calibration errors": {
        "camera": {
            "mirror": "A",
            "non_central_offset": 0.01,
            "imperfections": {"principal_point_offset": [2.0, -1.0], "focal_ratio_error": 0.01},
        }
    },
}


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), camera=st.sampled_from(sorted(CAMERAS)))
def test_an_episode_with_fewer_landmarks_and_its_mirror_is_observed_as_its_own_scene(
    seed: int, camera: str
) -> None:
    kwargs = {"physics": "kinematic", "obs_mode": "features", "goal_depths": True}
    ranged = gym.make(
        "RadialIBVS/Parking-v0", scenario="random", **kwargs, **DRAWN, **CAMERAS[camera]
    )
    ranged.reset(seed=seed)
    episode = ranged.unwrapped.episode
    n = len(episode.landmarks)
    own = gym.make(
        "RadialIBVS/Parking-v0",
        scenario="random",
        **kwargs,
        **_fixed_scene(episode, CAMERAS[camera]),
    )
    actions = np.random.default_rng(seed).uniform(-1, 1, (25, 2)).astype(np.float32)
    a = _rollout(ranged, seed, actions)
    b = _rollout(own, 0, actions)
    assert len(a) == len(b)
    for x, y in zip(a, b, strict=True):
        assert x["visible"].shape == (ranged.unwrapped.config.scenario.n_landmarks,)
        assert not x["visible"][n:].any() and not x["points"][2 * n :].any()
        np.testing.assert_array_equal(x["visible"][:n], y["visible"])
        np.testing.assert_allclose(x["points"][: 2 * n], y["points"], atol=1e-12)
        np.testing.assert_allclose(x["goal_depths"][:n], y["goal_depths"], atol=1e-6)
        assert not x["goal_depths"][n:].any()


def test_slots_mask_out_the_landmarks_an_episode_lacks() -> None:
    env = gym.make(
        "RadialIBVS/Parking-v0",
        scenario="random",
        physics="kinematic",
        obs_mode="features",
        max_landmarks=12,
        slot_order="random",
        **RANGES,
    )
    seen = set()
    for seed in range(12):
        obs, _ = env.reset(seed=seed)
        n = len(env.unwrapped.episode.landmarks)
        seen.add(n)
        assert obs["landmark_mask"].sum() == n
        assert not obs["visible"][obs["landmark_mask"] == 0].any()
    assert len(seen) > 1


ROOT = CONFIGS.parent


def test_the_unseen_family_lies_outside_the_training_ranges() -> None:
    train = load_scenario("random").config
    unseen = load_scenario("random-unseen").config
    assert train.random_room is not None and unseen.random_room is not None
    assert unseen.random_room.width[0] > train.random_room.width[1]
    assert unseen.random_room.depth[0] > train.random_room.depth[1]
    assert train.random_landmarks is not None and unseen.random_landmarks is not None
    assert unseen.random_landmarks.count_range[0] > train.random_landmarks.count_range[1]
    assert unseen.camera_height_range[1] < train.camera_height_range[0]


def test_no_training_or_tuning_reads_the_unseen_family() -> None:
    readers = [
        *(ROOT / "configs" / "agents").rglob("*.yaml"),
        *(ROOT / "research").rglob("*.yaml"),
        *(ROOT / "research").rglob("*.py"),
        *(ROOT / "agents" / "radial_ibvs_agents" / "learned").rglob("*.py"),
    ]
    assert len(readers) > 20
    named = [str(p.relative_to(ROOT)) for p in readers if "random-unseen" in p.read_text()]
    assert named == []


def test_mirrors_are_drawn_per_episode_and_one_listed_draws_nothing() -> None:
    drawn = load_scenario("random", mirrors=["A", "B"])
    mirrors = {drawn.sample(np.random.default_rng(seed)).mirror for seed in range(40)}
    assert mirrors == {"A", "B"}
    one = load_scenario("random", mirrors=["B"], camera={"mirror": "A", "non_central_offset": 0.01})
    mirror_b = load_scenario("random", camera={"mirror": "B", "non_central_offset": 0.01})
    for seed in range(5):
        a = one.sample(np.random.default_rng(seed))
        b = mirror_b.sample(np.random.default_rng(seed))
        assert a.mirror == "B" and b.mirror is None
        for x, y in zip(a[:-1], b[:-1], strict=True):
            np.testing.assert_array_equal(x, y)
    with pytest.raises((ConfigError, ValueError), match="mirrors must not repeat"):
        load_scenario("random", mirrors=["A", "A"])
    with pytest.raises((ConfigError, ValueError), match="mirrors"):
        load_scenario("random", mirrors=["C"])
    with pytest.raises(ValueError, match=r"ParkingImage-v0 renders through one camera"):
        gym.make("RadialIBVS/ParkingImage-v0", scenario="random", mirrors=["A", "B"])
    with pytest.raises(ValueError, match=r"measurement='detected' renders through one camera"):
        gym.make(
            "RadialIBVS/Parking-v0", scenario="random", measurement="detected", mirrors=["A", "B"]
        )
