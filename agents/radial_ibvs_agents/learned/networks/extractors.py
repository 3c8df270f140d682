"""Feature extractors for the learned policies (torch modules, no parameters of their own).

A network fed the raw image errors sees almost nothing near the goal: ``c*_ij - c_ij`` and
``alpha*_m - alpha_m`` shrink towards zero there, a few hundredths of their spread over an
episode, yet that is where parking needs centimetre precision. The paper's IBVS is precise
there because its law is proportional to the error whatever its size (eq. 30). To give a
network the same view, :class:`ErrorScaleExtractor` feeds each error vector ``e`` (a key of
``error_keys``, and its history ``KEY@-k``) as its direction and the logarithm of its size::

    e / (|e| + eps),   log(|e| + eps)

and each scalar error ``a`` as ``a`` and ``a / (|a| + eps)`` (a soft sign, sharp near zero).
With ``point_error`` it adds the image error ``x_n - x_n*`` of the landmarks seen now and in
the goal image, the same way: its direction is in the robot's frame, so near the goal it tells
which way to turn and drive whatever the distance (what the IBVS reads through its
interaction matrices). Every other key is flattened as stable-baselines3's
``CombinedExtractor`` does. The keys it reads raw (:func:`raw_keys`) should not be
normalised beforehand: they are on fixed scales already.
"""

from __future__ import annotations

import numpy as np
import torch
from gymnasium import spaces
from stable_baselines3.common.torch_layers import BaseFeaturesExtractor

from radial_ibvs_agents.learned.networks.pose_layer import POSE_FEATURES, goal_pose_features

__all__ = [
    "ERROR_KEYS",
    "LANDMARK_KEYS",
    "POINT_KEYS",
    "POSE_HISTORY_KEYS",
    "ErrorScaleExtractor",
    "GoalPoseExtractor",
    "LandmarkPoseExtractor",
    "LandmarkSetExtractor",
    "error_key_of",
    "raw_keys",
]

#: the observation keys treated as errors by default (the features observation)
ERROR_KEYS = ("c_error", "alpha_m_error")


#: the keys the image error is computed from
POINT_KEYS = ("points", "goal_points", "visible")


#: the keys whose past frames :class:`LandmarkPoseExtractor` solves (``pose_history``)
POSE_HISTORY_KEYS = ("points", "visible")


#: the keys :class:`LandmarkSetExtractor` builds its landmark tokens from
LANDMARK_KEYS = ("points", "goal_points", "visible", "goal_depths")


def raw_keys(
    error_keys: tuple[str, ...], point_error: bool, landmark_set: bool = False
) -> tuple[str, ...]:
    """Return the base keys the extractors read raw (not to be normalised)."""
    keys = (*error_keys, *(POINT_KEYS if point_error else ()))
    return (*keys, *(k for k in LANDMARK_KEYS if landmark_set and k not in keys))


def error_key_of(key: str, error_keys: tuple[str, ...]) -> str | None:
    """Return the error key that ``key`` is (``c_error``) or is the history of (``c_error@-1``)."""
    base = key.split("@", 1)[0]
    return base if base in error_keys else None


