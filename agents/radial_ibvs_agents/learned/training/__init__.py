"""Training with stable-baselines3: ``radial-ibvs train``.

- :mod:`~radial_ibvs_agents.learned.training.train`: the command (vectorised envs, observation
  normalisation, evaluations, checkpoints, export);
- :mod:`~radial_ibvs_agents.learned.training.zoo_config`: the rl-zoo3-style config schema;
- :mod:`~radial_ibvs_agents.learned.training.sb3_vec_env`: SB3's ``VecEnv`` over the native batched
  envs;
- :mod:`~radial_ibvs_agents.learned.training.curriculum`: the reverse curriculum of the start
  states;
- :mod:`~radial_ibvs_agents.learned.training.fine_tune`: PPO fine-tuning of a distilled student;
- :mod:`~radial_ibvs_agents.learned.training.tolerance_eval`: evaluations at the three tolerances.
"""
