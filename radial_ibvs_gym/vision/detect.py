"""Measure an omnidirectional image as the paper's set-up does (Section 4.2), with OpenCV.

Two steps, each a function of one grey image:

1. :func:`fit_mirror_border`: the image of the mirror rim, an ellipse fitted to the outline of
   the bright mirror disc. Its centre is the principal point (the paper uses a Hough circle;
   an ellipse also gives ``rho_f = fx / fy`` from the ratio of its axes, eq. 8).
2. :func:`detect_beacons`: the centres of the dark beacons inside the border, by
   intensity-weighted moments of each dark blob (sub-pixel). Blobs that touch the rim (cut by
   it, so their centre would be biased), that are too small or too large, or that are not
   blob-shaped (solidity) are rejected and counted.

Coordinates are image pixels ``(column, row)``, the centre of the top-left pixel at
``(0, 0)``; :func:`measure` chains the two steps and returns eq. (7)'s normalised points.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import cv2
import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.camera import normalise_pixels

__all__ = ["BeaconDetections", "BorderFit", "Measurement", "detect_beacons", "fit_mirror_border"]
__all__ += ["measure"]


@dataclass(frozen=True)
class BorderFit:
    """The fitted image of the mirror border.

    Attributes
    ----------
    centre
        ``(2,)`` ellipse centre ``(column, row)``, pixels: the principal point estimate.
    semi_axes
        ``(2,)`` half-extents of the ellipse along the columns and the rows, pixels.
    angle_deg
        Orientation of the ellipse's first axis as OpenCV reports it, degrees.
    residual_px
        RMS distance of the outline points to the fitted ellipse (algebraic approximation),
        pixels.
    """

    centre: NDArray[np.float64]
    semi_axes: NDArray[np.float64]
    angle_deg: float
    residual_px: float

    @property
    def rho_f(self) -> float:
        """Focal ratio ``fx / fy`` from the ellipse's half-extents (eq. 8)."""
        return float(self.semi_axes[0] / self.semi_axes[1])


@dataclass(frozen=True)
class BeaconDetections:
    """Dark blobs found inside the mirror border.

    Attributes
    ----------
    centres
        ``(K, 2)`` sub-pixel centres ``(column, row)``, pixels.
    areas
        ``(K,)`` blob areas, pixels.
    rejected
        Counts of blobs dropped, by reason: ``"rim"``, ``"size"``, ``"shape"``.
    """

    centres: NDArray[np.float64]
    areas: NDArray[np.float64]
    rejected: dict[str, int]


@dataclass(frozen=True)
class Measurement:
    """The result of :func:`measure`.

    Attributes
    ----------
    status
        ``"ok"``, ``"border_not_found"`` (no calibration: ``x_n`` is empty) or ``"no_beacons"``;
        ``"no_frame"`` for a dropped frame of a recording (nothing measured:
        :meth:`~radial_ibvs_gym.vision.pipeline.DetectedPoints.observe_image`).
    x_n
        ``(K, 2)`` eq. (7) points on the unit circle of the detected beacons.
    centres
        ``(K, 2)`` their image centres ``(column, row)``, pixels.
    border
        The border fit, or ``None``.
    rejected
        Counts of rejected blobs (see :class:`BeaconDetections`).
    """

    status: str
    x_n: NDArray[np.float64]
    centres: NDArray[np.float64]
    border: BorderFit | None
    rejected: dict[str, int]


def _check_image(image: NDArray[np.uint8]) -> NDArray[np.uint8]:
    image = np.asarray(image)
    if image.ndim == 3 and image.shape[-1] == 1:
        image = image[..., 0]
    if image.ndim != 2 or image.dtype != np.uint8:
        raise ValueError(
            f"expected a (H, W) or (H, W, 1) uint8 grey image, got shape {image.shape} and "
            f"dtype {image.dtype}"
        )
    if min(image.shape) < 16:
        raise ValueError(f"image too small to measure: {image.shape}")
    return np.ascontiguousarray(image)


