"""What stood between the env and a stable-baselines3 policy in training, recorded and replayed.

SB3 changes an observation on its way from the env to the policy: ``VecTransposeImage`` (which
the algorithm adds itself for channel-last images: the policy sees ``(C, H, W)`` where the env
gives ``(H, W, C)``), ``VecFrameStack`` (which a user adds: the policy sees the last ``n``
observations side by side, zeros before an episode's first) and ``VecNormalize``. A policy
evaluated on the env's own observations needs the same steps. :func:`describe_wrappers` reads
them from the training env when :func:`~radial_ibvs_agents.learned.files.saving.save_model_dir`
saves a model (``metadata.json``'s ``observation_wrappers``, innermost first, plain JSON), and
:class:`ObservationReplay` replays them for a loaded policy through SB3's own wrapper classes
around a stand-in ``VecEnv`` that only hands them the observations, so a frame stack is reset and
shifted exactly as in training.

A wrapper that changes observations in a way not listed here (``VecExtractDictObs``, one of the
user's own) is refused when the model is saved, by name: a model saved behind it could not be
evaluated.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

__all__ = [
    "WRAPPERS",
    "ObservationReplay",
    "ReplayState",
    "check_wrappers",
    "describe_wrappers",
    "predict_replayed",
    "read_observation_path",
    "replay_space",
    "same_space",
]

#: the wrappers a model directory may record, by the name ``metadata.json`` stores
WRAPPERS = ("normalize", "frame_stack", "transpose_image")
#: SB3 ``VecEnv`` wrappers that leave observations as they are
_PASS_THROUGH = ("VecMonitor", "VecCheckNan", "VecVideoRecorder")
#: the most frames a frame stack may ask (a model file is data: its sizes are bounded)
MAX_STACK = 64


def describe_wrappers(venv: Any) -> list[dict[str, Any]]:
    """Return the observation wrappers of an SB3 ``VecEnv``, innermost first, as JSON values.

    Parameters
    ----------
    venv
        The training ``VecEnv`` with its wrappers (``model.get_env()``).

    Returns
    -------
    list of dict
        ``{"name": "normalize"}``, ``{"name": "frame_stack", "n_stack": n, "channels_order":
        "first" | "last" | {key: ...}}`` or ``{"name": "transpose_image"}``, in the order the
        observations pass through them.

    Raises
    ------
    ValueError
        For a wrapper that changes observations and cannot be replayed, naming its class.
    """
    from stable_baselines3.common.vec_env import (
        VecEnvWrapper,
        VecFrameStack,
        VecNormalize,
        VecTransposeImage,
    )

    found: list[dict[str, Any]] = []
    layer = venv
    while isinstance(layer, VecEnvWrapper):
        if isinstance(layer, VecNormalize):
            found.append({"name": "normalize"})
        elif isinstance(layer, VecFrameStack):
            stack = layer.stacked_obs
            n_stack, order = int(stack.n_stack), _order(stack)
            found.append({"name": "frame_stack", "n_stack": n_stack, "channels_order": order})
        elif isinstance(layer, VecTransposeImage):
            if not layer.skip:
                found.append({"name": "transpose_image"})
        elif type(layer).__name__ not in _PASS_THROUGH:
            raise ValueError(
                f"{type(layer).__name__} changes what the model sees and cannot be replayed when "
                f"it is evaluated; the wrappers that can: VecNormalize, VecFrameStack, "
                f"VecTransposeImage (and {', '.join(_PASS_THROUGH)}, which change nothing)"
            )
        layer = layer.venv
    return found[::-1]


def _order(stack: Any) -> Any:
    """Return a ``StackedObservations``' stacking side: ``"first"``/``"last"``, or per key."""
    subs = getattr(stack, "sub_stacked_observations", None)
    if subs is not None:
        return {key: _order(sub) for key, sub in subs.items()}
    return "first" if stack.channels_first else "last"


def same_space(a: Any, b: Any) -> bool:
    """Whether two spaces have the same keys, shapes and dtypes (bounds aside)."""
    sub_a, sub_b = getattr(a, "spaces", None), getattr(b, "spaces", None)
    if isinstance(sub_a, dict) or isinstance(sub_b, dict):
        if not (isinstance(sub_a, dict) and isinstance(sub_b, dict)) or set(sub_a) != set(sub_b):
            return False
        return all(same_space(sub_a[k], sub_b[k]) for k in sub_a)
    return a.shape == b.shape and a.dtype == b.dtype


