"""The configs' errors: :class:`ConfigError`, and values shortened for its messages."""

from __future__ import annotations

import reprlib
from typing import Any

__all__ = [
    "MAX_MESSAGE_CHARS",
    "MAX_VALUE_CHARS",
    "ConfigError",
    "clip_message",
    "did_you_mean",
    "short",
]


class ConfigError(ValueError):
    """A configuration that does not match its schema (unknown key, missing key, bad type)."""


#: the longest a value or message is printed in an error
MAX_VALUE_CHARS = 120
MAX_MESSAGE_CHARS = 600


def short(value: Any, limit: int = MAX_VALUE_CHARS) -> str:
    """Return ``repr(value)``, shortened for an error message (long lists and strings cut)."""
    printer = reprlib.Repr()
    printer.maxlist = printer.maxtuple = printer.maxdict = printer.maxset = 6
    printer.maxstring = printer.maxother = limit
    printer.maxlevel = 4
    text = printer.repr(value)
    return text if len(text) <= limit else text[: limit - 3] + "..."


def did_you_mean(name: str, valid: Any) -> str:
    """Return ``" (did you mean 'x'?)"`` for the closest of ``valid`` to ``name``, or ``""``."""
    import difflib

    close = difflib.get_close_matches(str(name), [str(v) for v in valid], n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def clip_message(message: str) -> str:
    """Return ``message`` cut to :data:`MAX_MESSAGE_CHARS` characters."""
    return (
        message if len(message) <= MAX_MESSAGE_CHARS else message[: MAX_MESSAGE_CHARS - 3] + "..."
    )