def fit_mirror_border(image: NDArray[np.uint8], min_fill: float = 0.2) -> BorderFit | None:
    """Fit an ellipse to the border of the bright mirror disc.

    The image is split into dark and bright by Otsu's threshold; the outline of the largest
    bright region is replaced by its convex hull (so that dark beacons cut into the rim do not
    bend it) and an ellipse is fitted to the hull's outline (``cv2.fitEllipse``).

    Parameters
    ----------
    image
        ``(H, W)`` uint8 grey image.
    min_fill
        The bright region must cover at least this fraction of the image, else there is no
        border (a black, blank or over-exposed frame).

    Returns
    -------
    BorderFit or None
        ``None`` when no border is found.
    """
    image = _check_image(image)
    _, bright = cv2.threshold(image, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    contours, _ = cv2.findContours(bright, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    if not contours:
        return None
    outline = max(contours, key=cv2.contourArea)
    area = cv2.contourArea(outline)
    if area < min_fill * image.size or area > 0.98 * image.size or len(outline) < 20:
        return None
    hull = cv2.convexHull(outline)
    # densify the hull so that long bridging edges do not under-weight their stretch
    pts = hull[:, 0, :].astype(np.float64)
    nxt = np.roll(pts, -1, axis=0)
    dense = []
    for a, b in zip(pts, nxt, strict=True):
        n = max(1, math.ceil(float(np.hypot(*(b - a)))))
        dense.append(a + (b - a) * (np.arange(n) / n)[:, None])
    ring = np.concatenate(dense)
    # contour points are pixel centres on the inside of the edge: move them out half a pixel
    (cx, cy), (w, h), angle = cv2.fitEllipse(ring.astype(np.float32))
    if not (w > 0 and h > 0):
        return None
    theta = math.radians(angle)
    a, b = w / 2.0 + 0.5, h / 2.0 + 0.5
    ext_u = math.hypot(a * math.cos(theta), b * math.sin(theta))
    ext_v = math.hypot(a * math.sin(theta), b * math.cos(theta))
    c, s = math.cos(theta), math.sin(theta)
    du, dv = ring[:, 0] - cx, ring[:, 1] - cy
    xr, yr = c * du + s * dv, -s * du + c * dv
    radial = np.hypot(xr / (a - 0.5), yr / (b - 0.5))
    residual = float(np.sqrt(np.mean(((radial - 1.0) * 0.5 * (a + b - 1.0)) ** 2)))
    return BorderFit(
        centre=np.array([cx, cy], dtype=np.float64),
        semi_axes=np.array([ext_u, ext_v], dtype=np.float64),
        angle_deg=float(angle),
        residual_px=residual,
    )


@functools.lru_cache(maxsize=8)
def _grid(
    rows: int, cols: int, cu: float, cv: float, au: float, av: float
) -> tuple[NDArray[np.int_], NDArray[np.int_], NDArray[np.float64]]:
    """Pixel rows, columns and elliptic radius about the border (cached: fixed per episode)."""
    yy, xx = np.mgrid[0:rows, 0:cols]
    radius = np.hypot((xx - cu) / au, (yy - cv) / av)
    for array in (yy, xx, radius):
        array.flags.writeable = False
    return yy, xx, radius


@functools.lru_cache(maxsize=8)
def _zones(
    rows: int,
    cols: int,
    border: tuple[float, float, float, float],
    rim_margin_px: float,
    centre_exclusion: float,
) -> tuple[NDArray[np.bool_], NDArray[np.bool_], NDArray[np.uint8]]:
    """Return the searched zone, the band along the rim and the zone as a uint8 mask (cached)."""
    _, _, radius = _grid(rows, cols, *border)
    scale = 0.5 * (border[2] + border[3])
    inner = (radius < 1.0 - rim_margin_px / scale) & (radius > centre_exclusion)
    band = ~inner & (radius < 1.0 + 1.0 / scale) & (radius > centre_exclusion)
    mask = inner.astype(np.uint8)
    for array in (inner, band, mask):
        array.flags.writeable = False
    return inner, band, mask


def _median_grey(values: NDArray[np.uint8]) -> float:
    """``np.median`` of a few grey levels (``(K,)``, K > 0): the middle one, or the two's mean."""
    ordered = np.sort(values).tolist()
    half = len(ordered) // 2
    return float(ordered[half]) if len(ordered) % 2 else (ordered[half - 1] + ordered[half]) / 2.0


def _median_of_histogram(counts: NDArray[np.int64]) -> float:
    """Return the median grey level from the values' cumulated histogram ``(256,)``."""
    n = int(counts[-1])
    upper = int(np.searchsorted(counts, n // 2, side="right"))
    if n % 2:
        return float(upper)
    lower = int(np.searchsorted(counts, n // 2 - 1, side="right"))
    return (lower + upper) / 2.0


#: OpenCV's block-based labelling (Grana's BBDT): the default's labels, in a third of its time
#: here (``tests/vision/test_pixels.py`` checks that they are the same)
_LABELLING = cv2.CCL_BBDT


def _below(image: NDArray[np.uint8], threshold: float) -> NDArray[np.bool_]:
    """``image < threshold`` for a uint8 image, compared as integers (a few times faster).

    A grey level is below a threshold when it is below the threshold's ceiling.
    """
    if not math.isfinite(threshold):
        return image < threshold
    limit = math.ceil(threshold)
    if limit > 255:
        return np.ones(image.shape, dtype=bool)
    return image < np.uint8(limit) if limit > 0 else np.zeros(image.shape, dtype=bool)


def _label(dark: NDArray[np.uint8]) -> tuple[NDArray[np.int32], list[list[int]]]:
    """8-connected blobs of a 0/1 image: labels ``(H, W)`` and each blob's statistics.

    The statistics are OpenCV's ``connectedComponentsWithStats`` rows but the background's:
    ``[left, top, width, height, area]`` of blobs 1, 2, ..., pixels. They are read from the
    few dark pixels (OpenCV's own statistics visit every pixel of the image: twice the time
    of the labelling).
    """
    n, found = cv2.connectedComponentsWithAlgorithm(dark, 8, cv2.CV_32S, _LABELLING)
    labels = np.asarray(found, dtype=np.int32)
    if n <= 1:
        return labels, []
    xy = cv2.findNonZero(dark).reshape(-1, 2)  # (column, row) of each dark pixel
    label = labels[xy[:, 1], xy[:, 0]]
    area = np.bincount(label, minlength=n)[1:]  # every blob has a pixel
    xy = xy[np.argsort(label, kind="stable")]  # blob by blob
    starts = np.cumsum(area) - area
    low = np.minimum.reduceat(xy, starts, axis=0)
    high = np.maximum.reduceat(xy, starts, axis=0)
    return labels, np.concatenate([low, high - low + 1, area[:, None]], axis=1).tolist()


def _median_in(image: NDArray[np.uint8], mask: NDArray[np.uint8]) -> float:
    """``np.median(image[mask > 0])``, from OpenCV's histogram of the masked pixels."""
    counts = np.asarray(cv2.calcHist([image], [0], mask, [256], [0, 256])).reshape(-1)
    return _median_of_histogram(np.cumsum(counts.astype(np.int64)))


def detect_beacons(
    image: NDArray[np.uint8],
    border: BorderFit,
    *,
    dark_fraction: float = 0.5,
    rim_margin_px: float = 3.0,
    centre_exclusion: float = 0.15,
    min_area: int = 2,
    max_area_fraction: float = 0.01,
    min_solidity: float = 0.7,
    max_elongation: float = 4.0,
) -> BeaconDetections:
    """Centres of the dark blobs inside the mirror border.

    A pixel is dark when it is below ``dark_fraction`` times the median grey level inside the
    border (the threshold follows the exposure). Each 8-connected dark blob is kept when its
    area is in ``[min_area, max_area_fraction * H * W]``, it stays ``rim_margin_px`` inside the
    fitted border (a blob cut by the rim would have a biased centre), it is not in the blind
    centre (``centre_exclusion`` of the border radius: the camera's own reflection) and, from 12
    pixels on, its solidity (area over convex-hull area) is at least ``min_solidity`` and its
    elongation (ratio of the principal axes of its second moments) at most
    ``max_elongation`` (beacon images are ellipses, squeezed radially). Its
    centre is the centroid of the pixels of the blob grown by one pixel, weighted by how much
    darker than the surface around the blob (the median of a ring 1 to 3 pixels out) each is:
    sub-pixel, and unbiased by blur or shading.

    Parameters
    ----------
    image
        ``(H, W)`` uint8 grey image.
    border
        The fitted mirror border (:func:`fit_mirror_border`).
    dark_fraction, rim_margin_px, centre_exclusion, min_area, max_area_fraction, min_solidity,
    max_elongation
        Thresholds described above (pixels where a length or an area).

    Returns
    -------
    BeaconDetections
    """
    image = _check_image(image)
    rows, cols = image.shape
    key = (*(float(v) for v in border.centre), *(float(v) for v in border.semi_axes))
    yy, xx, _ = _grid(rows, cols, *key)
    inner, band, inner_u8 = _zones(rows, cols, key, float(rim_margin_px), float(centre_exclusion))
    if not inner.any():
        return BeaconDetections(np.zeros((0, 2)), np.zeros(0), {"rim": 0, "size": 0, "shape": 0})
    threshold = dark_fraction * _median_in(image, inner_u8)
    below = _below(image, threshold)
    dark = (below & inner).view(np.uint8)
    labels, stats = _label(dark)
    max_area = max_area_fraction * rows * cols
    kernel = np.ones((3, 3), np.uint8)
    ring_kernel = np.ones((7, 7), np.uint8)
    centres, areas = [], []
    rejected = {"rim": 0, "size": 0, "shape": 0}
    for label, (x0, y0, w, h, area) in enumerate(stats, start=1):
        if area < min_area or area > max_area:
            rejected["size"] += 1
            continue
        # a window three pixels larger than the blob on every side
        r0, r1 = max(0, y0 - 4), min(rows, y0 + h + 4)
        c0, c1 = max(0, x0 - 4), min(cols, x0 + w + 4)
        near = labels[r0:r1, c0:c1]
        blob = (near == label).view(np.uint8)  # 0 and 1, as OpenCV takes
        grown = cv2.dilate(blob, kernel) > 0
        # blobs touching the dark band along the rim are cut by it
        if (grown & below[r0:r1, c0:c1] & band[r0:r1, c0:c1]).any():
            rejected["rim"] += 1
            continue
        if area >= 12:
            contours, _ = cv2.findContours(blob, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
            hull_area = cv2.contourArea(cv2.convexHull(max(contours, key=cv2.contourArea)))
            m = cv2.moments(blob, binaryImage=True)
            spread = np.linalg.eigvalsh(
                np.array([[m["mu20"], m["mu11"]], [m["mu11"], m["mu02"]]]) / m["m00"]
            )
            elongation = math.sqrt(spread[1] / max(spread[0], 1.0 / 12.0))
            solid = hull_area <= 0 or area / (hull_area + 0.5 * len(contours[0])) >= min_solidity
            if not solid or elongation > max_elongation:
                rejected["shape"] += 1
                continue
        window = image[r0:r1, c0:c1].astype(np.float64)
        ring = (cv2.dilate(blob, ring_kernel) > 0) & ~grown & (near == 0)
        background = _median_grey(image[r0:r1, c0:c1][ring]) if ring.any() else threshold
        wts = np.maximum(background - window, 0.0) * grown
        total = wts.sum()
        if total <= 0:
            rejected["size"] += 1
            continue
        centres.append(
            (
                (wts * xx[r0:r1, c0:c1]).sum() / total,
                (wts * yy[r0:r1, c0:c1]).sum() / total,
            )
        )
        areas.append(float(area))
    return BeaconDetections(
        centres=np.asarray(centres, dtype=np.float64).reshape(-1, 2),
        areas=np.asarray(areas, dtype=np.float64),
        rejected=rejected,
    )


def measure(
    image: NDArray[np.uint8],
    *,
    rho_f: float | None = None,
    border: BorderFit | None = None,
    **detect_kwargs: float,
) -> Measurement:
    """Border fit, beacon detection and eq. (7) normalisation of one image.

    Parameters
    ----------
    image
        ``(H, W)`` uint8 grey image.
    rho_f
        Focal ratio to use; ``None`` takes it from the border ellipse.
    border
        A border fit to reuse (e.g. the last good one) instead of fitting this image's.
    **detect_kwargs
        Passed to :func:`detect_beacons`.

    Returns
    -------
    Measurement
        Never raises on a bad frame: the status says what went wrong.
    """
    image = _check_image(image)
    border = border if border is not None else fit_mirror_border(image)
    empty = np.zeros((0, 2))
    if border is None:
        return Measurement("border_not_found", empty, empty, None, {})
    found = detect_beacons(image, border, **detect_kwargs)  # type: ignore[arg-type]
    centres = found.centres
    # a centre on the principal point has no direction: drop it
    keep = np.hypot(*(centres - border.centre).T) > 1e-6 if len(centres) else np.zeros(0, bool)
    centres = centres[keep]
    if len(centres) == 0:
        return Measurement("no_beacons", empty, empty, border, found.rejected)
    ratio = border.rho_f if rho_f is None else rho_f
    x_n = normalise_pixels(centres, border.centre, ratio)
    return Measurement("ok", x_n, centres, border, found.rejected)
