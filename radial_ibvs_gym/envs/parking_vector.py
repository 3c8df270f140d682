"""Native vector envs: ``N`` robots stepped in one batched call (``gym.make_vec``).

``gym.make_vec("RadialIBVS/Parking-v0", num_envs=N, vectorization_mode="vector_entry_point")``
(and the same for ``ParkingGoal-v1``) builds a :class:`ParkingVectorEnv`: one
``gymnasium.vector.VectorEnv`` that steps all ``N`` robots with batched numpy (the
:mod:`~radial_ibvs_gym.physics.fleet` physics, the observation, visibility, reward terms,
termination and truncation of :mod:`~radial_ibvs_gym.envs.observation` and
:mod:`~radial_ibvs_gym.envs.rules`, the code the scalar envs run). It takes the scalar env's
keyword arguments, validated into the same :class:`~radial_ibvs_gym.envs.config.ParkingConfig`,
and gives the same numbers as ``gym.make_vec(..., vectorization_mode="sync")`` on the same
seeds and actions.

One class of about 530 lines: its reset, its step with its three autoreset modes, its observation
and its info share the step state it holds, so they stay together. The episodes' ``(N, ...)``
arrays are in :class:`~radial_ibvs_gym.envs.episode_batch.EpisodeBatch`, the info helpers in
:mod:`~radial_ibvs_gym.envs.vector_info`, the goal-conditioned variant in
:mod:`~radial_ibvs_gym.envs.parking_goal`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector import VectorEnv
from gymnasium.vector.utils import batch_space
from numpy.typing import NDArray

from radial_ibvs_gym.envs import observation as seen
from radial_ibvs_gym.envs import rules
from radial_ibvs_gym.envs.autoreset import AutoresetMode
from radial_ibvs_gym.envs.camera_rows import CameraRows
from radial_ibvs_gym.envs.config import ParkingConfig
from radial_ibvs_gym.envs.detectors import DetectorRows
from radial_ibvs_gym.envs.episode_batch import EpisodeBatch
from radial_ibvs_gym.envs.episodes import EpisodeSetup, EpisodeSource
from radial_ibvs_gym.envs.vector_info import masked, put, select, spread
from radial_ibvs_gym.geometry import world_to_camera
from radial_ibvs_gym.limits import MAX_NUM_ENVS
from radial_ibvs_gym.physics.fleet import make_fleet
from radial_ibvs_gym.registration import MAX_EPISODE_STEPS

__all__ = ["ParkingVectorEnv"]

#: accepted spellings: Gymnasium's values (``"NextStep"``) and snake case (``"next_step"``)
_MODES = {k: m for m in AutoresetMode for k in (m.value, m.name.lower())}


class ParkingVectorEnv(VectorEnv):
    """``RadialIBVS/Parking-v0`` for ``num_envs`` robots at once, batched in numpy.

    ## Description
    The task, spaces, rewards and episode end of
    :class:`~radial_ibvs_gym.envs.parking.ParkingEnv`, for ``N`` robots. Each env has its own
    generator (``reset(seed=s)`` seeds env ``i`` with ``s + i``, as ``SyncVectorEnv``
    does), its own episode and, in ``random`` rooms, its own room and landmarks. The physics
    is batched: the ``kinematic`` unicycle in numpy, or all ``N`` pymunk robots in one
    ``pymunk.Space`` with their rooms placed apart (:mod:`radial_ibvs_gym.physics.fleet`).

    ## Spaces
    ``single_observation_space`` and ``single_action_space`` are the scalar env's;
    ``observation_space`` and ``action_space`` batch them (leading ``N``).

    ## Autoreset
    ``metadata["autoreset_mode"]`` is the ``autoreset_mode`` argument (Gymnasium's
    ``AutoresetMode``): ``"next_step"`` (default, as ``SyncVectorEnv``: the step after an
    episode ends resets that env, ignoring its action, with reward 0) or ``"same_step"`` (the
    env is reset in the step that ends it; ``info["final_obs"]`` and ``info["final_info"]``
    hold the last observation and info) or ``"disabled"`` (no env is reset by ``step``: an
    env that ended steps on if asked, its camera off: its observation stays that of the step
    that ended it, and an imperfect camera draws no more noise, until the caller resets it).
    ``reset(options={"reset_mask": mask})`` resets only the masked envs.

    ## Info
    A dict of arrays (Gymnasium's vector convention): every key of the scalar env's ``info``
    with a leading ``N``, and its ``_key`` mask of the envs that reported it.

    ## Arguments
    ``num_envs`` (>= 1), ``autoreset_mode``, ``max_episode_steps`` (the time limit; the
    registration's 600 by default), and every keyword argument of ``ParkingEnv``.
    ``render_mode`` is not batched: use ``vectorization_mode="sync"`` for it. With
    ``measurement="detected"`` each robot renders and detects its own frame, as the scalar
    env does (:class:`~radial_ibvs_gym.envs.detectors.DetectorRows`: the renderers shared; on
    the kinematic backend the same points bit for bit); the step around it is batched.

    ## Errors
    A NaN or infinite action raises ``ValueError`` naming the env; so does an action of the
    wrong shape, and ``num_envs < 1``.

    ```python
    import gymnasium as gym
    import radial_ibvs_gym  # registers the environments

    envs = gym.make_vec("RadialIBVS/Parking-v0", num_envs=256, physics="kinematic")
    obs, info = envs.reset(seed=0)
    obs, reward, terminated, truncated, info = envs.step(envs.action_space.sample())
    ```
    """

    metadata: dict[str, Any] = {"autoreset_mode": AutoresetMode.NEXT_STEP}  # noqa: RUF012
    #: the reward terms (``info["reward_<term>"]``), in the order they are summed
    reward_term_names: tuple[str, ...] = rules.REWARD_TERMS
    #: the arguments a subclass takes itself (named in the unknown-argument message)
    _own_arguments: tuple[str, ...] = ()

    def __init__(
        self,
        num_envs: int = 1,
        *,
        autoreset_mode: AutoresetMode | str = AutoresetMode.NEXT_STEP,
        max_episode_steps: int | None = MAX_EPISODE_STEPS,
        render_mode: str | None = None,
        **kwargs: Any,
    ) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, int | np.integer) or num_envs < 1:
            raise ValueError(f"num_envs must be an integer >= 1, got {num_envs!r}")
        if num_envs > MAX_NUM_ENVS:
            raise ValueError(
                f"num_envs must be at most MAX_NUM_ENVS = {MAX_NUM_ENVS}, got {num_envs}"
            )
        if render_mode is not None:
            raise ValueError(
                "the native vector env does not render; use gym.make_vec(..., "
                "vectorization_mode='sync', render_mode=...) or a scalar env"
            )
        if not isinstance(autoreset_mode, AutoresetMode):
            if not isinstance(autoreset_mode, str) or autoreset_mode not in _MODES:
                raise ValueError(
                    f"unknown autoreset_mode {autoreset_mode!r}; valid: {sorted(_MODES)}"
                )
            autoreset_mode = _MODES[autoreset_mode]
        if max_episode_steps is not None and max_episode_steps < 1:
            raise ValueError(f"max_episode_steps must be >= 1, got {max_episode_steps!r}")
        #: the validated arguments, as the scalar env holds them
        self.config = config = ParkingConfig.from_kwargs(
            extra=self._own_arguments, owner=f"{type(self).__name__}.__init__", **kwargs
        )
        self.episodes = EpisodeSource(config)
        self.num_envs = n = int(num_envs)
        self.autoreset_mode = autoreset_mode
        self.metadata = {**type(self).metadata, "autoreset_mode": autoreset_mode}
        self.render_mode = None
        self.max_episode_steps = max_episode_steps
        self.scenario = config.scenario
        self.single_observation_space = self._single_observation_space()
        self.single_action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, n)
        self.action_space = batch_space(self.single_action_space, n)
        scene = config.scenario.config
        room = scene.random_room
        max_room = (room.width[1], room.depth[1]) if room is not None else tuple(scene.room)
        extra = {"physics_dt": config.physics_dt, "max_room": max_room}
        self.fleet = make_fleet(config.physics, config.robot, n, obstacles=scene.obstacles, **extra)
        nl = self.scenario.n_landmarks
        self._rngs: list[np.random.Generator | None] = [None] * n
        #: each env's current episode, as (N, ...) arrays
        self.batch = EpisodeBatch(config, n)
        # the step state of each env
        self._points = np.zeros((n, nl, 2))
        self._visible = np.zeros((n, nl), dtype=bool)
        self._held = np.zeros(n, dtype=np.int64)  # steps in a row within the tolerances
        self._prev = (np.zeros(n), np.zeros(n))
        self._elapsed = np.zeros(n, dtype=np.int64)
        self._autoreset = np.zeros(n, dtype=bool)
        self._ended = np.zeros(n, dtype=bool)  # autoreset "disabled": ended, not reset since
        camera = self.scenario.config.camera
        self._drawn = camera.imperfection_ranges is not None  # imperfections drawn per episode
        self._fast = not (camera.imperfections.any or self._drawn)
        #: each robot's detected-points pipeline (``measurement="detected"``), else None
        self._detectors = DetectorRows(config, n) if config.measurement == "detected" else None
        #: the imperfect cameras as arrays, their noise drawn ahead (None: the ideal camera or
        #: detected points, whose noise the renderer draws)
        self._cameras = None if self._fast or self._detectors is not None else CameraRows(n, nl)

    def _single_observation_space(self) -> spaces.Space[Any]:
        """One robot's observation space (the scalar env's)."""
        return seen.observation_space(self.config)

    @property
    def start_reach(self) -> float:
        """``start_reach`` (a curriculum knob, as the scalar env's), shared by every env.

        Setting it takes effect at each env's next reset (autoresets included).
        """
        return self.episodes.start_reach

    @start_reach.setter
    def start_reach(self, value: float) -> None:
        self.episodes.start_reach = value

    # --- reset ---------------------------------------------------------------------------------
    def reset(
        self,
        *,
        seed: int | list[int | None] | None = None,
        options: dict[str, Any] | None = None,
    ) -> tuple[Any, dict[str, Any]]:
        """Reset every env (or those of ``options["reset_mask"]``); env ``i`` gets ``seed + i``."""
        n = self.num_envs
        if seed is None:
            seeds: list[int | None] = [None] * n
        elif isinstance(seed, int | np.integer):
            seeds = [int(seed) + i for i in range(n)]
        else:
            seeds = list(seed)
            if len(seeds) != n:
                raise ValueError(f"seed must be an int or {n} seeds, got {len(seeds)}")
        options = dict(options or {})
        mask = options.pop("reset_mask", None)
        if mask is None:
            mask = np.ones(n, dtype=bool)
        else:
            mask = np.asarray(mask)
            if mask.shape != (n,) or mask.dtype != np.bool_ or not mask.any():
                raise ValueError(
                    f"options['reset_mask'] must be a bool array of shape ({n},) with a True"
                )
        for i in np.flatnonzero(mask).tolist():
            if seeds[i] is not None or self._rngs[i] is None:
                if self._cameras is not None:  # noise drawn ahead from the replaced generator
                    self._cameras.noise.drop(i)
                self._rngs[i] = seeding.np_random(seeds[i])[0]
        indices = np.flatnonzero(mask)
        self._reset_envs(indices, options)
        self._autoreset[indices] = False
        self._ended[indices] = False
        info = self._reset_info(indices)
        return self._observation(), info

    def _reset_envs(self, indices: NDArray[np.intp], options: dict[str, Any]) -> None:
        """Draw new episodes for the envs ``indices`` (each with its own generator)."""
        t = self.config
        unknown = sorted(set(options) - {"start", "goal", "task"})
        if unknown:
            raise ValueError(f"unknown reset option(s) {unknown}; valid: ['goal', 'start', 'task']")
        task = options.get("task", t.task)
        rooms, starts, obstacles = [], [], []
        for i in indices.tolist():
            rng = self._rngs[i]
            assert rng is not None
            if self._cameras is not None:  # the generator as one noise draw a step leaves it
                self._cameras.noise.sync(i, rng)
            detector = None if self._detectors is None else self._detectors[i]
            setup = self.episodes.setup_episode(rng, task, options, detector)
            self.batch.put(i, setup)
            if self._cameras is not None:
                self._cameras.put(i, setup.cameras["current"])
            rooms.append(setup.episode.room)
            starts.append(setup.episode.start)
            obstacles.append(setup.episode.obstacles)
        self.fleet.reset(indices, np.array(rooms), np.array(starts), obstacles)
        poses = self.fleet.poses
        self._observe(poses, indices, first=True)
        goals = self.batch.goals[indices].T
        errors = rules.pose_errors(poses[indices].T, goals)
        self._prev[0][indices], self._prev[1][indices] = errors
        self._elapsed[indices] = 0
        self._held[indices] = 0

    # --- step ----------------------------------------------------------------------------------
    def step(
        self, actions: Any
    ) -> tuple[Any, NDArray[np.float64], NDArray[np.bool_], NDArray[np.bool_], dict[str, Any]]:
        """Step every env; see the class docstring for autoreset and the info arrays."""
        n, t = self.num_envs, self.config
        a = rules.real_actions(actions)
        if a.shape != (n, 2):
            raise ValueError(
                f"actions must have shape ({n}, 2) (one (v, omega) row per env), got {a.shape}"
            )
        finite = np.isfinite(a).all(axis=1)
        if not finite.all():
            i = int(np.argmin(finite))
            raise ValueError(f"env {i}: action must be {rules.ACTION_RULE}, got {a[i].tolist()}")
        if not any(self._rngs):
            raise RuntimeError("call reset() before step()")
        resetting = (
            self._autoreset.copy() if self.autoreset_mode == AutoresetMode.NEXT_STEP else None
        )
        command = rules.twist_commands(a, t)
        if resetting is not None and resetting.any():
            command[resetting] = 0.0  # ignored: these envs are reset below
        poses, collision = self.fleet.step(command, t.control_dt)
        if resetting is not None and resetting.any():
            # the envs being reset do not observe: an imperfect camera's noise would use up
            # their generators, which their reset must find as SyncVectorEnv leaves them
            self._observe(poses, np.flatnonzero(~resetting))
        elif self.autoreset_mode == AutoresetMode.DISABLED and self._ended.any():
            self._observe(poses, np.flatnonzero(~self._ended))  # the ended ones: camera off
        else:
            self._observe(poses, np.arange(n))
        now = rules.pose_errors(poses.T, self.batch.goals.T)
        n_visible = self._visible.sum(axis=1)
        success, lost, terminated, self._held = rules.episode_end(
            *now,
            n_visible,
            collision,
            success_position_m=t.success_position_m,
            success_heading_rad=t.success_heading_rad,
            min_visible=t.min_visible,
            terminate_on_collision=t.terminate_on_collision,
            held=self._held,
            hold_steps=t.hold_steps,
        )
        terms = self._reward_terms(self._prev, now, collision, lost, success)
        reward = sum(terms.values(), np.zeros(n))
        self._prev = now
        self._elapsed += 1
        truncated = (
            self._elapsed >= self.max_episode_steps
            if self.max_episode_steps is not None
            else np.zeros(n, dtype=bool)
        )
        info = self._info(poses, now, success, collision, n_visible, lost, self._held == 1)
        info |= masked(rules.reward_info(terms), np.ones(n, dtype=bool))
        self._add_detection(info, np.arange(n))
        obs = self._observation()
        if resetting is not None:
            if resetting.any():
                idx = np.flatnonzero(resetting)
                self._reset_envs(idx, {})
                reward[idx] = 0.0
                terminated[idx] = False
                truncated[idx] = False
                self._refresh(obs, idx)
                self._merge_reset_info(info, idx)
            self._autoreset = terminated | truncated
        elif self.autoreset_mode == AutoresetMode.DISABLED:
            self._ended |= terminated | truncated
        elif self.autoreset_mode == AutoresetMode.SAME_STEP:  # the envs that ended reset now
            ended = terminated | truncated
            if ended.any():
                idx = np.flatnonzero(ended)
                final_obs = np.full(n, None, dtype=object)
                for i in idx.tolist():
                    final_obs[i] = {k: v[i].copy() for k, v in obs.items()}
                final_info = select(info, ended)
                self._reset_envs(idx, {})
                self._refresh(obs, idx)
                self._merge_reset_info(info, idx)
                info["final_obs"], info["_final_obs"] = final_obs, ended.copy()
                info["final_info"], info["_final_info"] = final_info, ended.copy()
        return obs, reward, terminated, truncated, info

    def _reward_terms(
        self,
        previous: tuple[NDArray[np.float64], NDArray[np.float64]],
        now: tuple[NDArray[np.float64], NDArray[np.float64]],
        collision: NDArray[np.bool_],
        lost: NDArray[np.bool_],
        success: NDArray[np.bool_],
    ) -> dict[str, NDArray[np.float64]]:
        """Return the step's named reward terms ``(N,)`` each: the reward hook of both envs.

        :meth:`ParkingEnv._reward_terms <radial_ibvs_gym.envs.parking.ParkingEnv._reward_terms>`
        for ``N`` robots; ``ParkingGoal-v1`` overrides both with its goal reward.
        """
        return rules.reward_terms(previous, now, collision, lost, success, self.config.weights)

    def _images(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return the current and the goal image points, ``(N, L, 2)`` each (zeros where hidden)."""
        return self._points, self.batch.goal_points

    # --- observation and info ------------------------------------------------------------------
    def _observe(
        self, poses: NDArray[np.float64], indices: NDArray[np.intp], first: bool = False
    ) -> None:
        """Image points and visibility of the envs ``indices`` at their ``poses`` ``(N, 3)``.

        ``first``: the envs were just reset (detected points: their episode's first frame,
        measured by the reset).
        """
        batch = self.batch
        if self._detectors is not None:
            if len(indices):
                nl = self._points.shape[1]
                self._points[indices], self._visible[indices] = (
                    self._detectors.initial(indices, nl)
                    if first
                    else self._detectors.observe(indices, poses, self._rngs, nl)
                )
        elif self._fast:
            if len(indices) == self.num_envs:
                lo, hi = batch.bounds
                pts, vis = seen.radial_image(batch.landmarks_c, lo, hi, poses)
            else:
                pts, vis = seen.radial_image(
                    batch.landmarks_c[indices],
                    batch.bounds[0, indices],
                    batch.bounds[1, indices],
                    poses[indices],
                )
            self._points[indices], self._visible[indices] = pts, vis
        elif len(indices):  # a camera with imperfections: exact projection and noise, batched
            assert self._cameras is not None
            heights = batch.camera_heights[indices, None]  # (k, 1): each robot's height
            p_cam = world_to_camera(
                batch.landmarks_w[indices], poses[indices], heights, validate=False
            )
            points, visible = self._cameras.measure(indices, p_cam, self._rngs)
            present = batch.present[indices]
            if not present.all():  # a drawn landmark count: the absent are never visible
                visible &= present
                points[~visible] = 0.0
            self._points[indices], self._visible[indices] = points, visible
        if self.config.missed_detections is not None and self._detectors is None:
            for i in indices.tolist():
                missed = self._setup(i).missed
                if missed is not None:
                    self._points[i], self._visible[i] = missed.apply(
                        self._points[i], self._visible[i]
                    )
        if batch.features is not None:
            batch.features.update(indices, self._visible[indices] & batch.goal_visible[indices])

    def _setup(self, i: int) -> EpisodeSetup:
        """Return env ``i``'s episode (after its first reset)."""
        setup = self.batch.setups[i]
        assert setup is not None, "call reset() before step()"
        return setup

    def _observation(self, idx: Any = slice(None)) -> dict[str, NDArray[Any]]:
        """Return the observations of the envs ``idx`` (default: all)."""
        t, batch = self.config, self.batch
        points = self._points[idx]
        extra: dict[str, NDArray[Any]] = {}
        if batch.features is not None:
            c_err, a_err = batch.features.errors(points, idx)
            extra = {"c_error": c_err, "alpha_m_error": a_err}
        obs = seen.observation(
            points.reshape(len(points), -1),
            batch.goal_points[idx].reshape(len(points), -1),
            self._visible[idx],
            features=extra,
            goal_depths=batch.goal_depths[idx] if t.goal_depths else None,
            robot_pose=self.fleet.poses[idx] if t.privileged else None,
            goal_pose=batch.privileged_goals[idx] if t.privileged else None,
            landmarks=batch.landmarks_c[idx] if t.privileged else None,
            slots=t.slots,
            slot_order=batch.slot_orders[idx] if t.slot_order == "random" else None,
            present=None if batch.present.all() else batch.present[idx],
        )
        if t.privileged_map:
            setups = [self.batch.setups[i] for i in np.arange(self.num_envs)[idx].tolist()]
            maps = [s.map for s in setups if s is not None and s.map is not None]
            for key in ("room", "obstacles", "landmarks", "landmark_range"):
                obs[key] = np.stack([m[key] for m in maps])
        return obs

    def _refresh(self, obs: dict[str, NDArray[Any]], idx: NDArray[np.intp]) -> None:
        """Overwrite the rows ``idx`` of ``obs`` with those envs' current observations."""
        fresh = self._observation(idx)
        for key, value in obs.items():
            value[idx] = fresh[key]

    def _info(
        self,
        poses: NDArray[np.float64],
        errors: tuple[NDArray[np.float64], NDArray[np.float64]],
        success: NDArray[np.bool_],
        collision: NDArray[np.bool_],
        n_visible: NDArray[np.integer[Any]],
        lost: NDArray[np.bool_] | None = None,
        reached: NDArray[np.bool_] | None = None,
    ) -> dict[str, Any]:
        values = rules.info_values(
            poses,
            self.batch.goals,
            errors,
            success,
            collision,
            np.zeros(self.num_envs, bool) if lost is None else lost,
            n_visible,
            self.batch.tasks,
            self.batch.goal_depths,
            self._imperfections_info(slice(None)),
            reached=np.zeros(self.num_envs, bool) if reached is None else reached,
        )
        return masked(values, np.ones(self.num_envs, dtype=bool))

    def _imperfections_info(self, rows: Any) -> dict[str, Any] | None:
        """Return the drawn imperfections of the envs ``rows`` (``{key: (k,) array}``) or None."""
        return self.batch.imperfections_info(rows) if self._drawn else None

    def _reset_values(self, indices: NDArray[np.intp]) -> dict[str, Any]:
        """Return the reset ``info`` values of the envs ``indices`` (rows of each key)."""
        no = np.zeros(len(indices), dtype=bool)
        values = rules.info_values(
            self.fleet.poses[indices],
            self.batch.goals[indices],
            (self._prev[0][indices], self._prev[1][indices]),
            no,
            no,
            no,
            self._visible[indices].sum(axis=1),
            self.batch.tasks[indices],
            self.batch.goal_depths[indices],
            self._imperfections_info(indices),
        )
        zero = np.zeros(len(indices))
        return values | rules.reward_info({k: zero for k in self.reward_term_names})

    def _reset_info(self, indices: NDArray[np.intp]) -> dict[str, Any]:
        """Return the ``info`` of :meth:`reset`: the reset envs' rows, the others masked."""
        mask = np.zeros(self.num_envs, dtype=bool)
        mask[indices] = True
        info = spread(self._reset_values(indices), indices, mask)
        self._add_detection(info, indices)
        return info

    def _merge_reset_info(self, info: dict[str, Any], indices: NDArray[np.intp]) -> None:
        """Replace the entries of the envs just reset by their reset info (as SyncVectorEnv)."""
        put(info, self._reset_values(indices), indices)
        self._add_detection(info, indices)

    def _add_detection(self, info: dict[str, Any], indices: NDArray[np.intp]) -> None:
        """Write the envs ``indices``' ``info["detection"]`` (detected points), as SyncVectorEnv.

        Gymnasium's own :meth:`~gymnasium.vector.VectorEnv._add_info` builds the entry: the
        scalar env's dict (a status string, counts, the calibration found, the rejected blobs
        by reason), row by row, with the same arrays, types and masks as ``SyncVectorEnv``.
        """
        if self._detectors is not None:
            for i in indices.tolist():
                self._add_info(info, {"detection": self._detectors.info(i)}, i)

    def close_extras(self, **kwargs: Any) -> None:
        """Release the physics."""
        self.fleet = None  # type: ignore[assignment]
