"""Minari datasets on local disk: where they are, how to check one and read it (no hub).

:mod:`radial_ibvs_agents.experiments.collect` writes them (``radial-ibvs collect``);
:mod:`radial_ibvs_agents.learned.dagger.distill` reads a teacher's dataset as its first labels.
A dataset is data: :func:`check_dataset` reads its metadata in pure Python before Minari sees
it (Minari would build the env that a dataset's ``env_spec`` names), and
:func:`load_collected` calls it first.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from radial_ibvs_agents.learned.files.policy_size import MAX_SPACE_ELEMENTS
from radial_ibvs_agents.untrusted import UntrustedFileError, read_json
from radial_ibvs_gym.registration import ENTRY_POINTS, ENV_IDS, VECTOR_ENTRY_POINTS

__all__ = [
    "MAX_SPACE_DEPTH",
    "MAX_SUBSPACES",
    "UnsafeDatasetError",
    "check_dataset",
    "datasets_path",
    "load_collected",
    "minari_module",
]


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

    Its metadata is checked first (:func:`check_dataset`), before Minari is imported.

    Returns
    -------
    minari.MinariDataset
        Iterate its episodes (``observations`` a dict of arrays, ``actions``, ``rewards``...).

    Raises
    ------
    UnsafeDatasetError
        For a dataset whose metadata :func:`check_dataset` refuses.
    """
    directory = Path(path)
    if not (directory / "data").is_dir():
        raise UnsafeDatasetError(f"{directory} is not a Minari dataset directory (no data/)")
    check_dataset(directory)
    minari = minari_module()
    root = directory.parent.parent
    dataset_id = f"{directory.parent.name}/{directory.name}"
    with datasets_path(root):
        return minari.load_dataset(dataset_id)


#: what a dataset's ``metadata.json`` may describe: the space types, and their dtypes
_SPACE_TYPES = ("Box", "Discrete", "Dict", "Tuple")
_DTYPES = ("float16", "float32", "float64", "int8", "int16", "int32", "int64", "uint8", "bool")
#: at most this many subspaces in a ``Dict`` or ``Tuple`` space, and nested this deep
MAX_SUBSPACES, MAX_SPACE_DEPTH = 256, 8


class UnsafeDatasetError(UntrustedFileError):
    """A dataset whose metadata would make Minari build an env or allocate without a bound."""


def check_dataset(directory: Path | str) -> dict[str, Any]:
    """Check a Minari dataset's ``data/metadata.json`` before Minari reads it (pure Python).

    Minari calls ``gym.make`` on the dataset's ``env_spec`` when either space is missing from
    the metadata, and an ``env_spec`` may name any ``module:callable`` as its entry point: a
    dataset handed over could run code. So, before Minari is imported:

    - ``observation_space`` and ``action_space`` must be present, of the types Minari writes
      (``Box``, ``Discrete``, ``Dict``, ``Tuple``), with finite bounds and at most
      ``MAX_SPACE_ELEMENTS`` numbers;
    - ``env_spec`` (and ``eval_env_spec``, if set) must name one of this package's env ids with
      the registry's own ``entry_point`` (and vector entry point), and no
      ``additional_wrappers`` (``radial-ibvs collect`` records none).

    Parameters
    ----------
    directory
        The dataset's directory (``DIR/<namespace>/<name>``, holding ``data/``).

    Returns
    -------
    dict
        The metadata, as read.

    Raises
    ------
    UnsafeDatasetError
        Naming the file, the key and the value, for any of the above; nothing is imported.
    """
    path = Path(directory) / "data" / "metadata.json"
    if not path.is_file():
        raise UnsafeDatasetError(f"{Path(directory)} is not a Minari dataset (no {path.name})")
    metadata = read_json(path, path.parent)
    if not isinstance(metadata, dict):
        raise UnsafeDatasetError(f"{path}: not a JSON object")
    for key in ("observation_space", "action_space"):
        if key not in metadata:
            raise UnsafeDatasetError(
                f"{path}: {key} is missing (Minari would build the env from env_spec to find it)"
            )
        _check_space(_json_value(metadata[key], path, key), path, key, [0], 0)
    for key in ("env_spec", "eval_env_spec"):
        if metadata.get(key) is None and key == "eval_env_spec":
            continue
        _check_env_spec(_json_value(metadata.get(key), path, key), path, key)
    return metadata


