"""Residual policies: a bounded, learned correction on top of the IBVS."""

from __future__ import annotations

import numpy as np
import pytest

from radial_ibvs_agents.analytic.ibvs_policy import IBVSPolicy
from radial_ibvs_agents.learned.networks.residual import BASE_KEY, ResidualConfig, ResidualVecEnv
from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env

ENV_KWARGS = {
    "scenario": "random", "physics": "kinematic", "goal_depths": True, "max_landmarks": 16
}  # fmt: skip


def _venv(n: int = 4, seed: int = 5) -> ResidualVecEnv:
    base = make_vec_env("RadialIBVS/Parking-v0", n, seed=seed, **ENV_KWARGS)
    return ResidualVecEnv(base, ResidualConfig("ibvs-backward", 0.5))


def test_zero_correction_drives_exactly_the_base_policy() -> None:
    residual, plain = _venv(), make_vec_env("RadialIBVS/Parking-v0", 4, seed=5, **ENV_KWARGS)
    ibvs = IBVSPolicy(allow_backward=True)
    obs, ref = residual.reset(), plain.reset()
    for _ in range(150):
        np.testing.assert_array_equal(obs[BASE_KEY], ibvs.predict(ref)[0])
        obs, _, dones, infos = residual.step(np.zeros((4, 2), np.float32))
        ref, _, ref_dones, _ = plain.step(ibvs.predict(ref)[0])
        np.testing.assert_array_equal(dones, ref_dones)
        for info in infos:
            if "terminal_observation" in info:
                assert BASE_KEY in info["terminal_observation"]
    assert residual.observation_space[BASE_KEY].shape == (2,)


def test_the_correction_is_scaled_and_the_action_clipped() -> None:
    venv = _venv(2)
    venv.reset()
    base = venv._base_actions.copy()
    sent = {}
    venv.venv.step_async = lambda actions: sent.setdefault("a", actions)  # type: ignore[method-assign]
    venv.step_async(np.array([[1.0, -1.0], [0.2, 0.0]], np.float32))
    expected = np.clip(base + 0.5 * np.array([[1.0, -1.0], [0.2, 0.0]]), -1, 1)
    np.testing.assert_allclose(sent["a"], expected, atol=1e-6)


@pytest.mark.parametrize(
    ("entry", "match"),
    [
        ({"base": "nope"}, "unknown policy 'nope'"),
        ({"base": "random"}, "unknown policy 'random'"),
        ({"scale": 0}, r"scale must be a number in \(0, 2\], got 0"),
        ({"scale": float("nan")}, "scale must be"),
        ({"scal": 1}, r"unknown key\(s\) \['scal'\]"),
        ({"gate": 0}, "gate must be a positive number or null, got 0"),
        ({"gate": "big"}, "gate must be a positive number"),
    ],
)
def test_bad_residual_entries_are_named(entry: dict, match: str) -> None:
    with pytest.raises(ValueError, match=match):
        ResidualConfig.from_mapping(entry, "cfg.residual")


def test_the_gate_fades_the_correction_where_the_base_action_is_small() -> None:
    gated = ResidualConfig("ibvs-backward", 0.5, gate=0.2)
    correction = np.array([[1.0, -1.0], [1.0, -1.0], [1.0, -1.0]], np.float32)
    base = np.array([[0.0, 0.0], [0.1, 0.0], [0.0, 0.6]], np.float32)  # |base| 0, 0.1, 0.6
    np.testing.assert_allclose(
        gated.combine(base, correction), [[0.0, 0.0], [0.35, -0.25], [0.5, 0.1]], atol=1e-6
    )
    plain = ResidualConfig("ibvs-backward", 0.5)
    np.testing.assert_allclose(plain.combine(base[0], correction[0]), [0.5, -0.5])
    assert gated.as_dict() == {"base": "ibvs-backward", "scale": 0.5, "gate": 0.2}
    assert ResidualConfig.from_mapping(gated.as_dict(), "x") == gated
