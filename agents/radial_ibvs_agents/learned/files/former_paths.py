"""The module paths of the policies before 0.1's two moves, and where they went.

Saved models name classes by module path: a ``policy.json`` names its feature extractor
(``{"__class__": "agents.learned.extractors.LandmarkPoseExtractor"}``), and a
stable-baselines3 ``model.zip`` pickles the same reference. Two moves changed those paths:

1. ``agents.learned`` was grouped by job (``extractors`` went to ``networks``, ...);
2. the import name ``agents`` became ``radial_ibvs_agents`` (a generic top-level name clashed
   with other packages, OpenAI's Agents SDK among them).

Models saved before (the shipped ones among them) keep loading through this table:
:func:`current_name` rewrites a name read from a ``policy.json`` (the allow-list then applies
to the current name), and :func:`former_modules` lets a *trusted* ``model.zip``'s pickles find
the modules while it loads. ``agents.learned.training`` was a module and is now a package (its
code is in ``radial_ibvs_agents.learned.training.train``); it held no class or function that a
model file names, so it maps to the package.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["FORMER_MODULES", "current_module", "current_name", "former_modules"]

#: the former import name of the policies, and the current one
FORMER_TOP, TOP = "agents", "radial_ibvs_agents"

#: former module path of ``agents.learned`` -> its current module, before the rename of the top
FORMER_MODULES: dict[str, str] = {
    "agents.learned.extractors": "agents.learned.networks.extractors",
    "agents.learned.pose_layer": "agents.learned.networks.pose_layer",
    "agents.learned.history": "agents.learned.networks.history",
    "agents.learned.residual": "agents.learned.networks.residual",
    "agents.learned.model_files": "agents.learned.files.model_files",
    "agents.learned.policy_size": "agents.learned.files.policy_size",
    "agents.learned.loading": "agents.learned.files.loading",
    "agents.learned.mean_action": "agents.learned.files.mean_action",
    "agents.learned.saving": "agents.learned.files.saving",
    "agents.learned.provenance": "agents.learned.files.provenance",
    "agents.learned.zoo_config": "agents.learned.training.zoo_config",
    "agents.learned.sb3_vec_env": "agents.learned.training.sb3_vec_env",
    "agents.learned.curriculum": "agents.learned.training.curriculum",
    "agents.learned.fine_tune": "agents.learned.training.fine_tune",
    "agents.learned.tolerance_eval": "agents.learned.training.tolerance_eval",
    "agents.learned.distill": "agents.learned.dagger.distill",
    "agents.learned.distill_config": "agents.learned.dagger.distill_config",
    "agents.learned.datasets": "agents.learned.dagger.datasets",
}


def current_module(module: str) -> str:
    """Return the current path of a module saved as ``module`` (any other path as it is)."""
    module = FORMER_MODULES.get(module, module)
    if module == FORMER_TOP or module.startswith(FORMER_TOP + "."):
        return TOP + module[len(FORMER_TOP) :]
    return module


def current_name(name: str) -> str:
    """Return the current ``module.qualname`` of a class saved as ``name``.

    A name under a former module path (:data:`FORMER_MODULES`, or the former import name
    ``agents``) is moved to the current module; any other name comes back as it is.

    Parameters
    ----------
    name
        ``module.qualname`` as a model file wrote it.
    """
    module, _, qualname = name.rpartition(".")
    return f"{current_module(module)}.{qualname}" if module else name


@contextmanager
def former_modules() -> Iterator[None]:
    """Let the former module paths import their current modules, for the ``with`` block only.

    For a trusted stable-baselines3 ``model.zip``, whose pickles import classes by the paths
    they had when it was saved. Imports the current modules (torch among them), puts them in
    ``sys.modules`` under their former paths (and ``agents``, ``agents.learned`` above them),
    and takes those entries out again on exit, so that another package named ``agents`` is
    untouched after the load.
    """
    names = sorted({FORMER_TOP, f"{FORMER_TOP}.learned", *FORMER_MODULES})
    added = {f: importlib.import_module(current_module(f)) for f in names if f not in sys.modules}
    sys.modules.update(added)
    try:
        yield
    finally:
        for name in added:
            sys.modules.pop(name, None)
