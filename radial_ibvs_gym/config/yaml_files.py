"""Reading YAML configs safely and within bounds, and their ``base:`` overlays.

:func:`read_yaml` parses one file with PyYAML's safe loader, strict (no anchors, aliases or
duplicate keys; bounded size, depth and values; YAML 1.2 numbers); :func:`read_yaml_with_base`
lays a config on the ``base:`` it varies; :func:`configs_dir` and :func:`config_path` find the
shipped configs.
"""

from __future__ import annotations

import contextlib
import functools
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from radial_ibvs_gym.config.errors import ConfigError, clip_message, did_you_mean, short
from radial_ibvs_gym.limits import (
    MAX_CONFIG_BASES,
    MAX_CONFIG_BYTES,
    MAX_CONFIG_DEPTH,
    MAX_CONFIG_NODES,
)

__all__ = ["config_path", "configs_dir", "merge_overlay", "read_yaml", "read_yaml_with_base"]


def read_yaml(source: str | Path, where: str | None = None) -> Any:
    """Parse YAML safely and within bounds: a file path, or YAML text with ``where`` set.

    Only plain YAML: PyYAML's safe loader (no Python objects), and no anchors or aliases
    (``&name``, ``*name``: a few hundred bytes of them expand to gigabytes); at most
    :data:`~radial_ibvs_gym.limits.MAX_CONFIG_BYTES` bytes and
    :data:`~radial_ibvs_gym.limits.MAX_CONFIG_DEPTH` levels of nesting.

    Parameters
    ----------
    source
        A path to a YAML file or, when ``where`` is given, the YAML text itself.
    where
        What the text is, for the messages (e.g. ``"--env-kwarg physics"``).

    Returns
    -------
    Any
        The parsed value (``None`` for an empty document).

    Raises
    ------
    ConfigError
        For a file that is missing, too large, too deep, not YAML, or uses anchors, aliases or
        tags of Python objects; the message names the file (or ``where``) and the line.
    """
    import yaml

    if where is None:
        path = Path(source)
        where = str(path)
        try:
            size = path.stat().st_size
            if size > MAX_CONFIG_BYTES:
                raise ConfigError(
                    f"{where}: {size} bytes exceed MAX_CONFIG_BYTES = {MAX_CONFIG_BYTES}"
                )
            text = path.read_text()
        except (OSError, UnicodeDecodeError) as error:
            raise ConfigError(f"{where}: cannot read it: {clip_message(str(error))}") from None
    else:
        text = str(source)
        if len(text) > MAX_CONFIG_BYTES:
            raise ConfigError(f"{where}: {len(text)} characters exceed MAX_CONFIG_BYTES")
    loader = None
    try:
        loader = _strict_loader_class()(text)
        return loader.get_single_data()
    except ConfigError as error:
        raise ConfigError(f"{where}: {error}") from None
    except yaml.YAMLError as error:  # the problem and where, never the file's text
        raise ConfigError(f"{where}: not valid YAML: {_yaml_problem(error)}") from None
    except (ValueError, OverflowError, RecursionError) as error:  # e.g. a 5,000-digit integer
        line = loader.line + 1 if loader is not None else "?"
        raise ConfigError(
            f"{where}: line {line}: a value cannot be read: {type(error).__name__}: "
            f"{clip_message(str(error))}"
        ) from None
    finally:
        if loader is not None:
            loader.dispose()


def merge_overlay(base: Mapping[str, Any], overlay: Mapping[str, Any]) -> dict[str, Any]:
    """Return ``base`` with ``overlay`` laid on top, mapping by mapping.

    A mapping in both is merged key by key (recursively); any other value of ``overlay``
    replaces ``base``'s; a ``null`` (``None``) in ``overlay`` removes the key, so that the
    default applies. Neither argument is changed.
    """
    out = dict(base)
    for key, value in overlay.items():
        if value is None:
            out.pop(key, None)
        elif isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = merge_overlay(out[key], value)
        else:
            out[key] = value
    return out


def read_yaml_with_base(path: str | Path, *, any_base: bool = False) -> Any:
    """Read a YAML config that may be an overlay of another one (a top-level ``base:`` key).

    ``base: other.yaml`` names the config this one varies, by a path relative to this file's
    folder; the result is the base (itself read the same way) with this file laid on top by
    :func:`merge_overlay`, without the ``base`` key. A config without ``base:`` is read as
    :func:`read_yaml` reads it. At most :data:`~radial_ibvs_gym.limits.MAX_CONFIG_BASES` files
    are chained; a file that names itself, directly or not, is refused.

    A base must lie (links resolved) beside the config that names it (in its folder or below),
    or in the package's ``configs/`` or the repository's ``research/configs/`` trees: so
    ``research/configs``' ``../../configs/agents/...`` holds, while an absolute path or one
    that climbs out of those trees is refused, unless ``any_base`` allows it.

    Raises
    ------
    ConfigError
        For a bad ``base`` value, a missing base file, a cycle, too long a chain, a base out of
        the trees above, or any error of :func:`read_yaml`; the message names the file and the
        value.
    """
    chain: list[Path] = []
    layers: list[Mapping[str, Any]] = []
    current = Path(path)
    while True:
        resolved = current.resolve()
        if resolved in chain:
            names = " -> ".join(str(p) for p in [*chain, resolved])
            raise ConfigError(f"{path}: its base: chain comes back to a file it holds: {names}")
        if len(chain) >= MAX_CONFIG_BASES:
            raise ConfigError(
                f"{path}: more than MAX_CONFIG_BASES = {MAX_CONFIG_BASES} chained base: files"
            )
        chain.append(resolved)
        data = read_yaml(current)
        if not isinstance(data, Mapping) or "base" not in data:
            if len(layers) == 0:
                return data
            if not isinstance(data, Mapping):  # its type, never its text
                kind = type(data).__name__
                raise ConfigError(f"{current}: a base: file must be a mapping, got a {kind}")
            break
        base = data["base"]
        if not isinstance(base, str) or not base.endswith((".yaml", ".yml")):
            raise ConfigError(
                f"{current}: base must be the path of a .yaml file, got {short(base)}"
            )
        layers.append({k: v for k, v in data.items() if k != "base"})
        following = current.parent / base
        if not following.is_file():
            raise ConfigError(f"{current}: base {short(base)}: no such file ({following})")
        if not any_base:
            _check_base(current, base, following)
        current = following
    merged: dict[str, Any] = dict(data)
    for layer in reversed(layers):
        merged = merge_overlay(merged, layer)
    return merged


