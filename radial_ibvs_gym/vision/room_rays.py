"""Where each of an omnidirectional renderer's rays first meets a box room, and its shade.

:class:`VerticalHits` holds every ray's floor or ceiling hit for one room height (computed
once: the floor and the ceiling do not turn with the robot), the rays sorted by how far that
hit lies from the camera's axis, and by azimuth. :func:`shade_rays` meets the rays that may
reach a wall with the walls at one pose, shades them and paints the beacons, each tried on
the rays of an azimuth window about its bearing (:func:`near_beacons`). Used by
:class:`~radial_ibvs_gym.vision.omni.OmniRenderer`; pure numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    from radial_ibvs_gym.vision.room_scene import RoomScene

__all__ = ["BEACON", "SHADE", "SHADES", "VerticalHits", "near_beacons", "shade_rays"]

#: grey levels (0..1) of the surfaces: walls facing +-x, walls facing +-y, floor, ceiling
SHADE = {"x": 0.78, "y": 0.66, "floor": 0.5, "ceiling": 0.9}
#: the shades by surface code: floor, ceiling, a y wall, an x wall
SHADES = np.array([SHADE["floor"], SHADE["ceiling"], SHADE["y"], SHADE["x"]])
#: grey level of the beacons
BEACON = 0.06


@dataclass(frozen=True)
class VerticalHits:
    """Every ray's floor or ceiling hit for one room height, the rays sorted by its reach.

    The arrays but ``image`` are ``(R,)``, one entry per ray, sorted by ``reach``.

    Attributes
    ----------
    index
        Flat image index of each ray.
    ox, oy, dx, dy, dz
        The rays' origins (relative to the camera) and directions in the camera frame, metres.
    tz, oz
        Ray parameter of the floor or ceiling hit (inf: none) and the origins' heights above
        the floor, metres.
    up
        Whether each ray points up (its flat surface is the ceiling, not the floor).
    reach
        Distance of the hit from the camera's axis, metres (inf where the ray meets neither).
    image
        ``(size * size,)`` the background with every ray's floor or ceiling hit shaded (with
        the fall-off with distance; black where a ray meets neither).
    azimuth, by_azimuth
        ``(R,)`` the rays' azimuths in the camera frame, ``atan2(dy, dx)`` in radians, sorted,
        and the position of each in the arrays above (the rays near a bearing, in slices).
    origin_reach
        How far the rays' origins lie from the camera's axis, metres.
    """

    index: NDArray[np.intp]
    ox: NDArray[np.float64]
    oy: NDArray[np.float64]
    dx: NDArray[np.float64]
    dy: NDArray[np.float64]
    dz: NDArray[np.float64]
    tz: NDArray[np.float64]
    oz: NDArray[np.float64]
    up: NDArray[np.bool_]
    reach: NDArray[np.float64]
    image: NDArray[np.float64]
    azimuth: NDArray[np.float64]
    by_azimuth: NDArray[np.intp]
    origin_reach: float

    @classmethod
    def of(
        cls,
        origins: NDArray[np.float64],
        directions: NDArray[np.float64],
        index: NDArray[np.intp],
        flat_shade: NDArray[np.float64],
        background: NDArray[np.float64],
        camera_height: float,
        height: float,
    ) -> VerticalHits:
        """Compute the hits of a renderer's rays in a room ``height`` metres high.

        Parameters
        ----------
        origins, directions
            ``(R, 3)`` the rays' origins (relative to the camera) and directions in the camera
            frame, metres.
        index
            ``(R,)`` flat image index of each ray.
        flat_shade
            ``(R,)`` grey level of each ray's floor or ceiling.
        background
            ``(size, size)`` the image outside the rays.
        camera_height, height
            The camera's height above the floor and the room's, metres.
        """
        o, d = origins, directions
        oz = camera_height + o[:, 2]
        dz = d[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            tz = np.where(dz > 0, height - oz, -oz) / dz
        tz[~(tz >= 0)] = np.inf
        finite = np.isfinite(tz)
        with np.errstate(invalid="ignore"):
            reach = np.hypot(o[:, 0] + tz * d[:, 0], o[:, 1] + tz * d[:, 1])
        reach[~(finite & np.isfinite(reach))] = np.inf
        order = np.argsort(reach, kind="stable")
        image = background.copy().reshape(-1)
        image[index] = flat_shade / (1.0 + 0.03 * tz)
        azimuth = np.arctan2(d[order, 1], d[order, 0])
        by_azimuth = np.argsort(azimuth, kind="stable")
        return cls(
            index=index[order],
            ox=o[order, 0],
            oy=o[order, 1],
            dx=d[order, 0],
            dy=d[order, 1],
            dz=dz[order],
            tz=tz[order],
            oz=oz[order],
            up=dz[order] > 0,
            reach=reach[order],
            image=image,
            azimuth=azimuth[by_azimuth],
            by_azimuth=by_azimuth,
            origin_reach=float(np.hypot(o[:, 0], o[:, 1]).max()),
        )


def shade_rays(
    v: VerticalHits, k: int, x: float, y: float, c: float, s: float, scene: RoomScene
) -> NDArray[np.float64]:
    """Shade the rays from the ``k``-th on, each met with every surface, and paint the beacons.

    The first surface along a ray is the one of least ray parameter (ties: the ``x`` walls,
    then the ``y`` walls, then the floor or ceiling); each step below gives the same bits as
    the plain formulas in the comments (``tests/vision/test_pixels.py``).

    Parameters
    ----------
    v
        The rays' floor and ceiling hits for the scene's height.
    k
        The first ray (in ``v``'s order) that may meet a wall.
    x, y, c, s
        The camera's position (metres) and the cosine and sine of the robot's heading.
    scene
        The room.

    Returns
    -------
    numpy.ndarray
        ``(R - k,)`` grey levels in ``[0, 1]``, in ``v``'s order.
    """
    o0, o1, d0, d1 = v.ox[k:], v.oy[k:], v.dx[k:], v.dy[k:]
    ox = c * o0
    ox += x
    ox -= s * o1  # x + c o0 - s o1, in that order
    oy = s * o0
    oy += y
    oy += c * o1  # y + s o0 + c o1
    dx = c * d0
    dx -= s * d1
    dy = s * d0
    dy += c * d1
    tz = v.tz[k:]  # the floor and ceiling do not turn
    w, depth = scene.size
    # where(dx > 0, w - ox, -ox) as (w or 0) - ox: the same numbers (but the sign of a zero,
    # which no shade depends on), without a masked operation
    tx = (dx > 0) * w
    tx -= ox
    ty = (dy > 0) * depth
    ty -= oy
    with np.errstate(divide="ignore", invalid="ignore"):
        tx /= dx
        ty /= dy
    tx[~(tx >= 0)] = np.inf  # NaN (dx = 0) and behind the ray
    ty[~(ty >= 0)] = np.inf
    t = np.minimum(tx, ty)
    np.minimum(t, tz, out=t)
    on_x = tx == t  # tx <= ty and tx <= tz
    on_y = ty == t
    on_y &= ~on_x
    # where(on_x, x shade, where(on_y, y shade, floor or ceiling shade)), as a table lookup
    code = v.up[k:] & ~(on_x | on_y)
    code = code.view(np.uint8) | (on_y.view(np.uint8) << 1)
    code |= on_x.view(np.uint8) * np.uint8(3)
    shade = SHADES.take(code)
    fall = 0.03 * t
    fall += 1.0
    shade /= fall  # gentle fall-off with distance
    # the beacons: each tried on the rays of an azimuth window about its bearing that holds
    # every ray that can meet it (near_beacons), those on the x walls together, then those on
    # the y walls; a ray is kept where it meets the beacon's own wall first (the opposite wall
    # is a room away), then by its coordinate along the wall alone (``h^2 < r^2`` needs
    # ``|h| < r`` for each of the three coordinates), then the few left by the full test
    r, r2 = scene.beacon_radius, scene.beacon_radius**2
    toward = np.where(np.asarray(scene.walls) % 2 == 0, -1.0, 1.0)  # each beacon's wall
    # x walls: the normal is x, the coordinate along the wall y (1); y walls: y, and x (0)
    for x_walls, hits, normal, a, origin, direction in (
        (True, on_x, dx, 1, oy, dy),
        (False, on_y, dy, 0, ox, dx),
    ):
        rays, owner = near_beacons(v, k, x, y, c, s, scene, x_walls)
        keep = hits[rays]
        # towards the beacon's wall (x = 0 or y = 0: -d > 0, which is d < 0 bit for bit)
        keep &= normal[rays] * toward[owner] > 0
        rays, owner = rays[keep], owner[keep]
        beacon = scene.beacons[owner]
        near = np.abs(origin[rays] + t[rays] * direction[rays] - beacon[:, a]) < r
        rays, beacon = rays[near], beacon[near]
        tr = t[rays]
        hx = ox[rays] + tr * dx[rays] - beacon[:, 0]
        hy = oy[rays] + tr * dy[rays] - beacon[:, 1]
        hz = v.oz[k:][rays] + tr * v.dz[k:][rays] - beacon[:, 2]
        shade[rays[hx * hx + hy * hy + hz * hz < r2]] = BEACON
    return shade


def near_beacons(
    v: VerticalHits,
    k: int,
    x: float,
    y: float,
    c: float,
    s: float,
    scene: RoomScene,
    x_walls: bool,
) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Every ray, among those from the ``k``-th on, that can meet a beacon (and a few more).

    A ray meets a beacon at ``o + t d`` within ``r`` of its centre ``b``; with the origin's
    offset ``|o - p| <= rho`` from the camera ``p`` (:attr:`VerticalHits.origin_reach`, in the
    horizontal plane), ``|t d - (b - p)| < r + rho``: seen from the camera, ``t d`` lies in a
    disc of that radius about the beacon, whose half-angle is ``asin((r + rho) / |b - p|)``.
    For a beacon closer than twice ``r + rho``, every ray is a candidate. The window is
    widened by a micro-radian, far more than the rounding of the rotated directions.

    Parameters
    ----------
    v
        The rays' floor and ceiling hits.
    k
        The first ray (in ``v``'s order) to consider.
    x, y, c, s
        The camera's position (metres) and the cosine and sine of the robot's heading.
    scene
        The room and its beacons.
    x_walls
        The beacons on the walls ``x = 0`` and ``x = width`` (else those on the ``y`` walls).

    Returns
    -------
    rays, owner
        ``(M,)`` positions, less ``k``, of the candidate rays, and the beacon each is a
        candidate for (a ray may be one for several).
    """
    n = len(v.index) - k
    parts, owners = [], []
    reach = scene.beacon_radius + v.origin_reach
    for j, (beacon, wall) in enumerate(zip(scene.beacons, scene.walls, strict=True)):
        if (wall < 2) != x_walls:
            continue
        bx, by = float(beacon[0]) - x, float(beacon[1]) - y
        ratio = reach / math.hypot(bx, by) if (bx or by) else math.inf
        if not ratio < 0.5:  # too close for a window: every ray
            part = np.arange(k, k + n)
        else:
            bearing = math.atan2(c * by - s * bx, c * bx + s * by)  # camera frame: by -yaw
            part = _window(v, bearing, math.asin(ratio) + 1e-6)
        parts.append(part)
        owners.append(np.full(len(part), j, dtype=np.intp))
    if not parts:
        return np.zeros(0, dtype=np.intp), np.zeros(0, dtype=np.intp)
    rays, owner = np.concatenate(parts), np.concatenate(owners)
    keep = rays >= k
    rays, owner = rays[keep], owner[keep]
    rays -= k
    return rays, owner


def _window(v: VerticalHits, bearing: float, half_width: float) -> NDArray[np.intp]:
    """Positions ``(M,)`` in ``v`` of the rays within ``half_width`` of a bearing (radians)."""
    centre = (bearing + math.pi) % (2.0 * math.pi) - math.pi
    lo, hi = centre - half_width, centre + half_width
    if lo < -math.pi:  # the window wraps around -pi
        edges = [(-math.inf, hi), (lo + 2.0 * math.pi, math.inf)]
    elif hi > math.pi:
        edges = [(lo, math.inf), (-math.inf, hi - 2.0 * math.pi)]
    else:
        edges = [(lo, hi)]
    bounds = np.searchsorted(v.azimuth, [e for edge in edges for e in edge]).tolist()
    slices = [v.by_azimuth[bounds[i] : bounds[i + 1]] for i in range(0, len(bounds), 2)]
    return slices[0] if len(slices) == 1 else np.concatenate(slices)
