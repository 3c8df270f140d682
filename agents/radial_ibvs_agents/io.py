"""Files written all at once: atomic writes, JSON and CSV rows.

Every file the commands write goes through :func:`write_atomic`: a reader (or a run stopped
half-way) never sees a half-written file.
"""

from __future__ import annotations

import csv
import io
import json
import os
import tempfile
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

__all__ = ["current_umask", "json_safe", "write_atomic", "write_csv", "write_json", "write_through"]


def write_atomic(path: Path | str, data: str | bytes) -> Path:
    """Write a file all at once: to a temporary file beside it, then rename (nothing half-way).

    Parameters
    ----------
    path
        Destination; missing parent folders are created.
    data
        Text (written as UTF-8) or bytes.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    payload = data.encode() if isinstance(data, str) else data
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
        os.chmod(tmp, 0o666 & ~current_umask())  # mkstemp makes 0600; give the usual permissions
        os.replace(tmp, path)
    except OSError as error:  # a full or read-only disk: name the file
        Path(tmp).unlink(missing_ok=True)
        reason = error.strerror or str(error)
        raise OSError(error.errno, f"cannot write {path}: {reason}") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def write_through(path: Path | str, data: str | bytes) -> Path:
    """Rewrite an existing file all at once, as :func:`write_atomic`, keeping what it is.

    A symbolic link is written through (its target is rewritten; the link stays a link), and
    the file keeps its permission bits (a 0600 page stays 0600).

    Returns
    -------
    pathlib.Path
        The file written (the link's target).
    """
    target = Path(path).resolve() if Path(path).is_symlink() else Path(path)
    mode = target.stat().st_mode & 0o7777
    write_atomic(target, data)
    os.chmod(target, mode)
    return target


def current_umask() -> int:
    """Return the process's umask (read by setting it and setting it back)."""
    mask = os.umask(0)
    os.umask(mask)
    return mask


def json_safe(row: Mapping[str, Any]) -> dict[str, Any]:
    """Keep the JSON scalars of a row (``None``, text, numbers, booleans, and dicts of them)."""
    return {
        k: v
        for k, v in row.items()
        if v is None or isinstance(v, str | int | float | bool) or _scalar_dict(v)
    }


def _scalar_dict(value: Any) -> bool:
    return isinstance(value, dict) and all(
        isinstance(v, str | int | float | bool) for v in value.values()
    )


def write_json(path: Path | str, data: Any) -> Path:
    """Write ``data`` as indented JSON (one object per line of a list is easy to diff)."""
    return write_atomic(path, json.dumps(data, indent=1) + "\n")


def write_csv(
    path: Path | str,
    rows: Iterable[Mapping[str, Any]] | Iterable[Sequence[Any]],
    columns: Sequence[str],
) -> Path:
    """Write rows (dicts, keyed by ``columns``, extra keys ignored; or sequences) as CSV."""
    buffer = io.StringIO()
    items = list(rows)
    if items and isinstance(items[0], Mapping):
        dict_writer = csv.DictWriter(buffer, columns, extrasaction="ignore", lineterminator="\n")
        dict_writer.writeheader()
        dict_writer.writerows(items)  # type: ignore[arg-type]
    else:
        writer = csv.writer(buffer, lineterminator="\n")
        writer.writerow(columns)
        writer.writerows(items)
    return write_atomic(path, buffer.getvalue())
