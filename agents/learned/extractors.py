"""Feature extractors for the learned policies (torch modules, no parameters of their own).

A network fed the raw image errors sees almost nothing near the goal: ``c*_ij - c_ij`` and
``alpha*_m - alpha_m`` shrink towards zero there, a few hundredths of their spread over an
episode, yet that is where parking needs centimetre precision. The paper's IBVS is precise
there because its law is proportional to the error whatever its size (eq. 30). To give a
network the same view, :class:`ErrorScaleExtractor` feeds each error vector ``e`` (a key of
``error_keys``, and its history ``KEY@-k``) as its direction and the logarithm of its size::

    e / (|e| + eps),   log(|e| + eps)

and each scalar error ``a`` as ``a`` and ``a / (|a| + eps)`` (a soft sign, sharp near zero).
With ``point_error`` it adds the image error ``x_n - x_n*`` of the landmarks seen now and in
the goal image, the same way: its direction is in the robot's frame, so near the goal it tells
which way to turn and drive whatever the distance (what the IBVS reads through its
interaction matrices). Every other key is flattened as stable-baselines3's
``CombinedExtractor`` does. The keys it reads raw (:func:`raw_keys`) should not be
normalised beforehand: they are on fixed scales already.
"""

from __future__ import annotations

import numpy as np
import torch
from gymnasium import spaces
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

__all__ = ["ERROR_KEYS", "POINT_KEYS", "ErrorScaleExtractor", "error_key_of", "raw_keys"]

#: the observation keys treated as errors by default (the features observation)
ERROR_KEYS = ("c_error", "alpha_m_error")


#: the keys the image error is computed from
POINT_KEYS = ("points", "goal_points", "visible")


def raw_keys(error_keys: tuple[str, ...], point_error: bool) -> tuple[str, ...]:
    """Return the base keys :class:`ErrorScaleExtractor` reads raw (not to be normalised)."""
    return (*error_keys, *(POINT_KEYS if point_error else ()))


def error_key_of(key: str, error_keys: tuple[str, ...]) -> str | None:
    """Return the error key that ``key`` is (``c_error``) or is the history of (``c_error@-1``)."""
    base = key.split("@", 1)[0]
    return base if base in error_keys else None


class ErrorScaleExtractor(BaseFeaturesExtractor):
    """Flatten a ``Dict`` observation, giving the error keys as direction and log-size.

    Parameters
    ----------
    observation_space
        The ``Dict`` observation space.
    error_keys
        The error keys (and their histories) to transform.
    eps
        The size below which an error counts as zero (its unit: the observation's).
    point_error
        Add the image error ``x_n - x_n*`` (needs ``points``, ``goal_points``, ``visible``).
    """

    def __init__(
        self,
        observation_space: spaces.Dict,
        error_keys: tuple[str, ...] | list[str] = ERROR_KEYS,
        eps: float = 1e-3,
        point_error: bool = False,
    ) -> None:
        self.error_keys = tuple(error_keys)
        self.eps = float(eps)
        self.point_error = bool(point_error)
        size = 0
        if self.point_error:
            missing = sorted(set(POINT_KEYS) - set(observation_space.spaces))
            if missing:
                raise ValueError(f"point_error needs the observation keys {missing}")
            size += int(np.prod(observation_space.spaces["points"].shape or ())) + 1
        for key, space in observation_space.spaces.items():
            n = int(np.prod(space.shape or ()))
            if error_key_of(key, self.error_keys) is None:
                size += n
            else:
                size += n + 1 if n > 1 else 2
        super().__init__(observation_space, features_dim=size)
        self._keys = list(observation_space.spaces)

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """Return the ``(B, features_dim)`` features."""
        parts: list[torch.Tensor] = []
        if self.point_error:
            now = observations["points"].float().flatten(start_dim=1)
            goal = observations["goal_points"].float().flatten(start_dim=1)
            b = now.shape[0]
            seen = (goal.reshape(b, -1, 2).norm(dim=2) > 0.5) & (observations["visible"] > 0.5)
            error = ((now - goal).reshape(b, -1, 2) * seen[..., None]).reshape(b, -1)
            size = torch.linalg.vector_norm(error, dim=1, keepdim=True)
            parts += [error / (size + self.eps), torch.log(size + self.eps)]
        for key in self._keys:
            value = observations[key].float().flatten(start_dim=1)
            if error_key_of(key, self.error_keys) is None:
                parts.append(value)
            elif value.shape[1] > 1:
                size = torch.linalg.vector_norm(value, dim=1, keepdim=True)
                parts += [value / (size + self.eps), torch.log(size + self.eps)]
            else:
                parts += [value, value / (value.abs() + self.eps)]
        return torch.cat(parts, dim=1)

    def extra_repr(self) -> str:
        """Return the settings, for ``print(policy)``."""
        return f"error_keys={self.error_keys}, eps={self.eps}, point_error={self.point_error}"
