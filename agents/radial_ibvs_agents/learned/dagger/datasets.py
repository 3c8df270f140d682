"""Minari datasets on local disk: where they are and how to read one (no hub).

:mod:`radial_ibvs_agents.experiments.collect` writes them (``radial-ibvs collect``);
:mod:`radial_ibvs_agents.learned.dagger.distill` reads a teacher's dataset as its first labels.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

__all__ = ["datasets_path", "load_collected", "minari_module"]


def minari_module() -> Any:
    """Import Minari, or raise a ``ValueError`` naming the extra to install."""
    try:
        import minari
    except ImportError:
        raise ValueError(
            "Minari datasets need Minari: pip install 'radial_ibvs_gym[datasets]'"
        ) from None
    return minari


@contextlib.contextmanager
def datasets_path(directory: Path) -> Iterator[None]:
    """Point Minari at ``directory`` (its ``MINARI_DATASETS_PATH``) for the block."""
    old = os.environ.get("MINARI_DATASETS_PATH")
    os.environ["MINARI_DATASETS_PATH"] = str(directory.resolve())
    try:
        yield
    finally:
        if old is None:
            del os.environ["MINARI_DATASETS_PATH"]
        else:
            os.environ["MINARI_DATASETS_PATH"] = old


def load_collected(path: Path | str) -> Any:
    """Load a dataset written by :func:`collect` (its directory ``DIR/<namespace>/<name>``).

    Returns
    -------
    minari.MinariDataset
        Iterate its episodes (``observations`` a dict of arrays, ``actions``, ``rewards``...).
    """
    minari = minari_module()
    directory = Path(path)
    if not (directory / "data").is_dir():
        raise ValueError(f"{directory} is not a Minari dataset directory (no data/)")
    root = directory.parent.parent
    dataset_id = f"{directory.parent.name}/{directory.name}"
    with datasets_path(root):
        return minari.load_dataset(dataset_id)
