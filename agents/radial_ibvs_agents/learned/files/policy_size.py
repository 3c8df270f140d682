"""Checks on a policy described by ``policy.json`` before anything is allocated for it.

A ``policy.json`` can ask for any network (``net_arch: [65536, 65536, 65536]`` is 16 GiB of
weights) or space (``Discrete(10**11)``), and only ``policy.json`` need change for that: the
SHA-256 it holds is of the weights file, which stays as it was. So before the policy is built:

- every width in ``net_arch`` and every integer among the feature extractor's arguments is at
  most :data:`MAX_LAYER_WIDTH`; a space holds at most :data:`MAX_SPACE_ELEMENTS` numbers;
- the parameters that ``net_arch`` implies (a lower bound: its layers' weight matrices) are at
  most those of ``policy.safetensors``, whose header lists every tensor's shape (read without
  reading the tensors); the weights file itself is bounded by
  :data:`radial_ibvs_agents.untrusted.MAX_WEIGHTS_BYTES`.

After it is built, each stored tensor must have the dtype of the parameter it fills (no silent
cast of ``int64`` weights), and after loading every weight must be finite.
"""

from __future__ import annotations

import itertools
import json
import math
import struct
from pathlib import Path
from typing import Any

from radial_ibvs_agents.untrusted import MAX_JSON_BYTES, UntrustedFileError, check_inside
from radial_ibvs_gym.limits import MAX_LAYER_WIDTH, MAX_LAYERS

__all__ = [
    "MAX_LAYERS",
    "MAX_LAYER_WIDTH",
    "MAX_SPACE_ELEMENTS",
    "check_finite_weights",
    "check_net_arch",
    "check_policy_size",
    "check_space_size",
    "check_weight_types",
    "read_weight_shapes",
]

#: the most numbers one observation or action space may hold (a ``Discrete``'s ``n`` too)
MAX_SPACE_ELEMENTS = 1 << 22

#: safetensors' dtype names, as torch names them
_DTYPES = {
    "F64": "float64",
    "F32": "float32",
    "F16": "float16",
    "BF16": "bfloat16",
    "I64": "int64",
    "I32": "int32",
    "I16": "int16",
    "I8": "int8",
    "U8": "uint8",
    "BOOL": "bool",
}


def read_weight_shapes(weights: Path | str) -> dict[str, tuple[str, tuple[int, ...]]]:
    """Read the tensor names, dtypes and shapes from a safetensors file's header.

    Parameters
    ----------
    weights
        ``policy.safetensors``.

    Returns
    -------
    dict
        ``{name: (dtype, shape)}``, dtypes as torch names them (``"float32"``).

    Raises
    ------
    UntrustedFileError
        For a header that is missing, too long, or not the safetensors layout.
    """
    path = check_inside(weights, None)
    try:
        with open(path, "rb") as handle:
            head = handle.read(8)
            if len(head) < 8:
                raise ValueError("shorter than a safetensors header")
            (length,) = struct.unpack("<Q", head)
            if length > MAX_JSON_BYTES:
                raise ValueError(f"a header of {length} bytes (MAX_JSON_BYTES = {MAX_JSON_BYTES})")
            header = json.loads(handle.read(length))
        shapes = {}
        for name, entry in header.items():
            if name == "__metadata__":
                continue
            shape = tuple(int(n) for n in entry["shape"])
            if any(n < 0 for n in shape):
                raise ValueError(f"tensor {name[:60]!r} has shape {shape}")
            shapes[str(name)] = (_DTYPES.get(str(entry["dtype"]), str(entry["dtype"])), shape)
    except (OSError, ValueError, KeyError, TypeError, AttributeError, RecursionError) as error:
        raise UntrustedFileError(f"{path} is not a safetensors file: {str(error)[:200]}") from None
    return shapes


def check_space_size(space: Any, where: str) -> None:
    """Refuse a space of more than :data:`MAX_SPACE_ELEMENTS` numbers (before it is used).

    Raises
    ------
    ValueError
        Naming ``where`` and the size.
    """
    spaces = getattr(space, "spaces", None)
    if isinstance(spaces, dict):
        total = 0
        for key, sub in spaces.items():
            check_space_size(sub, f"{where}[{key!r}]")
            total += math.prod(getattr(sub, "shape", ()) or (1,))
        size = total
    else:
        size = int(getattr(space, "n", 0)) or math.prod(getattr(space, "shape", ()) or (1,))
    if size > MAX_SPACE_ELEMENTS:
        raise ValueError(
            f"{where}: {size} numbers exceed MAX_SPACE_ELEMENTS = {MAX_SPACE_ELEMENTS}"
        )