def check_wrappers(wrappers: Any, where: str) -> list[dict[str, Any]]:
    """Validate ``metadata.json``'s ``observation_wrappers`` (data, from a file a user hands over).

    Raises
    ------
    ValueError
        For anything but a list of known wrappers with valid arguments, naming ``where``.
    """
    if not isinstance(wrappers, list):
        raise ValueError(f"{where}: observation_wrappers must be a list, got {wrappers!r:.80}")
    for i, entry in enumerate(wrappers):
        at = f"{where}: observation_wrappers[{i}]"
        if not isinstance(entry, dict) or entry.get("name") not in WRAPPERS:
            raise ValueError(f"{at} must be an object whose name is one of {list(WRAPPERS)}")
        if entry["name"] == "frame_stack":
            n = entry.get("n_stack")
            if type(n) is not int or not 1 <= n <= MAX_STACK:
                raise ValueError(f"{at}: n_stack must be an integer, 1 to {MAX_STACK}, got {n!r}")
            order = entry.get("channels_order")
            sides = order.values() if isinstance(order, dict) else [order]
            if not all(side in ("first", "last") for side in sides):
                raise ValueError(f"{at}: channels_order must be first or last, got {order!r:.80}")
    return wrappers


def replay_space(wrappers: list[dict[str, Any]], space: Any) -> Any:
    """Return the observation space the policy sees behind ``wrappers``, given the env's."""
    from stable_baselines3.common.vec_env import VecTransposeImage
    from stable_baselines3.common.vec_env.stacked_observations import StackedObservations

    for entry in wrappers:
        if entry["name"] == "frame_stack":
            space = StackedObservations(
                1, entry["n_stack"], space, entry["channels_order"]
            ).stacked_observation_space
        elif entry["name"] == "transpose_image":
            space = _transposed_space(space, VecTransposeImage)
    return space


def _transposed_space(space: Any, transpose: Any) -> Any:
    from gymnasium import spaces
    from stable_baselines3.common.preprocessing import is_image_space

    if isinstance(space, spaces.Dict):
        return spaces.Dict(
            {
                k: transpose.transpose_space(s, k) if is_image_space(s) else s
                for k, s in space.spaces.items()
            }
        )
    return transpose.transpose_space(space)


class ObservationReplay:
    """A batch of robots' observations through a model's recorded wrappers, step by step.

    SB3's own ``VecFrameStack`` and ``VecTransposeImage`` wrap a stand-in ``VecEnv`` that
    returns the observations it is handed; the replay holds their state (the stacked frames),
    so it is a policy's state: one per batch of robots, made anew when the batch's size changes.

    Parameters
    ----------
    wrappers
        ``metadata.json``'s ``observation_wrappers`` (:func:`check_wrappers`).
    space, action_space
        The env's observation space (one robot's) and action space.
    n
        The robots in the batch.
    normalise
        The model's observation normalisation (a function of a batch), applied where the list
        says ``normalize``.
    """

    def __init__(
        self,
        wrappers: list[dict[str, Any]],
        space: Any,
        action_space: Any,
        n: int,
        normalise: Any,
    ) -> None:
        from stable_baselines3.common.vec_env import VecFrameStack, VecTransposeImage

        self.n = n
        self.steps: list[Any] = []  # callables of a batch, or stateful SB3 wrappers
        for entry in wrappers:
            name = entry["name"]
            if name == "normalize":
                self.steps.append(normalise)
                continue
            feed = _feed_class()(n, space, action_space)
            if name == "frame_stack":
                layer: Any = VecFrameStack(feed, entry["n_stack"], entry["channels_order"])
            else:
                layer = VecTransposeImage(feed)
            space = layer.observation_space
            self.steps.append((feed, layer))
        self.started = False

    def __call__(self, observation: Any, episode_start: np.ndarray) -> Any:
        """Return what the policy sees for this step's batch of observations.

        Parameters
        ----------
        observation
            The batch's observations (``(n, ...)`` arrays, or a dict of them).
        episode_start
            ``(n,)`` bool: the robots whose observation is an episode's first (their stack
            starts anew, as SB3's ``VecFrameStack`` does after a ``done``).
        """
        for step in self.steps:
            if not isinstance(step, tuple):
                observation = step(observation)
                continue
            feed, layer = step
            feed.observation = observation
            if not self.started:
                observation = layer.reset()
            else:
                feed.dones = np.asarray(episode_start, dtype=bool).copy()
                observation, _, _, _ = layer.step_wait()
        self.started = True
        return _copy(observation)  # a frame stack hands out its own buffer: the caller's copy


def _copy(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: np.array(v) for k, v in value.items()}
    return np.array(value)


