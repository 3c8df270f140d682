"""Correspondence of detected beacons with the landmarks, frame after frame.

Method (documented in ``docs/pixels.md``):

1. **Labelling.** The first frame's blobs get the landmark identities of the nearest
   predicted positions (the operator's labelling in the paper, who also measured each beacon's
   goal depth). :func:`assign` is a greedy global nearest-neighbour assignment with a gate:
   the closest (slot, blob) pair is taken first, and pairs farther than the gate never are.
2. **Tracking.** Each later frame, every tracked landmark is predicted at its last position
   plus its last displacement in polar coordinates about the image centre (constant velocity:
   a turning robot rotates its image), the predictions are turned together by the rotation
   that best lays them on the blobs (a change of turn rate), and :func:`assign` matches the
   predictions with the new blobs. A blob nobody claims is an extra (noise, a spurious dark
   region) and is ignored.
3. **Coasting.** A landmark with no blob keeps its predicted position for up to
   ``coast_frames`` frames (a beacon lost for a frame to noise), then it is hidden.
4. **Re-acquisition.** A hidden landmark comes back through the cyclic order of azimuths: in a
   convex room with the beacons on its walls, every position inside sees the beacons in the same
   cyclic order around the image centre (the walls are star-shaped from any inner point). A
   free blob is given to a hidden landmark when it is the only free blob in the azimuth
   interval between that landmark's tracked neighbours in the reference order, that interval
   holds no other hidden landmark, and its distance to the image centre (the beacon's
   elevation) is within ``reacquire_radius`` (relative) of the landmark's last one. A landmark
   never seen yet (out of view in the first frame) is acquired the same way when it enters the
   view, its distance compared with the reference image's with twice the tolerance.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["BeaconTracker", "assign"]


def assign(predicted: NDArray[np.float64], blobs: NDArray[np.float64], gate: float) -> NDArray:
    """Greedy global nearest-neighbour assignment.

    Parameters
    ----------
    predicted
        ``(N, 2)`` predicted positions, pixels (NaN rows take no blob).
    blobs
        ``(M, 2)`` detected centres, pixels.
    gate
        Largest admissible distance, pixels.

    Returns
    -------
    numpy.ndarray
        ``(N,)`` int: the blob index of each slot, -1 where none.
    """
    out = np.full(len(predicted), -1, dtype=np.int64)
    if len(blobs) == 0 or len(predicted) == 0:
        return out
    with np.errstate(invalid="ignore"):
        dist = np.linalg.norm(predicted[:, None, :] - blobs[None, :, :], axis=-1)
    dist[~np.isfinite(dist)] = np.inf
    order = np.argsort(dist, axis=None, kind="stable")
    taken = np.zeros(len(blobs), dtype=bool)
    for flat in order:
        i, j = divmod(int(flat), len(blobs))
        if dist[i, j] > gate:
            break
        if out[i] < 0 and not taken[j]:
            out[i], taken[j] = j, True
    return out


def _azimuth(points: NDArray[np.float64], centre: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.arctan2(points[..., 1] - centre[1], points[..., 0] - centre[0])


#: rotations about the image centre tried between two frames (the robot turning), radians
_ROTATIONS = np.radians(np.concatenate([[0.0], np.arange(-20.0, 20.01, 0.25)]))


def _rotate(points: NDArray[np.float64], centre: NDArray[np.float64], angle: float) -> NDArray:
    c, s = math.cos(angle), math.sin(angle)
    rel = points - centre
    return centre + np.stack([c * rel[:, 0] - s * rel[:, 1], s * rel[:, 0] + c * rel[:, 1]], -1)


def _best_rotation(
    predicted: NDArray[np.float64],
    blobs: NDArray[np.float64],
    centre: NDArray[np.float64],
    gate: float,
) -> float:
    """Rotation about the image centre that best lays the predictions on the blobs, radians.

    The image of a turning robot rotates about the principal point; the rotation (from -20 to
    20 deg, 0.25 deg apart, about the constant-velocity prediction) minimising the sum of gated
    nearest-blob distances is taken.
    """
    if len(predicted) == 0 or len(blobs) == 0:
        return 0.0
    rel = predicted - centre
    c, s = np.cos(_ROTATIONS)[:, None], np.sin(_ROTATIONS)[:, None]
    rx = centre[0] + c * rel[:, 0] - s * rel[:, 1]
    ry = centre[1] + s * rel[:, 0] + c * rel[:, 1]
    d = np.hypot(rx[..., None] - blobs[:, 0], ry[..., None] - blobs[:, 1]).min(axis=-1)
    cost = np.minimum(d, gate).sum(axis=-1)
    return float(_ROTATIONS[int(np.argmin(cost))])


def _polar(points: NDArray[np.float64], centre: NDArray[np.float64]) -> NDArray[np.float64]:
    """``(..., 2)`` azimuth (radians) and distance (pixels) about the centre."""
    rel = np.asarray(points) - centre
    return np.stack([np.arctan2(rel[..., 1], rel[..., 0]), np.hypot(rel[..., 0], rel[..., 1])], -1)


def _ccw(a: float, b: float) -> float:
    """Counter-clockwise angle from ``a`` to ``b`` in ``[0, 2 pi)``."""
    return (b - a) % (2.0 * math.pi)


class BeaconTracker:
    """Keep the identity of ``N`` landmarks' blobs across frames (see the module docstring).

    Parameters
    ----------
    n_landmarks
        Number of landmark slots.
    gate_px
        Tracking gate, pixels.
    coast_frames
        Frames a lost landmark keeps its predicted position before it is hidden.
    reacquire_radius
        Largest relative change of distance to the image centre (elevation) for a hidden
        landmark to be re-acquired.
    """

    def __init__(
        self,
        n_landmarks: int,
        gate_px: float = 6.0,
        coast_frames: int = 3,
        reacquire_radius: float = 0.25,
    ) -> None:
        if n_landmarks < 1:
            raise ValueError(f"n_landmarks must be >= 1, got {n_landmarks!r}")
        if not (math.isfinite(gate_px) and gate_px > 0):
            raise ValueError(f"gate_px must be positive, got {gate_px!r}")
        if coast_frames < 0:
            raise ValueError(f"coast_frames must be >= 0, got {coast_frames!r}")
        self.n = n_landmarks
        self.gate_px = float(gate_px)
        self.coast_frames = int(coast_frames)
        if not (math.isfinite(reacquire_radius) and reacquire_radius > 0):
            raise ValueError(f"reacquire_radius must be positive, got {reacquire_radius!r}")
        self.reacquire_radius = float(reacquire_radius)
        self.reset()

    def reset(self) -> None:
        """Forget every track."""
        self.position = np.full((self.n, 2), np.nan)
        self.velocity = np.zeros((self.n, 2))  # (azimuth, radius) per frame: radians, pixels
        self.missed = np.zeros(self.n, dtype=np.int64)
        self.order: NDArray[np.int64] = np.arange(self.n)
        self.reference_radius = np.full(self.n, np.nan)

    @property
    def tracked(self) -> NDArray[np.bool_]:
        """``(N,)`` landmarks with a current position (seen, or coasting)."""
        return np.isfinite(self.position[:, 0]) & (self.missed <= self.coast_frames)

    def start(
        self,
        blobs: NDArray[np.float64],
        predicted: NDArray[np.float64],
        centre: NDArray[np.float64],
        reference: NDArray[np.float64] | None = None,
    ) -> NDArray[np.int64]:
        """Label the first frame's blobs with the nearest predicted landmark positions.

        Parameters
        ----------
        blobs
            ``(M, 2)`` detected centres, pixels.
        predicted
            ``(N, 2)`` where each landmark is expected, pixels (NaN: not expected).
        centre
            ``(2,)`` image centre (principal point), pixels.
        reference
            ``(N, 2)`` positions (NaN where unknown) defining the cyclic azimuth order used for
            re-acquisition (e.g. the goal image's); default: ``predicted``.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` blob index of each landmark, -1 where none.
        """
        self.reset()
        ref = predicted if reference is None else reference
        az = _azimuth(ref, centre)
        az = np.where(np.isfinite(az), az, np.inf)
        self.order = np.argsort(az, kind="stable")[: int(np.isfinite(az).sum())]
        self.reference_radius = np.hypot(*(np.asarray(ref, float) - centre).T)
        match = assign(np.asarray(predicted, float), np.asarray(blobs, float), self.gate_px)
        found = match >= 0
        self.position[found] = blobs[match[found]]
        self.missed[~found] = self.coast_frames + 1
        return match

    def update(self, blobs: NDArray[np.float64], centre: NDArray[np.float64]) -> NDArray[np.int64]:
        """Match a new frame's blobs with the landmarks.

        Parameters
        ----------
        blobs
            ``(M, 2)`` detected centres, pixels.
        centre
            ``(2,)`` image centre (principal point), pixels.

        Returns
        -------
        numpy.ndarray
            ``(N,)`` blob index of each landmark, -1 where it has none this frame (it may
            still be :attr:`tracked`, coasting).
        """
        blobs = np.asarray(blobs, dtype=np.float64).reshape(-1, 2)
        live = self.tracked
        predicted = np.where(live[:, None], self._predict(centre), np.nan)
        turn = _best_rotation(predicted[live], blobs, centre, self.gate_px)
        predicted = _rotate(predicted, centre, turn)
        match = assign(predicted, blobs, self.gate_px)
        self._reacquire(match, blobs, centre, live)
        steady = (match >= 0) & live & (self.missed == 0)
        if steady.any():  # each steady landmark's step, azimuth wrapped to [-pi, pi)
            step = _polar(blobs[match[steady]], centre) - _polar(self.position[steady], centre)
            step[:, 0] = (step[:, 0] + math.pi) % (2 * math.pi) - math.pi
            self.velocity[steady] = step
        # a landmark coming back moves with the others (the image turns as a whole)
        common = np.median(self.velocity[steady], axis=0) if steady.any() else np.zeros(2)
        for k in range(self.n):
            if match[k] >= 0:
                if not steady[k]:
                    self.velocity[k] = (common[0], 0.0)
                self.position[k] = blobs[match[k]]
                self.missed[k] = 0
            elif live[k]:
                self.position[k] = predicted[k]
                self.missed[k] += 1
        return match

    def _predict(self, centre: NDArray[np.float64]) -> NDArray[np.float64]:
        """Positions ``(N, 2)`` extrapolated in polar coordinates about the centre."""
        polar = _polar(self.position, centre) + self.velocity
        return centre + polar[:, 1:] * np.stack([np.cos(polar[:, 0]), np.sin(polar[:, 0])], -1)

    def _reacquire(
        self,
        match: NDArray[np.int64],
        blobs: NDArray[np.float64],
        centre: NDArray[np.float64],
        live: NDArray[np.bool_],
    ) -> None:
        taken = np.zeros(len(blobs), dtype=bool)
        taken[match[match >= 0]] = True
        free = np.flatnonzero(~taken)  # the blobs no landmark took, in order
        order = [int(k) for k in self.order]
        if len(free) == 0 or len(order) < 3:
            return
        anchored = [k for k in order if match[k] >= 0]
        if len(anchored) < 2:
            return
        blob_az = _azimuth(blobs, centre)
        for k in order:
            if live[k] or match[k] >= 0:
                continue
            # the distance to the centre last seen, else (never seen yet) the reference one
            seen = bool(np.isfinite(self.position[k, 0]))
            base_r = (
                float(np.hypot(*(self.position[k] - centre)))
                if seen
                else float(self.reference_radius[k])
            )
            if not np.isfinite(base_r):
                continue
            i = order.index(k)
            prev = next(
                order[(i - s) % len(order)]
                for s in range(1, len(order))
                if match[order[(i - s) % len(order)]] >= 0
            )
            nxt = next(
                order[(i + s) % len(order)]
                for s in range(1, len(order))
                if match[order[(i + s) % len(order)]] >= 0
            )
            a0 = float(blob_az[match[prev]])
            span = _ccw(a0, float(blob_az[match[nxt]]))
            between = [order[(order.index(prev) + s) % len(order)] for s in range(1, len(order))]
            between = between[: between.index(nxt)] if nxt in between else between
            if sum(1 for j in between if match[j] < 0) != 1:
                continue
            candidates = [int(b) for b in free if 0 < _ccw(a0, float(blob_az[b])) < span]
            if len(candidates) != 1:
                continue
            new_r = float(np.hypot(*(blobs[candidates[0]] - centre)))
            tolerance = self.reacquire_radius * (1.0 if seen else 2.0)
            if abs(new_r - base_r) <= tolerance * base_r:
                match[k] = candidates[0]
                free = free[free != candidates[0]]