def _integers(value: Any, where: str) -> list[tuple[str, int]]:
    """Every integer in a nested value, with where it is."""
    if isinstance(value, bool):
        return []
    if isinstance(value, int):
        return [(where, value)]
    if isinstance(value, dict):
        return [i for k, v in value.items() for i in _integers(v, f"{where}[{k!r}]")]
    if isinstance(value, list | tuple):
        if len(value) > MAX_LAYERS:
            raise ValueError(f"{where}: {len(value)} items exceed MAX_LAYERS = {MAX_LAYERS}")
        return [i for n, v in enumerate(value) for i in _integers(v, f"{where}[{n}]")]
    return []


def check_net_arch(value: Any, where: str) -> None:
    """Check a ``net_arch`` asked for by a config, before any network is built.

    Parameters
    ----------
    value
        A list of layer widths, or a mapping of such lists (``pi``, ``vf``, ``qf``).
    where
        The config and key, for the message.

    Raises
    ------
    ValueError
        Naming the key and the value: a width that is not an integer in 1..``MAX_LAYER_WIDTH``,
        or more than ``MAX_LAYERS`` layers (:mod:`radial_ibvs_gym.limits`).
    """
    heads = value.items() if isinstance(value, dict) else [("", value)]
    for head, widths in heads:
        name = f"{where}[{head!r}]" if head else where
        if not isinstance(widths, list | tuple):
            raise ValueError(f"{name} must be a list of layer widths, got {str(widths)[:80]}")
        if len(widths) > MAX_LAYERS:
            raise ValueError(f"{name}: {len(widths)} layers exceed MAX_LAYERS = {MAX_LAYERS}")
        for width in widths:
            if (
                isinstance(width, bool)
                or not isinstance(width, int)
                or not 1 <= width <= MAX_LAYER_WIDTH
            ):
                raise ValueError(
                    f"{name} holds {str(width)[:40]}: each width must be an integer in "
                    f"1..MAX_LAYER_WIDTH = {MAX_LAYER_WIDTH}"
                )


def _matrices(widths: Any) -> int:
    """Count the weights of consecutive layers of one ``net_arch`` list (a lower bound)."""
    if not isinstance(widths, list | tuple):
        return 0
    units = [w for w in widths if isinstance(w, int) and not isinstance(w, bool)]
    return sum(a * b for a, b in itertools.pairwise(units))


def check_policy_size(
    kwargs: dict[str, Any],
    observation_space: Any,
    action_space: Any,
    shapes: dict[str, tuple[str, tuple[int, ...]]],
) -> None:
    """Refuse a described policy that would allocate more than its weights file holds.

    Parameters
    ----------
    kwargs
        The policy's keyword arguments from ``policy.json`` (``net_arch``,
        ``features_extractor_kwargs``...).
    observation_space, action_space
        The spaces from ``policy.json``.
    shapes
        :func:`read_weight_shapes` of ``policy.safetensors``.

    Raises
    ------
    ValueError
        Naming the key and the value: a width over :data:`MAX_LAYER_WIDTH`, a space over
        :data:`MAX_SPACE_ELEMENTS`, or a ``net_arch`` implying more parameters than stored.
    """
    check_space_size(observation_space, "observation_space")
    check_space_size(action_space, "action_space")
    for key in ("net_arch", "features_extractor_kwargs", "n_critics", "n_quantiles"):
        for where, value in _integers(kwargs.get(key), f"policy_kwargs.{key}"):
            if not 0 <= value <= MAX_LAYER_WIDTH:
                raise ValueError(
                    f"{where} = {value} is outside 0..MAX_LAYER_WIDTH = {MAX_LAYER_WIDTH}"
                )
    arch = kwargs.get("net_arch")
    heads = list(arch.values()) if isinstance(arch, dict) else [arch]
    implied = sum(_matrices(h) for h in heads)
    stored = sum(math.prod(shape) for _, shape in shapes.values())
    if implied > stored:
        raise ValueError(
            f"policy_kwargs.net_arch = {str(arch)[:80]} implies at least {implied} weights; "
            f"policy.safetensors holds {stored}"
        )


def check_weight_types(policy: Any, weights: Path | str) -> None:
    """Refuse stored tensors whose dtype is not their parameter's (torch would cast silently).

    Raises
    ------
    ValueError
        Naming the tensor and both dtypes.
    """
    shapes = read_weight_shapes(weights)
    for name, tensor in policy.state_dict().items():
        if name in shapes:
            stored = shapes[name][0]
            wanted = str(tensor.dtype).removeprefix("torch.")
            if stored != wanted:
                raise ValueError(
                    f"{weights}: tensor {name!r} is {stored}, the policy's is {wanted}"
                )


def check_finite_weights(policy: Any, weights: Path | str) -> None:
    """Refuse weights that hold NaN or infinity (they would act as NaN, or fail inside torch).

    Raises
    ------
    ValueError
        Naming the first tensor with a non-finite value.
    """
    import torch

    for name, tensor in policy.state_dict().items():
        if tensor.is_floating_point() and not bool(torch.isfinite(tensor).all()):
            raise ValueError(f"{weights}: tensor {name!r} holds NaN or infinite values")
