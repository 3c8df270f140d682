"""The documented limits on what a configuration may ask for.

Each bounds the memory or time one value can cost (the pair features grow as the square of
the landmark count; every obstacle is tested against every robot at every step), so that a
small file can never take the machine down. An error that hits a limit names it.

========================  ==========  ===================================================
limit                     value       what it bounds
========================  ==========  ===================================================
``MAX_LANDMARKS``         256         landmarks of a scenario (fixed, or drawn per episode)
                                      and the env's ``max_landmarks`` slots
``MAX_OBSTACLES``         64          obstacles of a scenario (fixed plus drawn)
``MAX_NUM_ENVS``          4096        robots of one native vector env (``num_envs``)
``MAX_CONFIG_BYTES``      1 MiB       size of a YAML config file
``MAX_CONFIG_DEPTH``      32          nesting of lists and mappings in a YAML config
``MAX_CONFIG_BASES``      8           chained ``base:`` files under one config overlay
``MAX_CONFIG_NODES``      100,000     values (scalars, lists, mappings) of a YAML config
``MAX_WORLD_M``           1000 m      every room side, coordinate and radius of a scenario,
                                      so that every distance and reward term stays finite
``MIN_ROBOT_M``           1 mm        the robot's length, width, wheel base and wheel
                                      radius (a body pymunk can simulate)
``MAX_SUBSTEPS``          1000        physics sub-steps per control period
                                      (``control_dt / physics_dt``, pymunk backend)
``MAX_HOLD_STEPS``        600         steps a success may ask the pose held
                                      (``success_hold_steps``)
``MAX_GOAL_FRAMES``       1000        noisy frames the goal image averages
                                      (``goal_image_frames``)
``MAX_IMAGE_SIZE``        2048 px     side of a rendered frame (``image_size``)
``MAX_IMAGE_BLUR``        16 px       Gaussian blur of a rendered frame (``image_blur``)
``MAX_IMAGE_NOISE``       255         pixel noise of a rendered frame, grey levels
``MAX_HISTORY_FRAMES``    32          frames a learned policy's history keeps
``MAX_LAYER_WIDTH``       8192        units of one layer of a network (``net_arch``)
``MAX_LAYERS``            64          layers of one network (``net_arch``)
``MAX_BATCH_SIZE``        2^20        samples of one minibatch (``batch_size``)
``MAX_ROLLOUT_SIZE``      2^24        transitions of one rollout (``n_steps * n_envs``)
``MAX_BUFFER_SIZE``       2^24        transitions of a replay buffer (``buffer_size``)
``MAX_DATASET_SIZE``      2^24        transitions DAgger keeps (``dataset_size``)
``MAX_EPISODES``          100,000     episodes of one evaluation (``eval_episodes``)
========================  ==========  ===================================================

The env's arguments are checked against them in :mod:`radial_ibvs_gym.envs.config`; training
and DAgger configs in ``radial_ibvs_agents.learned`` (``zoo_config``, ``distill_config``,
``history``), before anything is built.

YAML anchors and aliases (``&name``, ``*name``) are refused outright: they let a file of a
few hundred bytes expand to gigabytes.
"""

from __future__ import annotations

__all__ = [
    "MAX_BATCH_SIZE",
    "MAX_BUFFER_SIZE",
    "MAX_CONFIG_BASES",
    "MAX_CONFIG_BYTES",
    "MAX_CONFIG_DEPTH",
    "MAX_CONFIG_NODES",
    "MAX_DATASET_SIZE",
    "MAX_EPISODES",
    "MAX_GOAL_FRAMES",
    "MAX_HISTORY_FRAMES",
    "MAX_HOLD_STEPS",
    "MAX_IMAGE_BLUR",
    "MAX_IMAGE_NOISE",
    "MAX_IMAGE_SIZE",
    "MAX_LANDMARKS",
    "MAX_LAYERS",
    "MAX_LAYER_WIDTH",
    "MAX_NUM_ENVS",
    "MAX_OBSTACLES",
    "MAX_ROLLOUT_SIZE",
    "MAX_SUBSTEPS",
    "MAX_WORLD_M",
    "MIN_ROBOT_M",
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
MAX_HOLD_STEPS = 600
MAX_GOAL_FRAMES = 1000
MAX_IMAGE_SIZE = 2048
MAX_IMAGE_BLUR = 16.0
MAX_IMAGE_NOISE = 255.0
MAX_HISTORY_FRAMES = 32
MAX_LAYER_WIDTH = 8192
MAX_LAYERS = 64
MAX_BATCH_SIZE = 1 << 20
MAX_ROLLOUT_SIZE = 1 << 24
MAX_BUFFER_SIZE = 1 << 24
MAX_DATASET_SIZE = 1 << 24
MAX_EPISODES = 100_000
MIN_ROBOT_M = 0.001
