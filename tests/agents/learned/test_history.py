"""The observation history (``radial_ibvs_agents.learned.networks.history``): the stack of past
frames, its space."""

from __future__ import annotations

import numpy as np
import pytest
from gymnasium import spaces

from radial_ibvs_agents.learned.networks.history import (
    HistoryConfig,
    HistoryStack,
    history_key,
    history_space,
)


def test_history_stack_shifts_and_restarts():
    config = HistoryConfig(frames=3, keys=("a",))
    stack = HistoryStack(config, 2)
    first = stack.reset({"a": np.array([[1.0], [10.0]]), "b": np.zeros((2, 1))})
    np.testing.assert_array_equal(first[history_key("a", 1)], [[1.0], [10.0]])  # filled
    second = stack.step({"a": np.array([[2.0], [20.0]])}, np.array([False, False]))
    np.testing.assert_array_equal(second[history_key("a", 1)], [[1.0], [10.0]])
    np.testing.assert_array_equal(second[history_key("a", 2)], [[1.0], [10.0]])
    third = stack.step({"a": np.array([[3.0], [30.0]])}, np.array([False, True]))
    np.testing.assert_array_equal(third[history_key("a", 1)], [[2.0], [30.0]])  # env 1 anew
    np.testing.assert_array_equal(third[history_key("a", 2)], [[1.0], [30.0]])
    assert "b" in first and history_key("b", 1) not in first


def test_history_space_names_a_missing_key():
    space = spaces.Dict({"points": spaces.Box(-1, 1, (4,))})
    assert set(history_space(HistoryConfig(2, ("points",)), space).spaces) == {
        "points", "points@-1"
    }  # fmt: skip
    with pytest.raises(ValueError, match="c_error"):
        history_space(HistoryConfig(2, ("c_error",)), space)
    with pytest.raises(ValueError, match="frames"):
        HistoryConfig.from_mapping({"frames": 1}, "history")