def _check_base(config: Path, base: str, following: Path) -> None:
    """Refuse a ``base:`` that is absolute or leaves the trees a base may come from."""
    if Path(base).is_absolute():
        raise ConfigError(f"{config}: base {short(base)} is an absolute path: give it relative")
    trees = [config.resolve().parent]
    with contextlib.suppress(FileNotFoundError):
        package = configs_dir().resolve()
        trees += [package, package.parent / "research" / "configs"]
    if not any(following.resolve().is_relative_to(tree) for tree in trees):
        raise ConfigError(
            f"{config}: base {short(base)} leaves the folders a base may come from (beside "
            "the config, configs/, research/configs/)"
        )


def _yaml_problem(error: Exception) -> str:
    """Return a YAML error's problem and position, not the text PyYAML quotes with it."""
    problem = getattr(error, "problem", None) or type(error).__name__
    mark = getattr(error, "problem_mark", None)
    where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
    return clip_message(f"{problem}{where}")


@functools.cache
def _strict_loader_class() -> type:
    import yaml

    class StrictLoader(yaml.SafeLoader):
        """PyYAML's safe loader without anchors and aliases, nesting and size bounded.

        Numbers as YAML 1.2 reads them (``1e6`` is a float, not the string YAML 1.1 makes
        of it); no timestamps (a date stays a string).
        """

        depth = 0
        nodes = 0

        def compose_node(self, parent: Any, index: Any) -> Any:
            event = self.peek_event()
            line = event.start_mark.line + 1
            if isinstance(event, yaml.AliasEvent) or getattr(event, "anchor", None) is not None:
                raise ConfigError(f"line {line}: YAML anchors and aliases (&, *) are not allowed")
            self.nodes += 1
            if self.nodes > MAX_CONFIG_NODES:
                raise ConfigError(
                    f"line {line}: more than MAX_CONFIG_NODES = {MAX_CONFIG_NODES} values"
                )
            self.depth += 1
            try:
                if self.depth > MAX_CONFIG_DEPTH:
                    raise ConfigError(
                        f"line {line}: nested deeper than MAX_CONFIG_DEPTH = {MAX_CONFIG_DEPTH}"
                    )
                return super().compose_node(parent, index)
            finally:
                self.depth -= 1

        def construct_mapping(self, node: Any, deep: bool = False) -> Any:
            seen: set[Any] = set()
            for key_node, _ in node.value:
                key = self.construct_object(key_node, deep=True)
                if isinstance(key, list | dict):
                    continue  # unhashable: PyYAML's own error names it
                if key in seen:
                    line = key_node.start_mark.line + 1
                    raise ConfigError(f"line {line}: duplicate key {short(key)}")
                seen.add(key)
            return super().construct_mapping(node, deep=deep)

    resolvers = {
        first: [
            (tag, regexp) for tag, regexp in entries if not tag.endswith((":float", ":timestamp"))
        ]
        for first, entries in yaml.SafeLoader.yaml_implicit_resolvers.items()
    }
    StrictLoader.yaml_implicit_resolvers = resolvers
    StrictLoader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT_1_2, list("-+0123456789."))
    return StrictLoader


#: YAML 1.2's floats (``1e6``, ``1.5``, ``.5``, ``-2.0E-3``, ``.inf``, ``.nan``): YAML 1.1
#: needs a dot in the mantissa, so PyYAML reads ``1e6`` as a string
_FLOAT_1_2 = re.compile(
    r"""^(?:[-+]?(?:[0-9][0-9_]*)\.[0-9_]*(?:[eE][-+]?[0-9]+)?
    |[-+]?(?:[0-9][0-9_]*)(?:[eE][-+]?[0-9]+)
    |\.[0-9_]+(?:[eE][-+]?[0-9]+)?
    |[-+]?\.(?:inf|Inf|INF)
    |\.(?:nan|NaN|NAN))$""",
    re.X,
)


def configs_dir() -> Path:
    """Return the folder holding the YAML configs.

    A source checkout (or an editable install) uses the repository's top-level ``configs/``; a
    wheel carries a copy as ``radial_ibvs_gym/_configs``.
    """
    here = Path(__file__).resolve().parent.parent
    for candidate in (here / "_configs", here.parent / "configs"):
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError(
        f"no configs folder found (looked in {here / '_configs'} and {here.parent / 'configs'})"
    )


def config_path(kind: str, name: str) -> Path:
    """Path of the shipped config ``configs/<kind>/<name>.yaml``.

    Raises
    ------
    ConfigError
        If there is no such config; the message lists the available names.
    """
    folder = configs_dir() / kind
    path = folder / f"{name}.yaml"
    if not path.is_file():
        available = sorted(p.stem for p in folder.glob("*.yaml")) if folder.is_dir() else []
        raise ConfigError(
            f"unknown {kind} config {short(name)}{did_you_mean(name, available)}; "
            f"available: {available}"
        )
    return path
