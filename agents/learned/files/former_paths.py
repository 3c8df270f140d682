"""The module paths of ``agents.learned`` before it was grouped by job, and where they went.

Saved models name classes by module path: a ``policy.json`` names its feature extractor
(``{"__class__": "agents.learned.extractors.LandmarkPoseExtractor"}``), and a
stable-baselines3 ``model.zip`` pickles the same reference. Models saved before the move (the
shipped ones among them) keep loading through this table: :func:`current_name` rewrites a
name read from a ``policy.json`` (the allow-list then applies to the current name), and
:func:`alias_former_modules` lets a *trusted* ``model.zip``'s pickles find the modules.

``agents.learned.training`` was a module and is now a package (its code is in
``agents.learned.training.train``); it held no class or function that a model file names, so
it has no alias.
"""

from __future__ import annotations

import importlib
import sys

__all__ = ["FORMER_MODULES", "alias_former_modules", "current_name"]

#: former module path -> current module path
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


def current_name(name: str) -> str:
    """Return the current ``module.qualname`` of a class saved as ``name``.

    A name under a former module path (:data:`FORMER_MODULES`) is moved to the current module;
    any other name comes back as it is.

    Parameters
    ----------
    name
        ``module.qualname`` as a model file wrote it.
    """
    module, _, qualname = name.rpartition(".")
    return f"{FORMER_MODULES[module]}.{qualname}" if module in FORMER_MODULES else name


def alias_former_modules() -> None:
    """Make every former module path import its current module (``sys.modules``).

    For a trusted stable-baselines3 ``model.zip``, whose pickles import classes by the path
    they had when it was saved. Imports the current modules (torch among them); idempotent.
    """
    for former, current in FORMER_MODULES.items():
        if former not in sys.modules:
            sys.modules[former] = importlib.import_module(current)