@functools.cache
def _feed_class() -> Any:
    from stable_baselines3.common.vec_env import VecEnv

    class Feed(VecEnv):
        """A ``VecEnv`` that returns the observations it is handed: what SB3's wrappers wrap."""

        def __init__(self, n: int, space: Any, action_space: Any) -> None:
            super().__init__(n, space, action_space)
            self.observation: Any = None
            self.dones = np.zeros(n, dtype=bool)

        def reset(self) -> Any:
            return self.observation

        def step_async(self, actions: np.ndarray) -> None:  # never called
            raise NotImplementedError

        def step_wait(self) -> Any:
            infos: list[dict[str, Any]] = [{} for _ in range(self.num_envs)]
            for i in np.flatnonzero(self.dones):  # what SB3 gives a wrapper at a done
                infos[i]["terminal_observation"] = _row(self.observation, int(i))
            return self.observation, np.zeros(self.num_envs), self.dones, infos

        def close(self) -> None:
            pass

        def get_attr(self, attr_name: str, indices: Any = None) -> list[Any]:
            raise AttributeError(attr_name)

        def set_attr(self, attr_name: str, value: Any, indices: Any = None) -> None:
            raise AttributeError(attr_name)

        def env_method(self, method_name: str, *args: Any, indices: Any = None, **kw: Any) -> Any:
            raise AttributeError(method_name)

        def env_is_wrapped(self, wrapper_class: type, indices: Any = None) -> list[bool]:
            return [False] * self.num_envs

    return Feed


def _row(observation: Any, i: int) -> Any:
    if isinstance(observation, dict):
        return {k: np.array(v[i]) for k, v in observation.items()}
    return np.array(observation[i])


def read_observation_path(metadata: dict[str, Any], name: str) -> tuple[list[dict[str, Any]], Any]:
    """Return a model's recorded wrappers and the env's observation space (or ``None``).

    Without ``observation_wrappers`` (models saved before they were recorded, or trained on
    the env's observations as they are): no wrappers but the normalisation, applied first.

    Raises
    ------
    ValueError
        For entries that are not valid (naming the model), or wrappers that change the
        observation without the env's space they start from.
    """
    from radial_ibvs_agents.learned.files.model_files import space_from_json

    where = f"model {name!r}: metadata.json"
    wrappers = check_wrappers(metadata.get("observation_wrappers", []), where)
    described = metadata.get("env_observation_space")
    reshaped = any(w["name"] != "normalize" for w in wrappers)
    if reshaped and described is None:
        raise ValueError(f"{where}: observation_wrappers {wrappers!r:.120} need its space")
    if described is None:
        return wrappers, None
    return wrappers, space_from_json(described, f"{where}: env_observation_space")


class ReplayState:
    """A replayed policy's state: the wrappers' (stacked frames) and the policy's own (an LSTM's).

    Parameters
    ----------
    replay
        The batch's :class:`ObservationReplay`.
    inner
        The SB3 policy's state (``None`` for a feed-forward policy).
    """

    def __init__(self, replay: ObservationReplay, inner: Any) -> None:
        self.replay = replay
        self.inner = inner


def predict_replayed(
    learned: Any,
    observation: Any,
    state: Any,
    episode_start: np.ndarray | None,
    deterministic: bool,
) -> tuple[np.ndarray, ReplayState]:
    """``predict`` of a model that saw the env through a frame stack or channels-first images.

    Called by :class:`~radial_ibvs_agents.learned.files.loading.LearnedPolicy`. The observations
    (one robot's, or a batch) pass through the recorded wrappers, then SB3's ``predict`` of the
    policy. The returned state carries the stacked frames: pass it back
    with ``episode_start`` true where an episode begins (``state=None`` starts every robot).
    """
    space = learned.env_space
    single = _unbatched(observation, space)
    batch = _batched(observation) if single else observation
    n = _first(batch).shape[0]
    starts = np.ones(n, dtype=bool)
    if episode_start is not None and state is not None:
        starts = np.broadcast_to(np.asarray(episode_start, dtype=bool).reshape(-1), n).copy()
    if not isinstance(state, ReplayState) or state.replay.n != n:
        replay = ObservationReplay(
            learned.wrappers, space, learned.model.action_space, n, learned._normalise
        )
        state, starts = ReplayState(replay, None), np.ones(n, dtype=bool)
    seen = state.replay(batch, starts)
    action, inner = learned.model.predict(seen, state.inner, starts, deterministic)
    action = np.asarray(action, dtype=np.float32)
    return (action[0] if single else action), ReplayState(state.replay, inner)


def _first(observation: Any) -> np.ndarray:
    if isinstance(observation, dict):
        return np.asarray(next(iter(observation.values())))
    return np.asarray(observation)


def _unbatched(observation: Any, space: Any) -> bool:
    """Whether ``observation`` is one robot's (the env space's own shape)."""
    spaces = getattr(space, "spaces", None)
    if isinstance(spaces, dict):
        key = next(iter(spaces))
        return np.ndim(observation[key]) == len(spaces[key].shape)
    return np.ndim(observation) == len(space.shape)


def _batched(observation: Any) -> Any:
    if isinstance(observation, dict):
        return {k: np.asarray(v)[None] for k, v in observation.items()}
    return np.asarray(observation)[None]
