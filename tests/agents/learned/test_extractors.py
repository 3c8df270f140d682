"""The feature extractors (``radial_ibvs_agents.learned.networks.extractors``): the error-scale one
and the landmark set's."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from gymnasium import spaces

from radial_ibvs_agents.learned.networks.extractors import ErrorScaleExtractor, LandmarkSetExtractor


def test_error_scale_extractor_is_scale_invariant_in_direction():
    space = spaces.Dict(
        {
            "c_error": spaces.Box(-2, 2, (6,)),
            "alpha_m_error": spaces.Box(-4, 4, (1,)),
            "points": spaces.Box(-1, 1, (4,)),
        }
    )
    extractor = ErrorScaleExtractor(space)
    assert extractor.features_dim == 7 + 2 + 4
    e = torch.tensor([[0.3, -0.1, 0.0, 0.2, 0.05, -0.4]])
    obs = {"alpha_m_error": torch.tensor([[0.01]]), "c_error": e, "points": torch.zeros(1, 4)}
    small = {**obs, "c_error": e * 1e-2}
    big, tiny = extractor(obs), extractor(small)
    # keys in the Dict's order: alpha_m_error (value, soft sign), c_error (6 + 1), points (4)
    np.testing.assert_allclose(big[0, :2], [0.01, 0.01 / (0.01 + 1e-3)], rtol=1e-5)
    # the direction keeps its size near the goal (to eps), the log-size tells how far
    np.testing.assert_allclose(big[0, 2:8], tiny[0, 2:8], atol=0.2)
    assert float(big[0, 8]) - float(tiny[0, 8]) > 3.0
    np.testing.assert_array_equal(big[0, 9:], 0.0)


def test_angle_keys_are_continuous_across_the_wrap_and_sharp_near_zero():
    space = spaces.Dict(
        {"alpha_m_error": spaces.Box(-4, 4, (1,)), "c_error": spaces.Box(-2, 2, (3,))}
    )
    plain = ErrorScaleExtractor(space)
    angles = ErrorScaleExtractor(space, angle_keys=["alpha_m_error"])
    assert angles.features_dim == plain.features_dim + 1

    def features(extractor, a):
        return extractor({"alpha_m_error": torch.tensor([[a]]), "c_error": torch.ones(1, 3)})[0, :3]

    below, above = np.pi - 1e-4, -np.pi + 1e-4  # the same heading, either side of the wrap
    torch.testing.assert_close(features(angles, below), features(angles, above), atol=1e-3, rtol=0)
    assert float(features(plain, below)[1] - features(plain, above)[1]) > 1.9  # the old jump
    near = features(angles, 0.01)  # sin, cos, soft sign: still sharp near zero
    assert float(near[2]) > 0.9 and float(features(angles, -0.01)[2]) < -0.9
    with pytest.raises(ValueError, match="angle key 'c_error'"):
        ErrorScaleExtractor(space, angle_keys=["c_error"])


def _set_space(n: int = 5):
    return spaces.Dict(
        {
            "alpha_m_error": spaces.Box(-4, 4, (1,)),
            "goal_depths": spaces.Box(0, 1e3, (n,)),
            "goal_points": spaces.Box(-1, 1, (2 * n,)),
            "points": spaces.Box(-1, 1, (2 * n,)),
            "visible": spaces.Box(0, 1, (n,)),
        }
    )


def _set_obs(rng, n: int = 5, seen: int = 4):
    angle = rng.uniform(-np.pi, np.pi, (2, n))
    now, goal = (np.stack([np.cos(a), np.sin(a)], axis=-1) for a in angle)
    visible = np.zeros(n)
    visible[:seen] = 1.0
    now *= visible[:, None]
    return {
        "alpha_m_error": torch.tensor([[0.02]]),
        "goal_depths": torch.tensor(rng.uniform(0.5, 4.0, (1, n)), dtype=torch.float32),
        "goal_points": torch.tensor(goal.reshape(1, -1), dtype=torch.float32),
        "points": torch.tensor(now.reshape(1, -1), dtype=torch.float32),
        "visible": torch.tensor(visible[None], dtype=torch.float32),
    }


def test_landmark_set_extractor_is_the_same_whichever_slots_the_landmarks_fill():
    torch.manual_seed(0)
    extractor = LandmarkSetExtractor(_set_space(), token_dim=16)
    base = ErrorScaleExtractor(_set_space(), point_error=True)
    assert extractor.features_dim == base.features_dim + 2 * 16 + 1
    obs = _set_obs(np.random.default_rng(1))
    order = torch.tensor([3, 0, 4, 1, 2])  # the landmarks moved to other slots

    def permute(key, value):
        width = value.shape[1] // 5
        if key == "alpha_m_error":
            return value
        return value.reshape(1, 5, width)[:, order].reshape(1, -1)

    moved = {k: permute(k, v) for k, v in obs.items()}
    a, b = extractor(obs), extractor(moved)
    tail = 2 * 16 + 1  # the set encoding: permutation invariant
    torch.testing.assert_close(a[:, -tail:], b[:, -tail:])
    assert float(a[0, -1].detach()) == pytest.approx(4 / 5)  # the share of slots seen
    assert (a[0, -tail:-1] > 0).any()  # the encoding is not empty
    # a hidden landmark's slot changes nothing, whatever numbers it holds
    hidden = {k: v.clone() for k, v in obs.items()}
    hidden["goal_points"][0, 8:] = torch.tensor([0.6, 0.8])
    hidden["goal_depths"][0, 4] = 9.0
    torch.testing.assert_close(extractor(hidden)[:, -tail:], a[:, -tail:])


def test_landmark_set_extractor_names_a_missing_key():
    space = _set_space()
    del space.spaces["goal_depths"]
    with pytest.raises(ValueError, match="goal_depths"):
        LandmarkSetExtractor(space)
