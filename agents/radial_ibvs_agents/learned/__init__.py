"""The learned policies: everything that trains or loads a network, grouped by job.

- :mod:`~radial_ibvs_agents.learned.networks`: what a learned policy computes: the observation
  history, the feature extractors, the closed-form pose layer, the residual on an analytic policy;
- :mod:`~radial_ibvs_agents.learned.files`: model directories: :func:`load` one as a policy,
  :func:`shipped_models` (the models in ``agents/radial_ibvs_agents/learned/models/``),
  ``save_model_dir``, the safetensors and JSON formats, and the table of module paths from before
  this grouping;
- :mod:`~radial_ibvs_agents.learned.training`: ``radial-ibvs train`` with stable-baselines3, its
  rl-zoo3-style config, :func:`make_vec_env` (SB3's ``VecEnv`` over the native batched envs),
  the reverse curriculum and the fine-tuning of a student;
- :mod:`~radial_ibvs_agents.learned.dagger`: ``radial-ibvs distill``, DAgger from the planner to an
  image-only student, and its datasets.

Each group imports only the ones before it in this list.
Importing this package loads neither torch nor stable-baselines3: the modules that need them
import them when they are used (:func:`make_vec_env` on first access). It may import
:mod:`radial_ibvs_agents.analytic` (a residual needs its base policy), never the reverse.
"""

from typing import Any

from radial_ibvs_agents.learned.files.loading import MODELS_DIR, LearnedPolicy, load, shipped_models

__all__ = ["MODELS_DIR", "LearnedPolicy", "load", "make_vec_env", "shipped_models"]


def __getattr__(name: str) -> Any:
    """Import :func:`make_vec_env` on first use (it loads stable-baselines3 and torch)."""
    if name == "make_vec_env":
        from radial_ibvs_agents.learned.training.sb3_vec_env import make_vec_env

        return make_vec_env
    raise AttributeError(f"module 'radial_ibvs_agents.learned' has no attribute {name!r}")
