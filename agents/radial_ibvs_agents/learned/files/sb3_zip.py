"""A stable-baselines3 ``model.zip`` loaded through its pickles: only when the user trusts it.

``radial-ibvs evaluate --trust-model`` and ``load(..., trust_pickle=True)`` take a folder holding
only SB3's own ``model.zip``. Its algorithm is told from the archive's ``data`` entry, read as
plain JSON (the policy class's module, then the settings only one algorithm has), before any
pickle is touched; :func:`load_sb3_zip` then loads it with a :class:`PickleLoadWarning`.
"""

from __future__ import annotations

import json
import zipfile
from pathlib import Path
from typing import Any

from radial_ibvs_agents.learned.files.former_paths import former_modules
from radial_ibvs_agents.learned.files.model_files import algorithms
from radial_ibvs_agents.untrusted import check_archive

__all__ = ["PickleLoadWarning", "algo_of_zip", "load_sb3_zip"]


class PickleLoadWarning(UserWarning):
    """A model is being loaded through pickles, as asked (``trust_pickle``, ``--trust-model``)."""


#: hyper-parameters that only one algorithm's ``model.zip`` ``data`` holds
_ALGO_MARKS = (
    ("top_quantiles_to_drop_per_net", "tqc"),
    ("policy_delay", "td3"),
    ("target_entropy", "sac"),
    ("clip_range", "ppo"),
    ("n_steps", "a2c"),
)
#: the modules of the policy classes only one algorithm uses (``data``'s ``policy_class``)
_POLICY_MODULES = {
    "sb3_contrib.common.recurrent.policies": "recurrent_ppo",
    "sb3_contrib.tqc.policies": "tqc",
    "stable_baselines3.td3.policies": "td3",
    "stable_baselines3.sac.policies": "sac",
}


def algo_of_zip(zip_path: Path, label: str) -> str:
    """Return the algorithm of an SB3 ``model.zip`` (its ``data`` entry read as plain JSON)."""
    try:
        check_archive(zip_path, zip_path.parent)
        with zipfile.ZipFile(zip_path) as archive:
            data = json.loads(archive.read("data"))
    except (zipfile.BadZipFile, KeyError, ValueError, RecursionError) as error:
        raise ValueError(f"model {label}: {zip_path} is corrupt: {str(error)[:300]}") from None
    if isinstance(data, dict):
        policy_class = data.get("policy_class")
        module = policy_class.get("__module__") if isinstance(policy_class, dict) else None
        if module in _POLICY_MODULES:
            return _POLICY_MODULES[module]
        for key, algo in _ALGO_MARKS:  # PPO and A2C share their policies: their settings differ
            if key in data:
                return algo
    raise ValueError(
        f"model {label}: cannot tell the algorithm of {zip_path}; add a metadata.json with "
        f'{{"algo": "ppo"}} (or one of {sorted(algorithms())}) beside it'
    )


def load_sb3_zip(zip_path: Path, metadata: dict[str, Any], label: str) -> Any:
    """Load a stable-baselines3 ``model.zip`` through its pickles (only when trusted).

    The archive is checked first (sizes, members: ``check_archive``), and a
    :class:`PickleLoadWarning` says that a pickle is being loaded.
    """
    import pickle
    import warnings

    check_archive(zip_path, zip_path.parent)
    warnings.warn(
        f"model {label}: loading {zip_path} through its pickles (trust_pickle / --trust-model): "
        "it can run code; load only models from a source you trust",
        PickleLoadWarning,
        stacklevel=3,
    )

    algos = algorithms()
    algo = metadata.get("algo")
    if algo not in algos:
        raise ValueError(f"model {label}: unknown algo {str(algo)[:40]!r}; valid: {sorted(algos)}")
    # off-policy models: no replay buffer to predict (a HER buffer would even need the env)
    inference: dict[str, Any] | None = (
        {"replay_buffer_class": None, "replay_buffer_kwargs": {}, "buffer_size": 1}
        if algo in ("sac", "td3", "tqc")
        else None
    )
    try:
        with former_modules():  # its pickles name classes by the paths they had when saved
            return algos[algo].load(zip_path, device="cpu", custom_objects=inference)
    except (
        zipfile.BadZipFile,
        ValueError,
        KeyError,
        RuntimeError,
        EOFError,
        pickle.UnpicklingError,
    ) as error:
        raise ValueError(f"model {label}: {zip_path} is corrupt: {str(error)[:300]}") from None
