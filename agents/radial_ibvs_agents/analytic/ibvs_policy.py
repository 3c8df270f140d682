"""The paper's IBVS and its variants as policies with stable-baselines3's ``predict``.

Four variants share one interface (names as in the CLI):

- ``ibvs`` (``variant="paper"``): Section 3.3 as the paper does it: the goal interaction
  matrix ``L*_c`` and its pseudo-inverse computed once per goal, the velocity ``v*`` of the goal
  camera, its rotation into the current frame by ``gamma`` (eq. 30, 36-37), eq. (38).
- ``ibvs-no-frame-change``: the same without the rotation by ``gamma`` (``v = -v*``).
- ``ibvs-current``: classic IBVS, the interaction matrix of ``(c_ij, alpha_m)`` at the current
  pose with the true current depths, pseudo-inverted every step.
- ``ibvs-mean``: the mean of the current and goal matrices (Malis), pseudo-inverted every step.

The paper's variants need the goal depths ``d*`` in the observation (``gym.make(...,
goal_depths=True)``); the classic ones also the true current depths (``privileged=True``).
:attr:`IBVSPolicy.env_kwargs` says which, and the benchmark makes the env accordingly.

Behaviour at the edges (tested): only landmarks visible both now and in the goal image are
used; with fewer than 3 of them the command is zero (the robot stops: nothing sensible can be
estimated). The command is zero once the feature error maps to an estimated distance below
``stop_radius`` and a rotation below ``stop_heading`` (the stop rule); within ``rotate_radius``
the robot makes a final approach, turning to the goal heading (eq. 38 is singular at
``r = 0``). Heading errors near ``+-pi`` are wrapped, so ``gamma`` stays in ``[-pi, pi)``.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_agents.analytic.ibvs_maths import GoalModel, ibvs_twist, park_command
from radial_ibvs_agents.analytic.ibvs_maths_batch import (
    GoalCache,
    ibvs_twist_batch,
    park_command_batch,
)
from radial_ibvs_gym.features import L_alpha_m, L_cij, alpha_m, c_ij
from radial_ibvs_gym.geometry import wrap_angle_scalar
from radial_ibvs_gym.physics import RobotConfig

__all__ = ["VARIANTS", "IBVSPolicy"]

VARIANTS = ("paper", "no-frame-change", "current", "mean")
Variant = Literal["paper", "no-frame-change", "current", "mean"]
_CACHE_SIZE = 64


class IBVSPolicy:
    """The paper's image-based visual servoing, or one of its variants, as a policy.

    Parameters
    ----------
    variant
        ``"paper"`` (default), ``"no-frame-change"``, ``"current"`` or ``"mean"`` (module
        docstring).
    lam
        The IBVS gain ``lambda``, 1/s (the paper's ``v_l / r``).
    k1, k2
        Gains of the smooth control law, eq. (38) (the paper's simulations: 4 and 12).
    robot
        The robot: speed limits and the action scale ``(v / v_max, omega / omega_max)``.
        Default: the Pioneer-like :class:`~radial_ibvs_gym.physics.RobotConfig`.
    stop_radius, stop_heading
        Stop rule: zero command when the estimated distance to the goal (metres) and the
        estimated rotation (radians) are both below these.
    rotate_radius
        Within this estimated distance (metres), the final approach: drive the forward part of ``v``
        and turn to the goal heading (``omega = lam * gamma``) instead of following eq. (38), which
        is singular at ``r = 0`` (:func:`radial_ibvs_agents.analytic.ibvs_maths.park_command`); 0
        never does.
    compensation
        Sign of eq. (30)'s compensation terms: ``"derived"`` (correct) or ``"printed"`` (the
        paper's misprint, for comparison only).
    allow_backward
        Drive backwards when the goal is behind the robot (nav2's graceful controller's
        ``allow_backward``; :func:`radial_ibvs_agents.analytic.ibvs_maths.robot_command`). The
        paper's law drives forwards only (the default).

    Examples
    --------
    >>> import gymnasium as gym, radial_ibvs_gym
    >>> policy = IBVSPolicy()
    >>> env = gym.make("RadialIBVS/Parking-v0", task=1, **policy.env_kwargs)
    >>> obs, info = env.reset(seed=0)
    >>> action, _ = policy.predict(obs)
    """

    #: how it runs in a batch of episodes (:mod:`radial_ibvs_agents.rollouts`): one ``predict`` for
    #: every robot, each robot's action as alone
    batch_mode = "batch"

    def __init__(
        self,
        variant: Variant = "paper",
        lam: float = 0.5,
        k1: float = 4.0,
        k2: float = 12.0,
        robot: RobotConfig | None = None,
        stop_radius: float = 0.002,
        stop_heading: float = math.radians(0.1),
        rotate_radius: float = 0.02,
        compensation: Literal["derived", "printed"] = "derived",
        allow_backward: bool = False,
    ) -> None:
        if variant not in VARIANTS:
            raise ValueError(f"unknown IBVS variant {variant!r}; valid: {list(VARIANTS)}")
        if compensation not in ("derived", "printed"):
            raise ValueError(f"compensation must be 'derived' or 'printed', got {compensation!r}")
        for name, value in (("lam", lam), ("k1", k1), ("k2", k2)):
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"{name} must be finite and positive, got {value!r}")
        for name, value in (
            ("stop_radius", stop_radius),
            ("stop_heading", stop_heading),
            ("rotate_radius", rotate_radius),
        ):
            if not (math.isfinite(value) and value >= 0):
                raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
        self.variant: Variant = variant
        self.lam, self.k1, self.k2 = float(lam), float(k1), float(k2)
        self.robot = robot or RobotConfig()
        self.stop_radius, self.stop_heading = float(stop_radius), float(stop_heading)
        self.rotate_radius = float(rotate_radius)
        self.compensation: Literal["derived", "printed"] = compensation
        self.allow_backward = bool(allow_backward)
        self._goal_cache: OrderedDict[bytes, GoalModel | None] = OrderedDict()
        self._cache_limit = _CACHE_SIZE  # a batch's goals all fit (twice the batch)
        #: the goal terms of the last batch (a residual env steps the same goals all episode)
        self._batch_goals = GoalCache()

    @property
    def env_kwargs(self) -> dict[str, bool]:
        """What ``gym.make`` must add to the observation for this variant."""
        if self.variant in ("current", "mean"):
            return {"goal_depths": True, "privileged": True}
        return {"goal_depths": True}

    def __repr__(self) -> str:
        backward = ", allow_backward=True" if self.allow_backward else ""
        return (
            f"IBVSPolicy(variant={self.variant!r}, lam={self.lam}, k1={self.k1}, k2={self.k2}"
            f"{backward})"
        )

    # --- SB3 interface ---------------------------------------------------------------------------
    def predict(
        self,
        observation: dict[str, np.ndarray],
        state: Any = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, Any]:
        """Action(s) for one observation or a batch, as stable-baselines3's ``predict``.

        Parameters
        ----------
        observation
            The env's ``Dict`` observation with ``points``, ``goal_points``, ``visible`` and
            ``goal_depths`` (plus ``depths`` for the classic variants), unbatched (``points``
            of shape ``(2N,)``) or batched (``(B, 2N)``).
        state, episode_start, deterministic
            Unused (the policy is stateless and deterministic); kept for the interface.

        Returns
        -------
        tuple
            ``(action, state)``: ``action`` ``(2,)`` or ``(B, 2)`` float32 in ``[-1, 1]``.

        Raises
        ------
        KeyError
            If the observation lacks a key the variant needs (the message says which
            ``gym.make`` argument adds it).
        """
        for key in ("points", "goal_points", "visible", "goal_depths"):
            if key not in observation:
                raise KeyError(
                    f"IBVSPolicy({self.variant!r}) needs observation[{key!r}]: make the env "
                    f"with {self.env_kwargs}"
                )
        if self.variant in ("current", "mean") and "depths" not in observation:
            raise KeyError(
                f"IBVSPolicy({self.variant!r}) needs the true current depths: make the env with "
                f"{self.env_kwargs}"
            )
        points = np.asarray(observation["points"], dtype=np.float64)
        batched = points.ndim == 2
        if batched and self.variant in ("paper", "no-frame-change"):
            return self._predict_batch(observation), state
        if batched:
            return self._predict_classic_batch(observation), state
        rows = {
            k: np.asarray(v).reshape(len(points) if batched else 1, -1)
            for k, v in observation.items()
        }
        actions = np.array(
            [self._act({k: v[i] for k, v in rows.items()}) for i in range(len(rows["points"]))],
            dtype=np.float32,
        ).reshape(-1, 2)
        return (actions if batched else actions[0]), state

    def _predict_batch(self, obs: dict[str, np.ndarray]) -> np.ndarray:
        """Act for a batch in one vectorised pass (``analytic.ibvs_maths_batch``)."""
        goal = self._batch_goals.terms(obs["goal_points"], obs["goal_depths"])
        v, gamma, _ = ibvs_twist_batch(
            obs["points"], obs["goal_points"], obs["goal_depths"], obs["visible"],
            self.lam, self.compensation, frame_change=self.variant == "paper", goal=goal,
        )  # fmt: skip
        v_max, w_max = self.robot.max_linear_speed, self.robot.max_angular_speed
        v_l, omega = park_command_batch(
            v, gamma, self.lam, self.k1, self.k2, v_max, w_max,
            self.stop_radius, self.stop_heading, self.rotate_radius, self.allow_backward,
        )  # fmt: skip
        return np.stack([v_l / v_max, omega / w_max], axis=-1).astype(np.float32)

    def _predict_classic_batch(self, obs: dict[str, Any]) -> NDArray[np.float32]:
        """Act for a batch of the classic variants, each robot's action as alone, bit for bit.

        Robots with the same number of landmarks in view share array shapes; each such group
        goes through the interaction matrices and a stacked pseudo-inverse at once (numpy
        computes every matrix of a stack as it computes one alone). The goal models come from
        the per-goal cache, sized to hold the batch's goals.
        """
        b = len(obs["points"])
        self._cache_limit = max(_CACHE_SIZE, 2 * b)
        x_now = np.asarray(obs["points"], dtype=np.float64).reshape(b, -1, 2)
        x_goal = np.asarray(obs["goal_points"], dtype=np.float64).reshape(b, -1, 2)
        mask = np.asarray(obs["visible"]).reshape(b, -1) > 0.5
        norm_now = np.hypot(x_now[..., 0], x_now[..., 1])
        norm_goal = np.hypot(x_goal[..., 0], x_goal[..., 1])
        mask &= (norm_now > 0.5) & (norm_goal > 0.5)
        d_goal = np.asarray(obs["goal_depths"], dtype=np.float64).reshape(b, -1)
        depths = np.asarray(obs["depths"], dtype=np.float64).reshape(b, -1)
        groups: dict[int, list[tuple[int, GoalModel]]] = {}
        for i in range(b):
            m = mask[i]
            if m.sum() < 3:
                continue
            goal = self._goal_model(x_goal[i, m] / norm_goal[i, m, None], d_goal[i, m], m)
            if goal is not None:
                groups.setdefault(int(m.sum()), []).append((i, goal))
        actions = np.zeros((b, 2), dtype=np.float32)
        for members in groups.values():
            rows = [i for i, _ in members]
            m = mask[rows]
            now = (x_now[rows][m] / norm_now[rows][m][:, None]).reshape(len(rows), -1, 2)
            v, gamma = self._classic_twist_batch(
                now, depths[rows][m].reshape(len(rows), -1), [g for _, g in members]
            )
            v_max, w_max = self.robot.max_linear_speed, self.robot.max_angular_speed
            v_l, omega = park_command_batch(
                v, gamma, self.lam, self.k1, self.k2, v_max, w_max,
                self.stop_radius, self.stop_heading, self.rotate_radius, self.allow_backward,
            )  # fmt: skip
            actions[rows] = np.stack([v_l / v_max, omega / w_max], axis=-1)
        return actions

    def _classic_twist_batch(
        self, x_now: NDArray[np.float64], depths: NDArray[np.float64], goals: list[GoalModel]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Return :meth:`_classic_twist` of ``G`` robots, ``k`` landmarks: ``(G, 2)``, ``(G,)``."""
        weights = np.stack([g.weights for g in goals])
        c_goal = np.stack([g.c_goal for g in goals])
        z = np.zeros_like(depths)
        n, m = len(goals), c_goal.shape[1]
        L = np.empty((n, m + 1, 3))
        L[:, :-1, :2] = L_cij(x_now, depths, z)[..., :2]
        L[:, :-1, 2] = 0.0  # c_ij is invariant to rotations about the axis
        L[:, -1] = L_alpha_m(x_now, depths, z, weights)[:, [0, 1, 5]]
        if self.variant == "mean":
            L_goal = np.zeros_like(L)
            L_goal[:, :-1, :2] = np.stack([g.L_c_v for g in goals])
            L_goal[:, -1] = [(*g.L_alpha_m_v, -1.0) for g in goals]
            L = 0.5 * (L + L_goal)
        error = np.empty((n, m + 1))
        error[:, :-1] = c_ij(x_now) - c_goal
        error[:, -1] = [wrap_angle_scalar(float(a)) for a in alpha_m(x_now, weights)]
        pinv = np.linalg.pinv(L)
        u = np.stack([-self.lam * (pinv[k] @ error[k]) for k in range(n)])
        return u[:, :2], u[:, 2] / self.lam

    # --- one observation -------------------------------------------------------------------------
    def _act(self, obs: dict[str, np.ndarray]) -> tuple[float, float]:
        estimate = self.twist(obs)
        if estimate is None:
            return 0.0, 0.0
        return self._command(*estimate)

    def twist(self, observation: dict[str, np.ndarray]) -> tuple[NDArray[np.float64], float] | None:
        """Estimate the camera velocity and the rotation to the goal from one observation.

        Parameters
        ----------
        observation
            One (unbatched) observation, as for :meth:`predict`.

        Returns
        -------
        tuple or None
            ``(v, gamma)``: ``v`` ``(2,)`` the camera velocity ``(v_x, v_y)`` in the current
            frame (m/s; ``v / lam`` estimates the goal position, metres) and ``gamma`` the
            estimated rotation to the goal orientation (radians); ``None`` when fewer than 3
            landmarks are visible both now and in the goal image, or the goal image is
            degenerate.
        """
        obs = observation
        x_now = np.asarray(obs["points"], dtype=np.float64).reshape(-1, 2)
        x_goal = np.asarray(obs["goal_points"], dtype=np.float64).reshape(-1, 2)
        mask = np.asarray(obs["visible"]) > 0.5
        norm_now = np.hypot(x_now[:, 0], x_now[:, 1])
        norm_goal = np.hypot(x_goal[:, 0], x_goal[:, 1])
        mask &= (norm_now > 0.5) & (norm_goal > 0.5)  # hidden at the goal: zeros
        if mask.sum() < 3:
            return None
        x_now = x_now[mask] / norm_now[mask, None]  # renormalise: the observation is float32
        x_goal = x_goal[mask] / norm_goal[mask, None]
        d_goal = np.asarray(obs["goal_depths"], dtype=np.float64)[mask]
        goal = self._goal_model(x_goal, d_goal, mask)
        if goal is None:
            return None
        if self.variant in ("paper", "no-frame-change"):
            v, _, gamma = ibvs_twist(x_now, goal, self.lam, self.compensation)
            if self.variant == "no-frame-change":  # v = -v*, not rotated into the current frame
                v = self.lam * (goal.L_c_pinv @ (goal.c_goal - c_ij(x_now)))
            return v, gamma
        depths = np.asarray(obs["depths"], dtype=np.float64)[mask]
        return self._classic_twist(x_now, depths, goal)

    def _goal_model(
        self, x_goal: NDArray[np.float64], d_goal: NDArray[np.float64], mask: NDArray[np.bool_]
    ) -> GoalModel | None:
        """Build the goal model for these goal points, depths and mask (cached: once per goal)."""
        key = x_goal.tobytes() + d_goal.tobytes() + mask.tobytes()
        if key in self._goal_cache:
            self._goal_cache.move_to_end(key)
            return self._goal_cache[key]
        try:
            model: GoalModel | None = GoalModel.from_goal(x_goal, d_goal)
        except ValueError:  # degenerate goal image (points collinear with the axis)
            model = None
        self._goal_cache[key] = model
        if len(self._goal_cache) > self._cache_limit:
            self._goal_cache.popitem(last=False)
        return model

    def _classic_twist(
        self, x_now: NDArray[np.float64], depths: NDArray[np.float64], goal: GoalModel
    ) -> tuple[NDArray[np.float64], float]:
        """Camera velocity ``(v_x, v_y)`` and rotation ``gamma`` of the classic variants.

        The task function ``e = (c - c*, alpha_m - alpha*_m)`` with ``de/dt = L u`` for the
        current camera twist ``u = (v_x, v_y, omega_z)``; ``u = -lam pinv(L) e``.
        """
        z = np.zeros_like(depths)
        L = np.empty((len(goal.c_goal) + 1, 3))
        L[:-1, :2] = L_cij(x_now, depths, z)[:, :2]
        L[:-1, 2] = 0.0  # c_ij is invariant to rotations about the axis
        L[-1] = L_alpha_m(x_now, depths, z, goal.weights)[[0, 1, 5]]
        if self.variant == "mean":
            L_goal = np.zeros_like(L)
            L_goal[:-1, :2] = goal.L_c_v
            L_goal[-1] = (*goal.L_alpha_m_v, -1.0)
            L = 0.5 * (L + L_goal)
        error = np.empty(len(goal.c_goal) + 1)
        error[:-1] = c_ij(x_now) - goal.c_goal
        error[-1] = wrap_angle_scalar(float(alpha_m(x_now, goal.weights)))  # alpha*_m = 0
        u = -self.lam * (np.linalg.pinv(L) @ error)
        return u[:2], float(u[2]) / self.lam

    def _command(self, v: NDArray[np.float64], gamma: float) -> tuple[float, float]:
        """Eq. (38) with the stop rule and the final rotation, scaled to the action range."""
        v_max, w_max = self.robot.max_linear_speed, self.robot.max_angular_speed
        v_l, omega = park_command(
            v, gamma, self.lam, self.k1, self.k2, v_max, w_max,
            self.stop_radius, self.stop_heading, self.rotate_radius, self.allow_backward,
        )  # fmt: skip
        return v_l / v_max, omega / w_max
