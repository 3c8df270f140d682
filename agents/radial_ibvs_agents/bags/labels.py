"""What a robot's owner gives a replay without a landmark map: labels, depths, a goal image.

A labels file (YAML) names where each landmark is in the goal image and in the first frame,
in pixels, and the goal depths ``d*``::

    goal: [[201.5, 96.0], [64.2, 130.8], null, [180.0, 200.5]]   # (column, row); null: unseen
    first: [[190.1, 88.7], null, [120.3, 40.2], [170.0, 210.0]]
    goal_depths: [2.1, 3.4, 2.8, 1.9]                            # metres (eq. 12's d*)

Read as data (the project's bounded YAML reader), each value checked; an error names the file,
the key and the value. A goal image file is a PNG (grey levels) or a ``.npy`` array (read
without pickles), its size bounded before it is decoded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Labels", "read_goal_image", "read_labels"]

#: the largest goal image file, bytes
MAX_IMAGE_FILE_BYTES = 64 * 2**20


@dataclass(frozen=True)
class Labels:
    """The landmarks' positions in the goal image and the first frame, and the goal depths."""

    goal: NDArray[np.float64]  # (N, 2) pixels, NaN where not seen
    first: NDArray[np.float64]  # (N, 2)
    goal_depths: NDArray[np.float64] | None  # (N,) metres


def _positions(path: Path, key: str, value: Any) -> NDArray[np.float64]:
    if not isinstance(value, list) or not value:
        raise ValueError(f"{path}: {key} must be a list of [column, row] or null, got {value!r}")
    rows = []
    for k, item in enumerate(value):
        if item is None:
            rows.append((math.nan, math.nan))
            continue
        ok = isinstance(item, list) and len(item) == 2
        ok = ok and all(isinstance(x, int | float) and not isinstance(x, bool) for x in item)
        if not ok or not all(math.isfinite(x) and 0 <= x < 1e5 for x in item):
            raise ValueError(
                f"{path}: {key}[{k}] must be [column, row] in pixels (or null), got {item!r}"
            )
        rows.append((float(item[0]), float(item[1])))
    return np.array(rows, dtype=np.float64)


def read_labels(path: Path | str) -> Labels:
    """Read a labels file (module docs).

    Raises
    ------
    ValueError
        For a missing or unknown key, or a bad value (named with the file).
    """
    from radial_ibvs_gym.config.yaml_files import read_yaml

    path = Path(path)
    data = read_yaml(path)
    if not isinstance(data, dict):
        raise ValueError(f"{path}: a mapping with goal, first and goal_depths, got {type(data)}")
    unknown = sorted(set(data) - {"goal", "first", "goal_depths"})
    missing = sorted({"goal", "first"} - set(data))
    if unknown or missing:
        raise ValueError(f"{path}: unknown keys {unknown}, missing keys {missing}")
    goal = _positions(path, "goal", data["goal"])
    first = _positions(path, "first", data["first"])
    if len(goal) != len(first):
        raise ValueError(f"{path}: goal has {len(goal)} landmarks, first {len(first)}")
    depths = data.get("goal_depths")
    if depths is not None:
        ok = isinstance(depths, list) and len(depths) == len(goal)
        ok = ok and all(isinstance(d, int | float) and not isinstance(d, bool) for d in depths)
        if not ok or not all(math.isfinite(d) and 0 < d < 1e3 for d in depths):
            raise ValueError(
                f"{path}: goal_depths must be {len(goal)} distances in metres (0 to 1000), "
                f"got {depths!r}"
            )
        depths = np.asarray(depths, dtype=np.float64)
    return Labels(goal, first, depths)


def read_goal_image(path: Path | str, max_pixels: int) -> NDArray[np.uint8]:
    """Read a goal image: a PNG in grey levels, or a ``.npy`` ``(H, W)`` uint8 array.

    Raises
    ------
    ValueError
        For another format, a file over :data:`MAX_IMAGE_FILE_BYTES`, more than
        ``max_pixels`` pixels, or another mode or dtype.
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such goal image")
    if path.stat().st_size > MAX_IMAGE_FILE_BYTES:
        raise ValueError(f"{path}: over {MAX_IMAGE_FILE_BYTES} bytes")
    suffix = path.suffix.lower()
    if suffix == ".npy":
        with path.open("rb") as stream:  # the header checked, then the array, from one open
            version = np.lib.format.read_magic(stream)
            read_header = (
                np.lib.format.read_array_header_1_0
                if version == (1, 0)
                else np.lib.format.read_array_header_2_0
            )
            shape, fortran, dtype = read_header(stream)
            if dtype != np.uint8 or len(shape) != 2 or math.prod(shape) > max_pixels:
                raise ValueError(f"{path}: a (H, W) uint8 array of at most {max_pixels} pixels, "
                                 f"got {shape} {dtype}")  # fmt: skip
            data = np.fromfile(stream, dtype=np.uint8, count=math.prod(shape))
        if len(data) != math.prod(shape):
            raise ValueError(f"{path}: {len(data)} bytes for a {shape} array")
        return np.ascontiguousarray(data.reshape(shape, order="F" if fortran else "C"))
    if suffix == ".png":
        from PIL import Image

        with Image.open(path, formats=["PNG"]) as image:  # no other decoder reads it
            if image.width * image.height > max_pixels:
                raise ValueError(
                    f"{path}: {image.width} x {image.height} (at most {max_pixels} px)"
                )
            if image.mode != "L":
                raise ValueError(f"{path}: a grey (mode L) PNG, got mode {image.mode!r}")
            return np.asarray(image, dtype=np.uint8).copy()
    raise ValueError(f"{path}: a goal image is a .png or a .npy file, got {suffix!r}")
