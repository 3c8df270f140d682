"""Where a trained model came from: the command, the config and the code's revision.

Training (:mod:`radial_ibvs_agents.learned.training.train`) and distillation
(:mod:`radial_ibvs_agents.learned.dagger.distill`) write
the same provenance into a model's ``metadata.json``, so a model names what made it.
"""

from __future__ import annotations

import platform
import subprocess
import sys
from pathlib import Path
from typing import Any

__all__ = ["git_revision", "jsonable", "provenance", "versions"]


def git_revision() -> str:
    """Return the checkout's commit, with ``+dirty`` when tracked files differ from it.

    ``"unknown"`` outside a git checkout (an installed wheel) or without git.
    """
    here = Path(__file__).resolve().parent

    def git(*args: str) -> str:
        return subprocess.run(
            ["git", *args], capture_output=True, text=True, check=True, cwd=here
        ).stdout.strip()

    try:
        revision = git("rev-parse", "HEAD")
        dirty = git("status", "--porcelain", "--untracked-files=no")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"
    return f"{revision}+dirty" if dirty else revision


def jsonable(value: Any) -> Any:
    """Return ``value`` as JSON can hold it: mappings and sequences kept, anything else its repr."""
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    if isinstance(value, str | int | float | bool) or value is None:
        return value
    return repr(value)


def provenance(command: str | None, source: Any) -> dict[str, Any]:
    """Return a model's ``command``, ``config`` and ``git_revision`` metadata entries.

    Parameters
    ----------
    command
        The command line that trained the model, or ``None`` for this process's ``sys.argv``.
    source
        The config as loaded (its file's path and the settings read from it).
    """
    return {
        "command": command or " ".join(sys.argv),
        "config": jsonable(source),
        "git_revision": git_revision(),
    }


def versions() -> dict[str, str]:
    """Return the versions of Python and of the learning stack that trained a model."""
    return {
        "python": platform.python_version(),
        "stable_baselines3": __import__("stable_baselines3").__version__,
        "torch": __import__("torch").__version__,
        "gymnasium": __import__("gymnasium").__version__,
    }