class ErrorScaleExtractor(BaseFeaturesExtractor):
    """Flatten a ``Dict`` observation, giving the error keys as direction and log-size.

    Parameters
    ----------
    observation_space
        The ``Dict`` observation space.
    error_keys
        The error keys (and their histories) to transform.
    eps
        The size below which an error counts as zero (its unit: the observation's).
    point_error
        Add the image error ``x_n - x_n*`` (needs ``points``, ``goal_points``, ``visible``).
    angle_keys
        Scalar error keys that are angles wrapped to ``(-pi, pi]`` (``alpha_m_error``): each
        value ``a`` is given as ``sin a``, ``cos a`` and the soft sign faded out towards
        ``pi``, ``sin a / (|sin a| + eps) (1 + cos a) / 2``, all continuous across the wrap
        (the plain soft sign jumps from +1 to -1 there, and a student facing away from the
        goal heading dithers between the two). Default: none (the plain treatment).
    """

    def __init__(
        self,
        observation_space: spaces.Dict,
        error_keys: tuple[str, ...] | list[str] = ERROR_KEYS,
        eps: float = 1e-3,
        point_error: bool = False,
        angle_keys: tuple[str, ...] | list[str] = (),
    ) -> None:
        self.error_keys = tuple(error_keys)
        self.eps = float(eps)
        self.point_error = bool(point_error)
        self.angle_keys = tuple(angle_keys)
        for key in self.angle_keys:
            space = observation_space.spaces.get(key)
            if key not in self.error_keys or space is None or int(np.prod(space.shape or ())) != 1:
                raise ValueError(
                    f"angle key {key!r} must be one of the scalar error keys {self.error_keys} "
                    "present in the observation"
                )
        size = 0
        if self.point_error:
            missing = sorted(set(POINT_KEYS) - set(observation_space.spaces))
            if missing:
                raise ValueError(f"point_error needs the observation keys {missing}")
            size += int(np.prod(observation_space.spaces["points"].shape or ())) + 1
        for key, space in observation_space.spaces.items():
            n = int(np.prod(space.shape or ()))
            if error_key_of(key, self.error_keys) is None:
                size += n
            elif error_key_of(key, self.angle_keys) is not None:
                size += 3
            else:
                size += n + 1 if n > 1 else 2
        super().__init__(observation_space, features_dim=size)
        # each key's treatment, decided once: raw, an error vector, an angle or a scalar error
        self._plan = []
        for key, space in observation_space.spaces.items():
            if error_key_of(key, self.error_keys) is None:
                kind = "raw"
            elif int(np.prod(space.shape or ())) > 1:
                kind = "vector"
            elif error_key_of(key, self.angle_keys) is not None:
                kind = "angle"
            else:
                kind = "scalar"
            self._plan.append((key, kind))

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """Return the ``(B, features_dim)`` features."""
        return self._features(observations, None)

    @staticmethod
    def _seen(observations: dict[str, torch.Tensor], visible: str = "visible") -> torch.Tensor:
        """Return ``(B, N)`` bools: the landmarks seen now and in the goal image."""
        goal = observations["goal_points"].float()
        goal = goal.reshape(goal.shape[0], -1, 2)
        # torch.linalg.vector_norm: what Tensor.norm calls, without its Python wrapper
        near = torch.linalg.vector_norm(goal, dim=2) > 0.5
        return near & (observations[visible].float() > 0.5)

    def _features(
        self, observations: dict[str, torch.Tensor], seen: torch.Tensor | None
    ) -> torch.Tensor:
        """Return the features, given :meth:`_seen` where a subclass computed it already."""
        parts: list[torch.Tensor] = []
        eps = self.eps
        if self.point_error:
            now = observations["points"].float().flatten(start_dim=1)
            goal = observations["goal_points"].float().flatten(start_dim=1)
            b = now.shape[0]
            seen = self._seen(observations) if seen is None else seen
            error = ((now - goal).reshape(b, -1, 2) * seen[..., None]).reshape(b, -1)
            size = torch.linalg.vector_norm(error, dim=1, keepdim=True) + eps
            parts += [error / size, torch.log(size)]
        for key, kind in self._plan:
            value = observations[key].float().flatten(start_dim=1)
            if kind == "raw":
                parts.append(value)
            elif kind == "vector":
                size = torch.linalg.vector_norm(value, dim=1, keepdim=True) + eps
                parts += [value / size, torch.log(size)]
            elif kind == "angle":
                sin, cos = torch.sin(value), torch.cos(value)
                parts += [sin, cos, sin / (sin.abs() + eps) * (1.0 + cos) / 2.0]
            else:
                parts += [value, value / (value.abs() + eps)]
        return torch.cat(parts, dim=1)

    def extra_repr(self) -> str:
        """Return the settings, for ``print(policy)``."""
        angles = f", angle_keys={self.angle_keys}" if self.angle_keys else ""
        return (
            f"error_keys={self.error_keys}, eps={self.eps}, point_error={self.point_error}{angles}"
        )


