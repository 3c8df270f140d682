"""A trained policy's deterministic action for one observation, without SB3's per-call work.

stable-baselines3's ``predict`` switches the modules to evaluation mode, copies and checks the
observation (``obs_to_tensor``), builds the action distribution and takes its mean, at every call.
For one robot that costs more than the network (the student: about a quarter of its time alone).
:func:`mean_action` does only the operations that make the action, in the same order (the features,
the actor's latent, the action net, SB3's clip), in inference mode: the same bits as ``predict``
(``tests/agents/learned/test_learned_predict.py``). It serves the policies it fits
(:func:`actor_layers`); :class:`~radial_ibvs_agents.learned.files.loading.LearnedPolicy` sends the
others, stochastic calls and calls with a state to SB3's ``predict``.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["actor_layers", "mean_action"]


def mean_action(
    policy: Any, layers: list[Any], observation: dict[str, np.ndarray]
) -> np.ndarray | None:
    """Return the deterministic action ``(2,)`` or ``(B, 2)``, or ``None`` (a bad shape).

    Parameters
    ----------
    policy
        A stable-baselines3 policy that :func:`actor_layers` fits.
    layers
        Its actor's layers and action net, from :func:`actor_layers`.
    observation
        One observation or a batch, normalised as in training.

    Returns
    -------
    numpy.ndarray or None
        float32 actions; ``None`` where the shapes are not the space's, one or a batch (SB3's
        ``predict`` then says what is wrong).
    """
    import torch

    if policy.training:  # trained since: evaluation mode, as SB3's predict would set
        policy.set_training_mode(False)
    spaces = policy.observation_space.spaces
    tensors, batched = {}, None
    for key, space in spaces.items():
        value = np.asarray(observation[key])
        if value.shape == space.shape:
            one = False
        elif value.shape[1:] == space.shape:
            one = True
        else:
            return None
        if batched is not None and one != batched:
            return None
        batched = one
        # what stable-baselines3's preprocessing does to a Box observation
        tensors[key] = torch.as_tensor(value.reshape((-1, *space.shape))).float()
    with torch.inference_mode():
        x = policy.pi_features_extractor.forward(tensors)
        for layer in layers:
            x = layer(x)
    space = policy.action_space
    actions = np.clip(x.numpy().reshape((-1, *space.shape)), space.low, space.high)
    return np.asarray(actions if batched else actions.squeeze(axis=0), dtype=np.float32)


def actor_layers(policy: Any) -> list[Any] | None:
    """Return the actor's layers and the action net as functions, or ``None`` (no fit).

    It fits a Gaussian actor-critic policy (PPO, A2C) with SB3's own ``_predict``,
    ``get_distribution`` and ``extract_features`` (not a recurrent one: its memory is in SB3's
    state), on a ``Dict`` of ``Box`` spaces, on the CPU, whose actor is a plain stack of
    linear layers and ReLU or Tanh.
    """
    import torch
    from gymnasium import spaces
    from stable_baselines3.common.distributions import DiagGaussianDistribution
    from stable_baselines3.common.policies import ActorCriticPolicy
    from stable_baselines3.common.torch_layers import MlpExtractor

    plain = isinstance(policy, ActorCriticPolicy) and all(
        getattr(type(policy), name) is getattr(ActorCriticPolicy, name)
        for name in ("_predict", "get_distribution", "extract_features")
    )
    fits = (
        plain
        and isinstance(policy.action_dist, DiagGaussianDistribution)
        and not policy.squash_output
        and isinstance(policy.observation_space, spaces.Dict)
        and all(isinstance(s, spaces.Box) for s in policy.observation_space.spaces.values())
        and isinstance(policy.action_space, spaces.Box)
        and type(policy.mlp_extractor) is MlpExtractor
        and isinstance(policy.mlp_extractor.policy_net, torch.nn.Sequential)
        and type(policy.action_net) is torch.nn.Linear
        and str(policy.device) == "cpu"
    )
    if not fits:
        return None
    functions = {torch.nn.ReLU: torch.relu, torch.nn.Tanh: torch.tanh}
    layers: list[Any] = []
    for module in [*policy.mlp_extractor.policy_net, policy.action_net]:
        if type(module) is torch.nn.Linear:
            layers.append(_linear(module))
        elif type(module) in functions:
            layers.append(functions[type(module)])
        else:
            return None
    return layers


def _linear(module: Any) -> Any:
    """``module``'s forward as a function (``torch.nn.Linear.forward`` without the call)."""
    import torch

    def forward(x: Any) -> Any:
        return torch.nn.functional.linear(x, module.weight, module.bias)

    return forward
