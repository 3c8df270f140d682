"""A copy of a shipped model whose training env asked another hold (a test fixture's body)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

from radial_ibvs_agents.learned.files.loading import MODELS_DIR


def model_trained_with_hold(folder: Path, hold: int, name: str = "dagger-student") -> Path:
    """Copy shipped ``name`` into ``folder`` with ``success_hold_steps: hold`` in its env."""
    target = folder / f"{name}-hold-{hold}"
    shutil.copytree(MODELS_DIR / name, target)
    metadata = json.loads((target / "metadata.json").read_text())
    metadata["env_kwargs"]["success_hold_steps"] = hold
    (target / "metadata.json").write_text(json.dumps(metadata))
    return target
