"""Command-line options shared by several commands."""

from __future__ import annotations

from typing import Any

__all__ = ["add_backend_options"]


def add_backend_options(parser: Any, task: str) -> None:
    """Add ``--backend`` and ``--address`` (where the jobs run) to ``parser``.

    Parameters
    ----------
    parser
        An ``argparse`` parser.
    task
        What one Ray task runs, for the help text (e.g. ``"20-episode chunk"``).
    """
    from agents.experiments.backends import BACKENDS

    parser.add_argument(
        "--backend",
        choices=BACKENDS,
        default="local",
        help=f"local processes, or one Ray task per {task} (default: %(default)s)",
    )
    parser.add_argument(
        "--address",
        help="Ray cluster to join: 'auto' or HOST:PORT (default: a private local instance)",
    )
