"""DAgger: a privileged teacher distilled into an image-only student, ``radial-ibvs distill``.

- :mod:`~radial_ibvs_agents.learned.dagger.distill`: the rounds (collect with the teacher's labels,
  fit the student, export);
- :mod:`~radial_ibvs_agents.learned.dagger.distill_config`: its settings
  (``configs/agents/dagger_*.yaml``);
- :mod:`~radial_ibvs_agents.learned.dagger.datasets`: Minari datasets on local disk, read as data.
"""
