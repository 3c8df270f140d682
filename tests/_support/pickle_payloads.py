"""Pickles that only write a marker file when they are loaded, and SB3 zips that carry them.

A test first shows the payload is live (loading the file the unsafe way writes the marker), so
that "the marker never appears" means something.
"""

from __future__ import annotations

import base64
import json
import pickle
import zipfile
from pathlib import Path


class Payload:
    """Unpickling this writes ``marker`` (and nothing else)."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self) -> tuple[object, tuple[str]]:
        return (exec, (f"open({str(self.marker)!r}, 'w').write('ran')",))


def payload(marker: Path) -> bytes:
    return pickle.dumps(Payload(marker))


def poison_zip(zip_path: Path, marker: Path, *, member: str = "data") -> None:
    """Add a cloudpickled entry to SB3's ``data`` JSON (or replace ``member`` by a pickle)."""
    with zipfile.ZipFile(zip_path) as archive:
        members = {name: archive.read(name) for name in archive.namelist()}
    if member == "data":
        data = json.loads(members["data"])
        data["extra"] = {
            ":type:": "<class 'object'>",
            ":serialized:": base64.b64encode(payload(marker)).decode(),
        }
        members["data"] = json.dumps(data).encode()
    else:
        members[member] = payload(marker)
    with zipfile.ZipFile(zip_path, "w") as archive:
        for name, content in members.items():
            archive.writestr(name, content)
