"""Training with stable-baselines3: ``radial-ibvs train``.

- :mod:`~agents.learned.training.train`: the command (vectorised envs, observation
  normalisation, evaluations, checkpoints, export);
- :mod:`~agents.learned.training.zoo_config`: the rl-zoo3-style config schema;
- :mod:`~agents.learned.training.sb3_vec_env`: SB3's ``VecEnv`` over the native batched envs;
- :mod:`~agents.learned.training.curriculum`: the reverse curriculum of the start states;
- :mod:`~agents.learned.training.fine_tune`: PPO fine-tuning of a distilled student;
- :mod:`~agents.learned.training.tolerance_eval`: evaluations at the three tolerances.
"""
