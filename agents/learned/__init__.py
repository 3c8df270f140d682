"""The learned policies: everything that trains or loads a network, grouped by job.

- :mod:`~agents.learned.networks`: what a learned policy computes: the observation history,
  the feature extractors, the closed-form pose layer, the residual on an analytic policy;
- :mod:`~agents.learned.files`: model directories: :func:`load` one as a policy,
  :func:`shipped_models` (the models in ``agents/learned/models/``), ``save_model_dir``, the
  safetensors and JSON formats, and the table of module paths from before this grouping;
- :mod:`~agents.learned.training`: ``radial-ibvs train`` with stable-baselines3, its
  rl-zoo3-style config, :func:`make_vec_env` (SB3's ``VecEnv`` over the native batched envs),
  the reverse curriculum and the fine-tuning of a student;
- :mod:`~agents.learned.dagger`: ``radial-ibvs distill``, DAgger from the planner to an
  image-only student, and its datasets.

Each group imports only the ones before it in this list.
Importing this package loads neither torch nor stable-baselines3: the modules that need them
import them when they are used (:func:`make_vec_env` on first access). It may import
:mod:`agents.analytic` (a residual needs its base policy), never the reverse.
"""

from typing import Any

from agents.learned.files.loading import MODELS_DIR, LearnedPolicy, load, shipped_models

__all__ = ["MODELS_DIR", "LearnedPolicy", "load", "make_vec_env", "shipped_models"]


def __getattr__(name: str) -> Any:
    """Import :func:`make_vec_env` on first use (it loads stable-baselines3 and torch)."""
    if name == "make_vec_env":
        from agents.learned.training.sb3_vec_env import make_vec_env

        return make_vec_env
    raise AttributeError(f"module 'agents.learned' has no attribute {name!r}")