class LandmarkSetExtractor(ErrorScaleExtractor):
    """:class:`ErrorScaleExtractor`'s features, plus a learned encoding of the landmark set.

    An MLP fed the landmark slots one after the other must learn the same geometry once per
    slot, and the slots a room fills vary. Here every landmark seen now and in the goal image
    is a *token*, encoded by one shared network (``phi``, learned), and the tokens are pooled
    (masked mean and max), as in Deep Sets (Zaheer et al., 2017): the encoding is the same
    whichever slot a landmark occupies and however many there are. Each token holds what
    the landmark tells about the goal's pose in the robot frame (14 numbers):

    - the current and goal image points ``x_n``, ``x_n*`` and the goal depth ``d*``
      (metres) and ``1 / d*``;
    - its image error ``x_n - x_n*`` divided by the norm of all the landmarks' errors (a
      direction, which stays informative as the errors vanish near the goal);
    - the landmark's position in the goal frame, ``p = d* x_n*``, and its dot and cross
      products with ``x_n`` (the coefficients of the bearing constraint that ties ``x_n``
      to the goal's pose);
    - the cosine and sine of the angle from ``x_n*`` to ``x_n``.

    Nothing is solved: the pose is left for the network to infer. The pooled encoding and
    the share of slots seen are appended to :class:`ErrorScaleExtractor`'s features.

    Parameters
    ----------
    observation_space
        The ``Dict`` observation space (needs ``points``, ``goal_points``, ``visible`` and
        ``goal_depths``).
    error_keys, eps, point_error, angle_keys
        As :class:`ErrorScaleExtractor`.
    token_dim
        Width of ``phi``'s two layers.
    """

    TOKEN_INPUTS = 14

    def __init__(
        self,
        observation_space: spaces.Dict,
        error_keys: tuple[str, ...] | list[str] = ERROR_KEYS,
        eps: float = 1e-3,
        point_error: bool = True,
        token_dim: int = 64,
        angle_keys: tuple[str, ...] | list[str] = (),
    ) -> None:
        missing = sorted(set(LANDMARK_KEYS) - set(observation_space.spaces))
        if missing:
            raise ValueError(f"LandmarkSetExtractor needs the observation keys {missing}")
        if not (isinstance(token_dim, int) and token_dim > 0):
            raise ValueError(f"token_dim must be a positive integer, got {token_dim!r}")
        super().__init__(observation_space, error_keys, eps, point_error, angle_keys)
        base = self._features_dim
        self._features_dim = base + 2 * token_dim + 1
        self.token_dim = token_dim
        self.phi = torch.nn.Sequential(
            torch.nn.Linear(self.TOKEN_INPUTS, token_dim),
            torch.nn.ReLU(),
            torch.nn.Linear(token_dim, token_dim),
            torch.nn.ReLU(),
        )

    def tokens(self, observations: dict[str, torch.Tensor]) -> tuple[torch.Tensor, torch.Tensor]:
        """Return the tokens ``(B, N, 14)`` and the mask of landmarks seen ``(B, N)``."""
        return self._tokens(observations, self._seen(observations))

    def _tokens(
        self, observations: dict[str, torch.Tensor], seen: torch.Tensor
    ) -> tuple[torch.Tensor, torch.Tensor]:
        b = observations["points"].shape[0]
        now = observations["points"].float().reshape(b, -1, 2)
        goal = observations["goal_points"].float().reshape(b, -1, 2)
        depth = observations["goal_depths"].float().reshape(b, -1)
        mask = seen.float()
        mask3 = mask[..., None]
        error = (now - goal) * mask3
        size = torch.linalg.vector_norm(error.reshape(b, -1), dim=1)[:, None, None]
        depth3 = depth[..., None]
        p = depth3 * goal
        n0, n1 = now[..., :1], now[..., 1:]
        dot = (p * now).sum(dim=2, keepdim=True)
        cross = p[..., :1] * n1 - p[..., 1:] * n0
        cos = (goal * now).sum(dim=2, keepdim=True)
        sin = goal[..., :1] * n1 - goal[..., 1:] * n0
        inverse = torch.where(depth3 > 0, 1.0 / depth3.clamp_min(1e-3), 0.0)
        parts = [now, goal, depth3, inverse, error / (size + self.eps), p, dot, cross]
        token = torch.cat([*parts, cos, sin], dim=2)
        return token * mask3, mask

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """Return the ``(B, features_dim)`` features."""
        return self._set_features(observations, self._seen(observations))

    def _set_features(
        self, observations: dict[str, torch.Tensor], seen: torch.Tensor
    ) -> torch.Tensor:
        token, mask = self._tokens(observations, seen)
        encoded = self.phi(token) * mask[..., None]
        count = mask.sum(dim=1, keepdim=True)
        mean = encoded.sum(dim=1) / count.clamp_min(1.0)
        # encodings are >= 0 (ReLU), so masked slots at 0 never win the max
        peak = encoded.amax(dim=1)
        share = count / mask.shape[1]
        return torch.cat([self._features(observations, seen), mean, peak, share], dim=1)

    def extra_repr(self) -> str:
        """Return the settings, for ``print(policy)``."""
        return f"{super().extra_repr()}, token_dim={self.token_dim}"