def _json_value(value: Any, path: Path, key: str) -> Any:
    """Return a metadata value that Minari stores as a JSON string, decoded."""
    if not isinstance(value, str):
        raise UnsafeDatasetError(f"{path}: {key} must be a JSON string, got {_short(value)}")
    try:
        return json.loads(value)
    except ValueError:
        raise UnsafeDatasetError(f"{path}: {key} is not valid JSON") from None


def _short(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."


def _numbers(value: Any, where: str, path: Path) -> int:
    """Count the finite numbers of a nested list (a Box's bounds); refuse anything else."""
    stack, count = [value], 0
    while stack:
        item = stack.pop()
        if isinstance(item, list):
            stack.extend(item)
        elif isinstance(item, int | float) and not isinstance(item, bool) and math.isfinite(item):
            count += 1
        else:
            raise UnsafeDatasetError(f"{path}: {where} holds {_short(item)}, not a finite number")
        if count > MAX_SPACE_ELEMENTS:
            break
    return count


def _check_space(space: Any, path: Path, where: str, total: list[int], depth: int) -> None:
    """Check one space description (recursively), counting its numbers in ``total``."""
    if depth > MAX_SPACE_DEPTH or not isinstance(space, dict):
        raise UnsafeDatasetError(f"{path}: {where} is not a space description")
    kind = space.get("type")
    if kind not in _SPACE_TYPES:
        raise UnsafeDatasetError(
            f"{path}: {where} has type {_short(kind)}; valid: {list(_SPACE_TYPES)}"
        )
    if kind in ("Dict", "Tuple"):
        subspaces = space.get("subspaces")
        items = (
            list(subspaces.items())
            if isinstance(subspaces, dict)
            else list(enumerate(subspaces))
            if isinstance(subspaces, list)
            else None
        )
        if items is None or len(items) > MAX_SUBSPACES:
            raise UnsafeDatasetError(f"{path}: {where} needs at most {MAX_SUBSPACES} subspaces")
        for name, sub in items:
            _check_space(sub, path, f"{where}[{_short(name)}]", total, depth + 1)
        return
    if kind == "Discrete":
        n = space.get("n")
        if not isinstance(n, int) or isinstance(n, bool) or not 0 < n <= MAX_SPACE_ELEMENTS:
            raise UnsafeDatasetError(f"{path}: {where}.n must be in 1..{MAX_SPACE_ELEMENTS}")
        total[0] += 1
    else:  # Box
        shape, dtype = space.get("shape"), space.get("dtype")
        if dtype not in _DTYPES:
            raise UnsafeDatasetError(f"{path}: {where}.dtype {_short(dtype)}; valid: {_DTYPES}")
        if not isinstance(shape, list) or not all(
            isinstance(d, int) and not isinstance(d, bool) and d >= 0 for d in shape
        ):
            raise UnsafeDatasetError(f"{path}: {where}.shape {_short(shape)} is not a shape")
        size = math.prod(shape)
        total[0] += size
        for bound in ("low", "high"):
            if _numbers(space.get(bound), f"{where}.{bound}", path) not in (size, 1):
                raise UnsafeDatasetError(f"{path}: {where}.{bound} does not fit {shape}")
    if total[0] > MAX_SPACE_ELEMENTS:
        raise UnsafeDatasetError(f"{path}: {where} holds over {MAX_SPACE_ELEMENTS} numbers")


def _check_env_spec(spec: Any, path: Path, key: str) -> None:
    """Check that an env spec names this package's env as the registry makes it."""
    if not isinstance(spec, dict):
        raise UnsafeDatasetError(f"{path}: {key} is not an env spec")
    env_id = spec.get("id")
    if env_id not in ENTRY_POINTS:
        raise UnsafeDatasetError(
            f"{path}: {key}.id {_short(env_id)} is not one of this package's envs {list(ENV_IDS)}"
        )
    if spec.get("entry_point") != ENTRY_POINTS[env_id]:
        raise UnsafeDatasetError(
            f"{path}: {key}.entry_point {_short(spec.get('entry_point'))} is not "
            f"{env_id}'s ({ENTRY_POINTS[env_id]})"
        )
    vector = spec.get("vector_entry_point")
    if vector is not None and vector != VECTOR_ENTRY_POINTS.get(env_id):
        raise UnsafeDatasetError(
            f"{path}: {key}.vector_entry_point {_short(vector)} is not {env_id}'s"
        )
    if spec.get("additional_wrappers") not in (None, []):
        raise UnsafeDatasetError(
            f"{path}: {key}.additional_wrappers must be empty (the datasets of radial-ibvs "
            f"collect record none), got {_short(spec.get('additional_wrappers'))}"
        )
