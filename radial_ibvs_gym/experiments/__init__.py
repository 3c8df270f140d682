"""Experiments on top of the envs and the agents: the paper's reproduction, its figures.

The top layer with the CLI: it may import everything below (envs, agents); nothing below
imports it.
"""

from radial_ibvs_gym.experiments.reproduce import (
    CASES,
    ROBUSTNESS_CASES,
    Case,
    reproduce,
    summary_table,
    write_atomic,
    write_json,
    write_trajectories_csv,
)

__all__ = [
    "CASES",
    "ROBUSTNESS_CASES",
    "Case",
    "reproduce",
    "summary_table",
    "write_atomic",
    "write_json",
    "write_trajectories_csv",
]
