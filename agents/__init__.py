"""Reference and learned policies for the radial IBVS parking tasks.

Every policy implements stable-baselines3's ``predict(observation, state=None,
episode_start=None, deterministic=True) -> (action, state)``. The controllers land with the
controller issue; this package is installed with the project so the import path is stable.
"""

__all__: list[str] = []
