"""PPO fine-tuning of a distilled student: its exploration noise and a critic warm-up.

A DAgger student (:mod:`radial_ibvs_agents.learned.dagger.distill`) arrives with a trained actor, an
untrained critic and the exploration noise it was built with. PPO started from it as it is forgets
what it learned: its first advantages come from a random critic, and its actions are drawn with a
noise under which the student hardly parks (its deterministic actions park; drawn with a standard
deviation of 0.37 it parked 2 % of rooms). Two settings of the config's
``radial_ibvs_gym.fine_tune`` section fix that:

- ``log_std``: the policy's log standard deviation at the start (the same for each action
  component), so that PPO explores near what the student does;
- ``critic_warmup``: for this many env steps (all envs together) only the critic learns (its
  own layers: the features the actor reads stay as they are); then everything learns.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from stable_baselines3.common.callbacks import BaseCallback

__all__ = ["CriticWarmup", "FineTuneConfig", "critic_parameters"]

#: the parameter names (prefixes) of an SB3 actor-critic policy that belong to the critic alone
CRITIC_PREFIXES = ("mlp_extractor.value_net.", "value_net.", "vf_features_extractor.")


@dataclass(frozen=True)
class FineTuneConfig:
    """How a PPO fine-tuning starts from a student (``train(..., init_from=DIR)``).

    Attributes
    ----------
    log_std
        The policy's log standard deviation at the start, or ``None`` to keep the student's.
        With actions in ``[-1, 1]``, ``-2.3`` draws with a standard deviation of 0.1.
    critic_warmup
        Env steps (all envs together) during which only the critic learns; ``0``: none.
    """

    log_std: float | None = None
    critic_warmup: int = 0

    @classmethod
    def from_mapping(cls, data: Any, where: str) -> FineTuneConfig:
        """Validate a ``fine_tune:`` config entry (``log_std``, ``critic_warmup``)."""
        if not isinstance(data, Mapping):
            raise ValueError(f"{where} must be a mapping (log_std, critic_warmup), got {data!r}")
        unknown = sorted(set(data) - {"log_std", "critic_warmup"})
        if unknown:
            valid = ["critic_warmup", "log_std"]
            raise ValueError(f"{where}: unknown key(s) {unknown}; valid: {valid}")
        log_std = data.get("log_std")
        if log_std is not None and (
            isinstance(log_std, bool)
            or not isinstance(log_std, int | float)
            or not (math.isfinite(log_std) and -10.0 <= log_std <= 2.0)
        ):
            raise ValueError(
                f"{where}.log_std must be a number in [-10, 2] or null, got {log_std!r}"
            )
        warmup = data.get("critic_warmup", 0)
        if isinstance(warmup, float) and warmup.is_integer():
            warmup = int(warmup)
        if isinstance(warmup, bool) or not isinstance(warmup, int) or warmup < 0:
            raise ValueError(f"{where}.critic_warmup must be an integer >= 0, got {warmup!r}")
        return cls(None if log_std is None else float(log_std), warmup)

    def as_dict(self) -> dict[str, Any]:
        """Return the config as a plain dict (for the model's metadata)."""
        return {"log_std": self.log_std, "critic_warmup": self.critic_warmup}

    def apply(self, policy: Any) -> None:
        """Set the policy's exploration noise (``log_std``), if one is given."""
        if self.log_std is None:
            return
        import torch

        if not isinstance(getattr(policy, "log_std", None), torch.nn.Parameter):
            raise ValueError("fine_tune.log_std needs a policy with a state-independent log_std")
        with torch.no_grad():
            policy.log_std.fill_(self.log_std)


def critic_parameters(policy: Any) -> set[str]:
    """Return the names of the parameters that only the critic uses."""
    return {name for name, _ in policy.named_parameters() if name.startswith(CRITIC_PREFIXES)}


class CriticWarmup(BaseCallback):
    """Train only the critic for the first ``steps`` env steps (SB3 callback, PPO/A2C).

    The actor's parameters (the shared features included) get ``requires_grad = False``, so
    the optimiser leaves them as they are; they are released at the first rollout that starts
    at or after ``steps``.

    Parameters
    ----------
    steps
        Env steps (all envs together) of critic-only training.
    """

    def __init__(self, steps: int) -> None:
        super().__init__()
        self.steps = int(steps)
        self.frozen = False

    def _set_actor_trainable(self, trainable: bool) -> None:
        critic = critic_parameters(self.model.policy)
        for name, parameter in self.model.policy.named_parameters():
            if name not in critic:
                parameter.requires_grad_(trainable)
        self.frozen = not trainable

    def _on_training_start(self) -> None:
        if self.steps > 0 and self.num_timesteps < self.steps:
            self._set_actor_trainable(False)

    def _on_rollout_start(self) -> None:
        if self.frozen and self.num_timesteps >= self.steps:
            self._set_actor_trainable(True)
        self.logger.record("fine_tune/actor_frozen", float(self.frozen))

    def _on_training_end(self) -> None:
        if self.frozen:
            self._set_actor_trainable(True)

    def _on_step(self) -> bool:
        return True