class LandmarkPoseExtractor(LandmarkSetExtractor):
    """:class:`LandmarkSetExtractor`'s features, plus the goal's pose solved from the image.

    The landmark tokens hold the coefficients of each landmark's bearing constraint, but a pooled
    encoding leaves the network to solve the constraints jointly, and near the goal, where parking
    needs the last centimetre and degree, its estimate is coarsest. Here the constraints are solved
    in closed form (:func:`radial_ibvs_agents.learned.networks.pose_layer.solve_goal_pose`: a
    least-squares fit over every landmark seen in both images, no parameters) and the solved pose is
    appended as :func:`radial_ibvs_agents.learned.networks.pose_layer.goal_pose_features`: the
    goal's position in the robot's frame, the robot's in the goal's, the heading error, each also as
    a soft sign sharp within ``pose_eps`` metres, and a validity flag (three landmarks or more).
    Nothing decides the action but the network.

    Parameters
    ----------
    observation_space, error_keys, eps, point_error, token_dim, angle_keys
        As :class:`LandmarkSetExtractor`.
    pose_eps
        The soft signs' scale, metres (and the heading's, radians).
    pose_history
        Solve the pose in each past frame too (``points@-k`` and ``visible@-k``, ``k = 1,
        2, ...``, with the goal image of now), appending each frame's features, so the
        network can filter a noisy camera's poses. The past frames' keys must not be
        normalised (:func:`raw_keys` does not list them).
    """

    def __init__(
        self,
        observation_space: spaces.Dict,
        error_keys: tuple[str, ...] | list[str] = ERROR_KEYS,
        eps: float = 1e-3,
        point_error: bool = True,
        token_dim: int = 64,
        angle_keys: tuple[str, ...] | list[str] = (),
        pose_eps: float = 1e-3,
        pose_history: bool = False,
    ) -> None:
        if not (isinstance(pose_eps, (int, float)) and pose_eps > 0):
            raise ValueError(f"pose_eps must be a positive number, got {pose_eps!r}")
        super().__init__(observation_space, error_keys, eps, point_error, token_dim, angle_keys)
        self.pose_eps = float(pose_eps)
        self.pose_history = bool(pose_history)
        self._frames = [("points", "visible")]
        lag = 1
        while self.pose_history and f"points@-{lag}" in observation_space.spaces:
            self._frames.append((f"points@-{lag}", f"visible@-{lag}"))
            lag += 1
        missing = sorted({v for _, v in self._frames} - set(observation_space.spaces))
        if self.pose_history and (len(self._frames) == 1 or missing):
            raise ValueError(
                "pose_history needs the past frames' keys points@-1, visible@-1, ... in the "
                f"observation (missing: {missing or ['points@-1']})"
            )
        self._features_dim += POSE_FEATURES * len(self._frames)

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """Return the ``(B, features_dim)`` features."""
        b = observations["points"].shape[0]
        goal = observations["goal_points"].float().reshape(b, -1, 2)
        depth = observations["goal_depths"].float().reshape(b, -1)
        seen_now = self._seen(observations)
        poses = []
        for points, visible in self._frames:
            now = observations[points].float().reshape(b, -1, 2)
            seen = seen_now if visible == "visible" else self._seen(observations, visible)
            poses.append(goal_pose_features(now, goal, depth, seen.float(), self.pose_eps))
        return torch.cat([self._set_features(observations, seen_now), *poses], dim=1)

    def extra_repr(self) -> str:
        """Return the settings, for ``print(policy)``."""
        return f"{super().extra_repr()}, pose_eps={self.pose_eps}, pose_history={self.pose_history}"


