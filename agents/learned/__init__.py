"""The learned policies: everything that trains or loads a network.

- :mod:`~agents.learned.loading`: :func:`load` a model directory as a policy;
  :func:`shipped_models` (the models in ``agents/learned/models/``).
- :mod:`~agents.learned.training`: ``radial-ibvs train`` (stable-baselines3).
- :mod:`~agents.learned.zoo_config`: the rl-zoo3-style training config schema.
- :mod:`~agents.learned.sb3_vec_env`: :func:`make_vec_env`, SB3's ``VecEnv`` over the native
  batched envs.
- :mod:`~agents.learned.residual`: a learned correction on top of an analytic policy.
- :mod:`~agents.learned.curriculum`: the reverse curriculum of the start states.
- :mod:`~agents.learned.distill`: ``radial-ibvs distill``, DAgger from the planner to an
  image-only student; :mod:`~agents.learned.history` (the last frames, for training and in
  the deployed policy's ``state``), :mod:`~agents.learned.extractors` (errors as direction
  and log-size), :mod:`~agents.learned.datasets` (reading Minari datasets).

Importing this package loads neither torch nor stable-baselines3: the modules that need them
import them when they are used (:func:`make_vec_env` on first access). It may import
:mod:`agents.analytic` (a residual needs its base policy), never the reverse.
"""

from typing import Any

from agents.learned.loading import MODELS_DIR, LearnedPolicy, load, shipped_models

__all__ = ["MODELS_DIR", "LearnedPolicy", "load", "make_vec_env", "shipped_models"]


def __getattr__(name: str) -> Any:
    """Import :func:`make_vec_env` on first use (it loads stable-baselines3 and torch)."""
    if name == "make_vec_env":
        from agents.learned.sb3_vec_env import make_vec_env

        return make_vec_env
    raise AttributeError(f"module 'agents.learned' has no attribute {name!r}")
