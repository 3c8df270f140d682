"""The pinhole camera behind the mirror: intrinsics ``K`` (paper eq. 2-3)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from radial_ibvs_gym._validation import as_float_array, check_last_dim, check_positive

__all__ = ["Intrinsics"]


@dataclass(frozen=True, kw_only=True)
class Intrinsics:
    """Pinhole intrinsics, zero skew (eq. 3).

    Attributes
    ----------
    fx, fy
        Focal lengths in pixels (> 0).
    mu_x, mu_y
        Principal point in pixels (the centre of distortion of the radial model).
    width, height
        Image size in pixels (> 0).
    """

    fx: float
    fy: float
    mu_x: float
    mu_y: float
    width: int
    height: int

    def __post_init__(self) -> None:
        check_positive(self.fx, "fx")
        check_positive(self.fy, "fy")
        for name in ("mu_x", "mu_y"):
            value = getattr(self, name)
            if not np.isfinite(value):
                raise ValueError(f"{name} must be finite, got {value!r}")
        for name in ("width", "height"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value <= 0:
                raise ValueError(f"{name} must be a positive integer (pixels), got {value!r}")

    @classmethod
    def from_lens(
        cls, focal_length: float, pixel_pitch: float, width: int, height: int
    ) -> Intrinsics:
        """Build the intrinsics of a lens on a sensor of square pixels.

        Parameters
        ----------
        focal_length
            Lens focal length, metres.
        pixel_pitch
            Pixel size, metres.
        width, height
            Image size, pixels; the principal point is the image centre.
        """
        f = check_positive(focal_length, "focal_length") / check_positive(
            pixel_pitch, "pixel_pitch"
        )
        return cls(
            fx=f, fy=f, mu_x=(width - 1) / 2.0, mu_y=(height - 1) / 2.0, width=width, height=height
        )

    @property
    def K(self) -> NDArray[np.float64]:
        """The ``(3, 3)`` intrinsic matrix of eq. (3)."""
        return np.array([[self.fx, 0.0, self.mu_x], [0.0, self.fy, self.mu_y], [0.0, 0.0, 1.0]])

    @property
    def rho_f(self) -> float:
        """Focal ratio ``fx / fy`` (eq. 8), the only focal information eq. (7) needs."""
        return self.fx / self.fy

    @property
    def principal_point(self) -> NDArray[np.float64]:
        """``(mu_x, mu_y)`` in pixels, shape ``(2,)``."""
        return np.array([self.mu_x, self.mu_y])

    def project(self, x_m: ArrayLike) -> NDArray[np.float64]:
        """Pixels ``x_d = K x_m`` (eq. 2) of metric image points ``(..., 2)``."""
        x = as_float_array(x_m, "x_m")
        check_last_dim(x, 2, "x_m")
        return np.stack([self.fx * x[..., 0] + self.mu_x, self.fy * x[..., 1] + self.mu_y], -1)

    def unproject(self, pixels: ArrayLike) -> NDArray[np.float64]:
        """Metric image points ``x_m = K^-1 x_d`` of pixels ``(..., 2)``."""
        p = as_float_array(pixels, "pixels")
        check_last_dim(p, 2, "pixels")
        return np.stack([(p[..., 0] - self.mu_x) / self.fx, (p[..., 1] - self.mu_y) / self.fy], -1)

    def contains(self, pixels: ArrayLike) -> NDArray[np.bool_]:
        """Whether pixels ``(..., 2)`` fall inside the image ``[0, width) x [0, height)``."""
        p = np.asarray(pixels, dtype=np.float64)
        with np.errstate(invalid="ignore"):
            return (
                (p[..., 0] >= 0)
                & (p[..., 0] < self.width)
                & (p[..., 1] >= 0)
                & (p[..., 1] < self.height)
            )