class GoalPoseExtractor(LandmarkPoseExtractor):
    """:class:`LandmarkPoseExtractor` on ``ParkingGoal-v1``'s goal-conditioned observation (HER).

    ``ParkingGoal-v1`` made with ``goal_depths=True`` gives each goal as its image points and
    depths (``(3M,)``: ``achieved_goal`` the current image with the depths a goal image taken
    here would have, ``desired_goal`` the goal image with ``d*``) and the visibility in
    ``observation``. These are read as the student's keys (``points``, ``goal_points``,
    ``goal_depths``, ``visible``), so the goal's pose is solved from the bearings of whichever
    goal HER hands in, relabelled or not.

    Parameters
    ----------
    observation_space
        ``ParkingGoal-v1``'s ``Dict`` space, ``goal_depths=True``.
    token_dim, pose_eps
        As :class:`LandmarkPoseExtractor`.

    Raises
    ------
    ValueError
        If the goals do not carry depths (the env made without ``goal_depths=True``).
    """

    def __init__(
        self, observation_space: spaces.Dict, token_dim: int = 64, pose_eps: float = 1e-3
    ) -> None:
        keys = ("observation", "achieved_goal", "desired_goal")
        sizes = [
            int(np.prod(observation_space.spaces[k].shape or ()))
            for k in keys
            if k in observation_space.spaces
        ]
        if len(sizes) != 3 or sizes[0] % 3 or sizes[1] != sizes[0] or sizes[2] != sizes[0]:
            raise ValueError(
                "GoalPoseExtractor needs ParkingGoal-v1 made with goal_depths=True (goals of "
                f"3M values, the observation of 3M); got sizes {sizes} for {list(keys)}"
            )
        m = sizes[0] // 3
        inner = spaces.Dict(
            {
                "points": spaces.Box(-1.0, 1.0, (2 * m,), np.float32),
                "goal_points": spaces.Box(-1.0, 1.0, (2 * m,), np.float32),
                "visible": spaces.Box(0.0, 1.0, (m,), np.float32),
                "goal_depths": spaces.Box(0.0, 1e3, (m,), np.float32),
            }
        )
        super().__init__(inner, (), point_error=True, token_dim=token_dim, pose_eps=pose_eps)
        self.landmarks = m

    def forward(self, observations: dict[str, torch.Tensor]) -> torch.Tensor:
        """Return the ``(B, features_dim)`` features of the goal-conditioned observation."""
        m = self.landmarks
        achieved = observations["achieved_goal"].float()
        desired = observations["desired_goal"].float()
        mapped = {
            "points": achieved[:, : 2 * m],
            "goal_points": desired[:, : 2 * m],
            "visible": observations["observation"].float()[:, 2 * m :],
            "goal_depths": desired[:, 2 * m :],
        }
        return super().forward(mapped)
