"""Reading files that a user hands over (models, chunks): bounded, inside their folder, named.

A model directory or a benchmark chunk may come from anyone. Every read here checks the size
before reading (never a whole 64 GiB file), refuses a symbolic link that leads out of the
folder it belongs to, checks the declared sizes of an archive's members before inflating one,
and turns every failure into a :class:`UntrustedFileError` that names the file. Nothing here
unpickles or imports anything.

==============================  ==========  =============================================
limit                           value       what it bounds
==============================  ==========  =============================================
``MAX_JSON_BYTES``              4 MiB       ``metadata.json``, ``policy.json``, a chunk
``MAX_JSON_DEPTH``              64          nesting of lists and objects in those
``MAX_WEIGHTS_BYTES``           512 MiB     ``policy.safetensors`` (and any other file
                                            hashed or read whole)
``MAX_ARCHIVE_MEMBER_BYTES``    64 MiB      one member of ``normalization.npz`` or of
                                            ``model.zip``, inflated
``MAX_ARCHIVE_BYTES``           1 GiB       all members of one archive, inflated
``MAX_ARCHIVE_MEMBERS``         1024        members of one archive
==============================  ==========  =============================================
"""

from __future__ import annotations

import hashlib
import json
import zipfile
from pathlib import Path
from typing import Any

__all__ = [
    "MAX_ARCHIVE_BYTES",
    "MAX_ARCHIVE_MEMBERS",
    "MAX_ARCHIVE_MEMBER_BYTES",
    "MAX_JSON_BYTES",
    "MAX_JSON_DEPTH",
    "MAX_WEIGHTS_BYTES",
    "UntrustedFileError",
    "check_archive",
    "check_inside",
    "read_bytes",
    "read_json",
    "sha256_file",
]

MAX_JSON_BYTES = 4 << 20
MAX_JSON_DEPTH = 64
MAX_WEIGHTS_BYTES = 512 << 20
MAX_ARCHIVE_MEMBER_BYTES = 64 << 20
MAX_ARCHIVE_BYTES = 1 << 30
MAX_ARCHIVE_MEMBERS = 1024

_CHUNK = 1 << 20


class UntrustedFileError(ValueError):
    """A file handed over that is too large, too deep, outside its folder, or corrupt."""


def check_inside(path: Path | str, folder: Path | str | None) -> Path:
    """Return ``path`` if it exists as a regular file that (links resolved) lies in ``folder``.

    Parameters
    ----------
    path
        The file.
    folder
        The folder it belongs to (a model directory, a chunk store); ``None``: any place.

    Raises
    ------
    UntrustedFileError
        If it is missing, not a regular file (a device, a FIFO), or a link out of ``folder``.
    """
    path = Path(path)
    try:
        resolved = path.resolve(strict=True)
    except (OSError, RuntimeError) as error:  # missing, or a loop of links
        raise UntrustedFileError(f"{path}: cannot be read: {error}") from None
    if folder is not None and not resolved.is_relative_to(Path(folder).resolve()):
        raise UntrustedFileError(f"{path}: a link to {resolved}, outside {folder}: refused")
    if not resolved.is_file():
        raise UntrustedFileError(f"{path}: not a regular file")
    return path


def _size(path: Path, limit: int, name: str) -> int:
    try:
        size = path.stat().st_size
    except OSError as error:
        raise UntrustedFileError(f"{path}: cannot be read: {error}") from None
    if size > limit:
        raise UntrustedFileError(f"{path}: {size} bytes exceed {name} = {limit}")
    return size


def read_bytes(
    path: Path | str,
    folder: Path | str | None,
    limit: int = MAX_WEIGHTS_BYTES,
    name: str = "MAX_WEIGHTS_BYTES",
) -> bytes:
    """Read a whole file of at most ``limit`` bytes (checked before reading, and while reading).

    Raises
    ------
    UntrustedFileError
        As :func:`check_inside`, or for a file larger than ``limit`` (naming ``name``).
    """
    path = check_inside(path, folder)
    _size(path, limit, name)
    try:
        with open(path, "rb") as handle:
            data = handle.read(limit + 1)  # the file may grow between stat and read
    except OSError as error:
        raise UntrustedFileError(f"{path}: cannot be read: {error}") from None
    if len(data) > limit:
        raise UntrustedFileError(f"{path}: more than {name} = {limit} bytes")
    return data


