"""The ``radial-ibvs`` command line: a short dispatcher, one module per command.

Each command module (:mod:`.demo`, :mod:`.reproduce`, :mod:`.evaluate`, :mod:`.train`,
:mod:`.distill`, :mod:`.collect`, :mod:`.benchmark`, :mod:`.report`, :mod:`.sweep`, :mod:`.render`,
:mod:`.image`, :mod:`.record`, :mod:`.replay`) has ``add_parser(sub)`` and ``run(args)``; its
heavy imports happen inside ``run``, so ``radial-ibvs --help`` is instant.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from radial_ibvs_agents.cli import (
    benchmark,
    collect,
    demo,
    distill,
    evaluate,
    image,
    record,
    render,
    replay,
    report,
    reproduce,
    sweep,
    train,
)

__all__ = ["COMMANDS", "build_parser", "main"]

#: the commands, in the order of ``--help``
COMMANDS = {
    "demo": demo,
    "reproduce": reproduce,
    "evaluate": evaluate,
    "train": train,
    "distill": distill,
    "collect": collect,
    "benchmark": benchmark,
    "report": report,
    "sweep": sweep,
    "render": render,
    "image": image,
    "record": record,
    "replay": replay,
}


#: what an interrupted command kept, and how to go on
RESUME_HINTS = {
    "benchmark": "; the finished chunks are in OUT/chunks: rerun the same command to resume",
    "sweep": "; the finished seeds are in OUT/seed-*: rerun the same command to resume",
    "train": "; checkpoints are in OUT/checkpoints: --resume continues from one",
}


def build_parser() -> argparse.ArgumentParser:
    """Return the argument parser of ``radial-ibvs`` (one sub-parser per command)."""
    parser = argparse.ArgumentParser(
        prog="radial-ibvs",
        description=(
            "Visual servoing of mobile robots with (non-)central catadioptric cameras "
            "(Aliakbarpour, Tahri, Araujo, RAS 2014)."
        ),
    )
    from radial_ibvs_gym import __version__

    parser.add_argument("--version", action="version", version=f"radial-ibvs {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for module in COMMANDS.values():
        module.add_parser(sub)
    return parser


#: the commands whose ``--out`` is a file (the others' is a folder)
FILE_OUTPUTS = ("render", "image", "demo")


def _check_out(args: argparse.Namespace) -> None:
    """Refuse an ``--out`` that cannot be written, before any work (not after the whole run).

    Raises
    ------
    ValueError
        For an ``--out`` folder that is a file, or under one; or a folder that exists and
        cannot be written.
    """
    import os
    from pathlib import Path

    out = getattr(args, "out", None)
    if out is None:
        return
    path = Path(out)
    folder = path.parent if args.command in FILE_OUTPUTS else path
    for parent in (folder, *folder.parents):
        if parent.exists():
            if not parent.is_dir():
                raise ValueError(f"--out {out}: {parent} is a file, not a folder")
            if not os.access(parent, os.W_OK | os.X_OK):
                raise ValueError(f"--out {out}: {parent} cannot be written (permissions)")
            return


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``radial-ibvs``; returns the process exit code."""
    from concurrent.futures.process import BrokenProcessPool

    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(argv)
    args.argv = argv  # the command line, for the metadata of what it writes
    hint = RESUME_HINTS.get(args.command, "")
    try:
        _check_out(args)
        return int(COMMANDS[args.command].run(args))
    except (ValueError, KeyError) as error:  # bad name, file or value: a message
        message = error.args[0] if error.args else error
        print(f"radial-ibvs {args.command}: error: {message}", file=sys.stderr)
        return 2
    except BrokenProcessPool:  # a worker was killed (out of memory, a signal)
        print(
            f"radial-ibvs {args.command}: error: a worker process died (killed, or out of "
            f"memory){hint}",
            file=sys.stderr,
        )
        return 1
    except OSError as error:  # a full or read-only disk, a folder that cannot be made
        where = f" {error.filename}" if error.filename else ""
        print(
            f"radial-ibvs {args.command}: error: cannot write{where}: {error.strerror or error}"
            f"{hint}",
            file=sys.stderr,
        )
        return 1
    except KeyboardInterrupt:  # Ctrl-C: what is saved stays saved (and says how to resume)
        print(f"\nradial-ibvs {args.command}: interrupted{hint}", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
