"""Gymnasium's ``AutoresetMode``, and the same enum where Gymnasium (1.0) does not have it.

Gymnasium 1.1 added ``gymnasium.vector.AutoresetMode``; 1.0 steps vector envs in the
``NEXT_STEP`` mode only and has no enum. The native vector env takes all three modes on either
version, so it imports the enum from here.
"""

from __future__ import annotations

from enum import Enum

__all__ = ["AutoresetMode"]

try:
    from gymnasium.vector import AutoresetMode
except ImportError:  # gymnasium 1.0

    class AutoresetMode(Enum):  # type: ignore[no-redef]
        """When a vector env resets its ended envs (values as Gymnasium 1.1's enum)."""

        NEXT_STEP = "NextStep"
        SAME_STEP = "SameStep"
        DISABLED = "Disabled"
