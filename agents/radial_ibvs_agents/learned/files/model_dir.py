"""Writing a model folder all at once: no half-written model, no stale file from an older one.

A model folder **owns** the files that make the model (:data:`MODEL_FILES`): the weights and
their description, ``metadata.json``, ``normalization.npz``, and what ``train`` and ``distill``
add beside them (SB3's ``model.zip`` and ``best_model.zip``, ``learning_curve.png``). It does
not own what a run leaves there (``progress.csv``, ``logs/``, ``eval/``, ``best/``,
``checkpoints/``, ``rounds/``): those are kept as they are.

:func:`replace_model_files` gives the writer an empty staging folder beside the target. When
the writer is done, the staging folder becomes the model folder:

1. every entry of the old folder that the new model does not own and did not write is linked
   into the staging folder (hard links: no copy, and the old folder is untouched);
2. the old folder is renamed aside, the staging folder renamed to the target (``os.rename``
   of a folder cannot replace a non-empty one, hence the two renames), and the old one removed.

So a reader finds the old model or the new one, never a mix, and an owned file the new model
lacks (a ``normalization.npz`` from an earlier, normalised model) is gone. Between the two
renames the target is missing for a moment; a crash there leaves both folders beside it, named
``.NAME.old-*`` and ``.NAME.new-*``. A writer that fails removes its staging folder and leaves
the old model as it was.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import uuid
from collections.abc import Collection, Iterator
from contextlib import contextmanager
from pathlib import Path

from radial_ibvs_agents.io import current_umask

__all__ = ["BEST_FILES", "MODEL_FILES", "replace_model_files"]

#: the files a model folder owns (:func:`replace_model_files` removes those the new model lacks)
MODEL_FILES = frozenset(
    {
        "policy.safetensors",
        "policy.json",
        "metadata.json",
        "normalization.npz",
        "model.zip",
        "best_model.zip",
        "learning_curve.png",
    }
)
#: what training's ``best/`` folder owns beside the ``best_model.zip`` that SB3 writes there
BEST_FILES = frozenset({"policy.safetensors", "policy.json", "normalization.npz"})


@contextmanager
def replace_model_files(
    directory: Path | str, owned: Collection[str] = MODEL_FILES
) -> Iterator[Path]:
    """Write a model's files into a staging folder; make it the model folder on success.

    Parameters
    ----------
    directory
        The model folder (created if missing; its parent too).
    owned
        The file names the model folder owns: those the new model lacks are removed.

    Yields
    ------
    pathlib.Path
        The empty staging folder to write into (beside ``directory``).

    Raises
    ------
    ValueError
        If ``directory`` exists and is not a folder (or is a symbolic link).
    """
    out = Path(directory)
    if out.is_symlink() or (out.exists() and not out.is_dir()):
        raise ValueError(f"{out} exists and is not a folder: a model folder is written there")
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}.new-", dir=out.parent))
    try:
        yield staging
        _swap(staging, out, frozenset(owned))
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise


def _swap(staging: Path, out: Path, owned: frozenset[str]) -> None:
    """Make ``staging`` the folder ``out``, keeping the entries of ``out`` it does not own."""
    os.chmod(staging, 0o777 & ~current_umask())  # mkdtemp makes it 0700: the usual permissions
    if not out.exists():
        os.rename(staging, out)
        return
    for entry in out.iterdir():
        if entry.name not in owned and not (staging / entry.name).exists():
            _link(entry, staging / entry.name)
    old = out.with_name(f".{out.name}.old-{uuid.uuid4().hex[:8]}")
    os.rename(out, old)
    os.rename(staging, out)
    shutil.rmtree(old, ignore_errors=True)


def _link(source: Path, target: Path) -> None:
    """Hard-link a file or a folder's files (copy where the file system cannot link)."""
    if source.is_dir() and not source.is_symlink():
        shutil.copytree(source, target, symlinks=True, copy_function=_link_file)
    else:
        _link_file(source, target)


def _link_file(source: str | Path, target: str | Path) -> None:
    if Path(source).is_symlink():
        os.symlink(os.readlink(source), target)
        return
    try:
        os.link(source, target)
    except OSError:
        shutil.copy2(source, target)
