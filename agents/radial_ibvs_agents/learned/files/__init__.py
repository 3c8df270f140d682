"""Model directories: saving, loading and checking a trained model's files (no pickles).

- :mod:`~radial_ibvs_agents.learned.files.model_files`: an SB3 policy's weights as safetensors,
  described in JSON, and the observation statistics;
- :mod:`~radial_ibvs_agents.learned.files.policy_size`: checks on a described policy before anything
  is allocated for it;
- :mod:`~radial_ibvs_agents.learned.files.saving`:
  :func:`~radial_ibvs_agents.learned.files.saving.save_model_dir`;
- :mod:`~radial_ibvs_agents.learned.files.loading`:
  :func:`~radial_ibvs_agents.learned.files.loading.load` a model directory as a policy;
- :mod:`~radial_ibvs_agents.learned.files.mean_action`: a loaded policy's deterministic action,
  fast;
- :mod:`~radial_ibvs_agents.learned.files.provenance`: where a model came from (command, config,
  code).
- :mod:`~radial_ibvs_agents.learned.files.former_paths`: the classes' module paths before the move,
  so that models saved before it still load.
"""