def _depth(value: Any) -> int:
    """Return the nesting depth of parsed JSON (without recursion)."""
    deepest, stack = 0, [(value, 1)]
    while stack:
        item, level = stack.pop()
        if isinstance(item, dict | list):
            deepest = max(deepest, level)
            children = item.values() if isinstance(item, dict) else item
            stack.extend((child, level + 1) for child in children)
    return deepest


def read_json(
    path: Path | str,
    folder: Path | str | None,
    limit: int = MAX_JSON_BYTES,
    name: str = "MAX_JSON_BYTES",
) -> Any:
    """Parse a JSON file of at most ``limit`` bytes (``name``) and :data:`MAX_JSON_DEPTH` levels.

    Raises
    ------
    UntrustedFileError
        As :func:`read_bytes`, or for text that is not JSON or nests too deep (Python's own
        parser would end in a ``RecursionError``).
    """
    data = read_bytes(path, folder, limit, name)
    try:
        value = json.loads(data)
    except RecursionError:  # Python's parser gives up near 1,000 levels
        raise UntrustedFileError(
            f"{path}: nested deeper than MAX_JSON_DEPTH = {MAX_JSON_DEPTH}"
        ) from None
    except (ValueError, UnicodeDecodeError) as error:
        raise UntrustedFileError(
            f"{path} is corrupt: {type(error).__name__}: {str(error)[:200]}"
        ) from None
    if _depth(value) > MAX_JSON_DEPTH:
        raise UntrustedFileError(f"{path}: nested deeper than MAX_JSON_DEPTH = {MAX_JSON_DEPTH}")
    return value


def sha256_file(path: Path | str, folder: Path | str | None, limit: int = MAX_WEIGHTS_BYTES) -> str:
    """SHA-256 of a file of at most ``limit`` bytes, read in 1 MiB pieces.

    Raises
    ------
    UntrustedFileError
        As :func:`read_bytes`.
    """
    path = check_inside(path, folder)
    _size(path, limit, "MAX_WEIGHTS_BYTES")
    digest, total = hashlib.sha256(), 0
    try:
        with open(path, "rb") as handle:
            while piece := handle.read(_CHUNK):
                total += len(piece)
                if total > limit:
                    raise UntrustedFileError(f"{path}: more than MAX_WEIGHTS_BYTES = {limit} bytes")
                digest.update(piece)
    except OSError as error:
        raise UntrustedFileError(f"{path}: cannot be read: {error}") from None
    return digest.hexdigest()


def check_archive(
    path: Path | str,
    folder: Path | str | None,
    member_limit: int = MAX_ARCHIVE_MEMBER_BYTES,
) -> Path:
    """Check a zip archive (``.npz``, ``model.zip``) before anything in it is inflated.

    Python's ``zipfile`` never inflates a member beyond its declared size (it stops there and
    fails the CRC), so bounding the declared sizes bounds the memory.

    Raises
    ------
    UntrustedFileError
        As :func:`check_inside`; for a file that is not a zip archive (a ``.npy`` named
        ``.npz``), more than :data:`MAX_ARCHIVE_MEMBERS` members, or a member (or all of them)
        that inflates beyond the limits.
    """
    path = check_inside(path, folder)
    _size(path, MAX_WEIGHTS_BYTES, "MAX_WEIGHTS_BYTES")
    try:
        with zipfile.ZipFile(path) as archive:
            members = archive.infolist()
    except (zipfile.BadZipFile, OSError, ValueError) as error:
        raise UntrustedFileError(f"{path}: not a zip archive: {str(error)[:200]}") from None
    if len(members) > MAX_ARCHIVE_MEMBERS:
        raise UntrustedFileError(
            f"{path}: {len(members)} members exceed MAX_ARCHIVE_MEMBERS = {MAX_ARCHIVE_MEMBERS}"
        )
    for member in members:
        if member.file_size > member_limit:
            raise UntrustedFileError(
                f"{path}: member {member.filename[:80]!r} inflates to {member.file_size} bytes, "
                f"more than MAX_ARCHIVE_MEMBER_BYTES = {member_limit}"
            )
    total = sum(m.file_size for m in members)
    if total > MAX_ARCHIVE_BYTES:
        raise UntrustedFileError(
            f"{path}: members inflate to {total} bytes, more than MAX_ARCHIVE_BYTES"
        )
    return path
