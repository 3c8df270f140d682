"""Experiments on top of the envs and the policies: each ``radial-ibvs`` command's work.

- :mod:`.reproduce`: the paper's Section 4.1 (``radial-ibvs reproduce``), :mod:`.figures` its
  Fig. 3-4 and 6-8;
- :mod:`.evaluate`: one policy, N seeded episodes, Wilson intervals;
- :mod:`.benchmark` (with :mod:`.jobs`, :mod:`.suites`, :mod:`.benchmark_plots`): every policy
  on the same suites and seeds;
- :mod:`.video`: a GIF or MP4 of a policy parking (``radial-ibvs render``);
- :mod:`.pixels`: a rendered image and its measurement (``radial-ibvs image``);
- :mod:`.demo`: the quick start's demo.

Every episode runs through :mod:`radial_ibvs_agents.rollouts`; its rows are
:mod:`radial_ibvs_agents.rows`', laid out by :mod:`.tables`; files are written by
:mod:`radial_ibvs_agents.io`.
"""

from radial_ibvs_agents.experiments.reproduce import (
    CASES,
    ROBUSTNESS_CASES,
    Case,
    reproduce,
    summary_table,
    write_json,
    write_trajectories_csv,
)

__all__ = [
    "CASES",
    "ROBUSTNESS_CASES",
    "Case",
    "reproduce",
    "summary_table",
    "write_json",
    "write_trajectories_csv",
]
