"""Model directories: saving, loading and checking a trained model's files (no pickles).

- :mod:`~agents.learned.files.model_files`: an SB3 policy's weights as safetensors, described
  in JSON, and the observation statistics;
- :mod:`~agents.learned.files.policy_size`: checks on a described policy before anything is
  allocated for it;
- :mod:`~agents.learned.files.saving`: :func:`~agents.learned.files.saving.save_model_dir`;
- :mod:`~agents.learned.files.loading`: :func:`~agents.learned.files.loading.load` a model
  directory as a policy;
- :mod:`~agents.learned.files.mean_action`: a loaded policy's deterministic action, fast;
- :mod:`~agents.learned.files.provenance`: where a model came from (command, config, code).
- :mod:`~agents.learned.files.former_paths`: the classes' module paths before the move, so
  that models saved before it still load.
"""
