"""Landmark slots: one observation space for every scene of at most ``M`` landmarks.

:class:`Slots` pads an observation of a scene's ``N`` landmarks to ``M`` slots (the envs'
``max_landmarks``) and says where each landmark and pair lies. Its own module, below both the
config (which makes it) and the observation (which pads with it).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.limits import MAX_LANDMARKS

__all__ = ["Slots"]


class Slots:
    """A fixed number of landmark slots: pads observations of ``N <= M`` landmarks to ``M``.

    Parameters
    ----------
    n
        The scene's landmarks ``N``.
    m
        The slots ``M`` (>= ``N``).
    """

    #: the keys with one entry per landmark, and how many values per entry
    PER_LANDMARK: Mapping[str, int] = {
        "points": 2,
        "goal_points": 2,
        "visible": 1,
        "goal_depths": 1,
        "depths": 1,
    }

    def __init__(self, n: int, m: int) -> None:
        if not (2 <= n <= m):
            raise ValueError(f"max_landmarks must be >= the scene's {n} landmarks, got {m!r}")
        if m > MAX_LANDMARKS:
            raise ValueError(
                f"max_landmarks must be at most MAX_LANDMARKS = {MAX_LANDMARKS}, got {m}"
            )
        self.n, self.m = int(n), int(m)
        i, j = np.triu_indices(n, 1)
        # the position of pair (i, j) among the M slots' pairs, in row-major order
        self.pair_slots = (i * (2 * m - i - 1)) // 2 + (j - i - 1)
        self.mask = np.zeros(m, dtype=np.float32)
        self.mask[:n] = 1.0

    def pair_index(self, order: NDArray[np.intp]) -> NDArray[np.intp]:
        """Return where each landmark pair ``(i, j)``, ``i < j``, lies among the slots' pairs.

        Parameters
        ----------
        order
            ``(..., N)`` the slot of each landmark (distinct, in ``0..M-1``).

        Returns
        -------
        ``(..., N (N - 1) / 2)`` indices into the ``M (M - 1) / 2`` pairs, in row-major order
        of the slots (a pair is unordered: ``c_ij`` is symmetric).
        """
        i, j = np.triu_indices(self.n, 1)
        a = np.minimum(order[..., i], order[..., j])
        b = np.maximum(order[..., i], order[..., j])
        return (a * (2 * self.m - a - 1)) // 2 + (b - a - 1)

    def draw_order(self, rng: np.random.Generator) -> NDArray[np.intp]:
        """Draw the slots of an episode's landmarks: ``(N,)`` distinct slots in ``0..M-1``."""
        return rng.permutation(self.m)[: self.n].astype(np.intp)

    def pad(
        self,
        obs: dict[str, NDArray[Any]],
        order: NDArray[np.intp] | None = None,
        present: NDArray[np.bool_] | None = None,
    ) -> dict[str, NDArray[Any]]:
        """Return ``obs`` with its landmark axes padded to ``M`` and ``landmark_mask`` added.

        Parameters
        ----------
        obs
            The observation of ``N`` landmarks, leading dimensions ``(...)``.
        order
            ``None``: landmark ``n`` in slot ``n``. Else ``(N,)`` or ``(..., N)`` the slot of
            each landmark (:meth:`draw_order`; one row per leading index).
        present
            ``None``: every landmark of the scene is in ``landmark_mask``. Else ``(N,)`` or
            ``(..., N)``: which landmarks the episode has (a drawn landmark count); the absent
            ones' slots are 0 in ``landmark_mask``, as padding.
        """
        lead = obs["visible"].shape[:-1]
        if order is not None:
            order = np.broadcast_to(np.asarray(order, dtype=np.intp), (*lead, self.n))
        out: dict[str, NDArray[Any]] = {}
        for key, value in obs.items():
            width = self.PER_LANDMARK.get(key)
            if width is not None:
                padded = np.zeros((*value.shape[:-1], width * self.m), dtype=value.dtype)
                if order is None:
                    padded[..., : width * self.n] = value
                else:
                    columns = order[..., :, None] * width + np.arange(width)
                    np.put_along_axis(padded, columns.reshape(*lead, -1), value, axis=-1)
                out[key] = padded
            elif key == "c_error":
                pairs = self.m * (self.m - 1) // 2
                padded = np.zeros((*value.shape[:-1], pairs), dtype=value.dtype)
                if order is None:
                    padded[..., self.pair_slots] = value
                else:
                    np.put_along_axis(padded, self.pair_index(order), value, axis=-1)
                out[key] = padded
            else:
                out[key] = value
        if order is None:
            out["landmark_mask"] = np.broadcast_to(self.mask, (*lead, self.m)).copy()
        else:
            mask = np.zeros((*lead, self.m), dtype=np.float32)
            np.put_along_axis(mask, order, 1.0, axis=-1)
            out["landmark_mask"] = mask
        if present is not None:
            has = np.broadcast_to(np.asarray(present, dtype=np.float32), (*lead, self.n))
            slots = np.broadcast_to(np.arange(self.n), (*lead, self.n)) if order is None else order
            in_slot = np.zeros((*lead, self.m), dtype=np.float32)
            np.put_along_axis(in_slot, slots, has, axis=-1)
            out["landmark_mask"] *= in_slot
        return out
