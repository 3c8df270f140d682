"""matplotlib, loaded only when a figure is drawn, and figures saved atomically."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

from radial_ibvs_agents.io import write_atomic

__all__ = ["pyplot", "save_figure"]


def pyplot() -> Any:
    """Return ``matplotlib.pyplot``, imported here (no backend forced: Jupyter stays inline)."""
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig: Any, path: Path | str, *, dpi: int = 110, close: bool = True) -> Path:
    """Save a figure atomically, in the format of the path's suffix (PNG by default).

    Parameters
    ----------
    fig
        A matplotlib ``Figure``.
    path
        Destination (``.png``, ``.pdf``, ``.svg``...); parent folders are created.
    dpi
        Resolution, dots per inch.
    close
        Close the figure afterwards (frees its memory in long runs).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    buffer = io.BytesIO()
    fig.savefig(buffer, format=Path(path).suffix.lstrip(".") or "png", dpi=dpi)
    if close:
        pyplot().close(fig)
    return write_atomic(path, buffer.getvalue())
