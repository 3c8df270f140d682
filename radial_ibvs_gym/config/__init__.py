"""Typed configuration: strict construction of frozen dataclasses from YAML or dicts.

Domain dataclasses (mirrors, intrinsics, robots, scenarios, agent settings) live in their own
layers and validate their values in ``__post_init__``; this module only turns mappings into them,
rejecting unknown or missing keys with the full key path in the message.
"""

from radial_ibvs_gym.config.errors import ConfigError, did_you_mean, short
from radial_ibvs_gym.config.loader import from_mapping, load_yaml
from radial_ibvs_gym.config.yaml_files import (
    config_path,
    configs_dir,
    merge_overlay,
    read_yaml,
    read_yaml_with_base,
)

__all__ = [
    "ConfigError",
    "config_path",
    "configs_dir",
    "did_you_mean",
    "from_mapping",
    "load_yaml",
    "merge_overlay",
    "read_yaml",
    "read_yaml_with_base",
    "short",
]
