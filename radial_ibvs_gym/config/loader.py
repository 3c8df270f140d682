"""Strict construction of frozen dataclasses from mappings and YAML files.

:func:`from_mapping` turns a mapping into a dataclass, rejecting unknown or missing keys with
the full key path; :func:`load_yaml` reads the YAML first (:mod:`.yaml_files`). The errors are
in :mod:`.errors`.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeVar

from radial_ibvs_gym.config.errors import ConfigError, clip_message, short
from radial_ibvs_gym.config.yaml_files import read_yaml

__all__ = ["from_mapping", "load_yaml"]

T = TypeVar("T")


def _convert(tp: Any, value: Any, where: str) -> Any:
    """Convert ``value`` to the annotated type ``tp`` (dataclasses, tuples, unions, scalars)."""
    origin = typing.get_origin(tp)
    args = typing.get_args(tp)
    if tp is Any:
        return value
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None
        errors = []
        for option in (a for a in args if a is not type(None)):
            try:
                return _convert(option, value, where)
            except (ConfigError, TypeError, ValueError) as exc:
                errors.append(str(exc))
        raise ConfigError(f"{where}: {short(value)} matches none of {tp}: {'; '.join(errors)}")
    if origin is typing.Literal:
        if value not in args:
            raise ConfigError(f"{where}: {short(value)} is not one of {list(args)}")
        return value
    if dataclasses.is_dataclass(tp) and isinstance(tp, type):
        if isinstance(value, tp):
            return value
        if not isinstance(value, Mapping):
            raise ConfigError(f"{where}: expected a mapping for {tp.__name__}, got {short(value)}")
        return from_mapping(tp, value, where=where)
    if origin is tuple:
        if not isinstance(value, (list, tuple)):
            raise ConfigError(f"{where}: expected a list, got {short(value)}")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_convert(args[0], v, f"{where}[{i}]") for i, v in enumerate(value))
        if len(args) != len(value):
            raise ConfigError(
                f"{where}: expected {len(args)} items, got {len(value)}: {short(value)}"
            )
        return tuple(
            _convert(a, v, f"{where}[{i}]")
            for i, (a, v) in enumerate(zip(args, value, strict=True))
        )
    if origin in (dict, Mapping) or tp in (dict, Mapping):
        if not isinstance(value, Mapping):
            raise ConfigError(f"{where}: expected a mapping, got {short(value)}")
        return dict(value)
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise ConfigError(f"{where}: expected a number, got {short(value)}")
        try:
            return float(value)  # YAML reads "inf" and "1e-3" as strings in some cases
        except (ValueError, OverflowError) as exc:
            raise ConfigError(f"{where}: expected a number, got {short(value)}") from exc
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{where}: expected an integer, got {short(value)}")
        return value
    if tp is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{where}: expected true or false, got {short(value)}")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise ConfigError(f"{where}: expected a string, got {short(value)}")
        return value
    return value


def from_mapping(cls: type[T], mapping: Mapping[str, Any], *, where: str = "") -> T:
    """Build the dataclass ``cls`` from ``mapping``, strictly.

    Nested dataclasses, tuples (from YAML lists), ``Literal`` choices, optional values and
    scalars are converted from their annotations. The dataclass's own ``__post_init__`` then
    validates the values.

    Parameters
    ----------
    cls
        A dataclass type.
    mapping
        Its fields by name; fields with defaults may be left out.
    where
        Key path prefix used in error messages (e.g. ``"camera.intrinsics"``).

    Returns
    -------
    cls
        The constructed instance.

    Raises
    ------
    ConfigError
        For an unknown key (the message lists the valid ones), a missing required key or a value
        of the wrong type, naming the full key path. Value errors raised by the dataclass's own
        validation are re-raised as ``ConfigError`` with the key path prepended.
    """
    if not (dataclasses.is_dataclass(cls) and isinstance(cls, type)):
        raise TypeError(f"{cls!r} is not a dataclass type")
    if not isinstance(mapping, Mapping):
        raise ConfigError(f"{where or cls.__name__}: expected a mapping, got {short(mapping)}")
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    prefix = f"{where}." if where else ""
    unknown = sorted(set(mapping) - set(fields))
    if unknown:
        raise ConfigError(
            f"{where or cls.__name__}: unknown key(s) {short(unknown)}; "
            f"valid keys: {sorted(fields)}"
        )
    hints = typing.get_type_hints(cls)
    kwargs: dict[str, Any] = {}
    for name, field in fields.items():
        if name in mapping:
            kwargs[name] = _convert(hints[name], mapping[name], f"{prefix}{name}")
        elif field.default is dataclasses.MISSING and field.default_factory is dataclasses.MISSING:
            raise ConfigError(f"{where or cls.__name__}: missing required key {name!r}")
    try:
        return cls(**kwargs)
    except ConfigError:
        raise
    except (TypeError, ValueError, OverflowError, ArithmeticError) as exc:
        raise ConfigError(clip_message(f"{where or cls.__name__}: {exc}")) from None


def load_yaml(cls: type[T], source: str | Path | Mapping[str, Any], **overrides: Any) -> T:
    """Load a dataclass from a YAML file (or a mapping), with keyword overrides on top.

    Parameters
    ----------
    cls
        The dataclass type to build.
    source
        A path to a YAML file, or an already-parsed mapping.
    **overrides
        Top-level keys that replace those of the file (unknown ones are rejected too).

    Returns
    -------
    cls
        The validated instance.
    """
    if isinstance(source, Mapping):
        data: Any = dict(source)
        where = cls.__name__
    else:
        path = Path(source)
        data = read_yaml(path)
        where = str(path)
        if data is None:
            data = {}
        if not isinstance(data, Mapping):
            raise ConfigError(f"{where}: the top level must be a mapping, got {short(data)}")
    data = {**data, **overrides}
    try:
        return from_mapping(cls, data)
    except ConfigError as exc:
        raise ConfigError(clip_message(f"{where}: {exc}")) from None
