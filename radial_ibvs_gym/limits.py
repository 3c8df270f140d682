"""The documented limits on what a configuration may ask for.

Each bounds the memory or time one value can cost (the pair features grow as the square of
the landmark count; every obstacle is tested against every robot at every step), so that a
small file can never take the machine down. An error that hits a limit names it.

=====================  ==========  ===================================================
limit                  value       what it bounds
=====================  ==========  ===================================================
``MAX_LANDMARKS``      256         landmarks of a scenario (fixed, or drawn per episode)
                                   and the env's ``max_landmarks`` slots
``MAX_OBSTACLES``      64          obstacles of a scenario (fixed plus drawn)
``MAX_NUM_ENVS``       4096        robots of one native vector env (``num_envs``)
``MAX_CONFIG_BYTES``   1 MiB       size of a YAML config file
``MAX_CONFIG_DEPTH``   32          nesting of lists and mappings in a YAML config
``MAX_CONFIG_BASES``   8           chained ``base:`` files under one config overlay
``MAX_CONFIG_NODES``   100,000     values (scalars, lists, mappings) of a YAML config
``MAX_WORLD_M``        1000 m      every room side, coordinate and radius of a scenario,
                                   so that every distance and reward term stays finite
``MAX_SUBSTEPS``       1000        physics sub-steps per control period
                                   (``control_dt / physics_dt``, pymunk backend)
=====================  ==========  ===================================================

YAML anchors and aliases (``&name``, ``*name``) are refused outright: they let a file of a
few hundred bytes expand to gigabytes.
"""

from __future__ import annotations

__all__ = [
    "MAX_CONFIG_BASES",
    "MAX_CONFIG_BYTES",
    "MAX_CONFIG_DEPTH",
    "MAX_CONFIG_NODES",
    "MAX_LANDMARKS",
    "MAX_NUM_ENVS",
    "MAX_OBSTACLES",
    "MAX_SUBSTEPS",
    "MAX_WORLD_M",
]

MAX_LANDMARKS = 256
MAX_OBSTACLES = 64
MAX_NUM_ENVS = 4096
MAX_CONFIG_BYTES = 1 << 20
MAX_CONFIG_DEPTH = 32
MAX_CONFIG_BASES = 8
MAX_CONFIG_NODES = 100_000
MAX_WORLD_M = 1000.0
MAX_SUBSTEPS = 1000
