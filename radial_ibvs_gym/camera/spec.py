"""Camera configurations as data: the YAML files under ``configs/cameras/``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera, Imperfections
from radial_ibvs_gym.camera.presets import paper_camera
from radial_ibvs_gym.config import config_path, load_yaml

__all__ = ["CameraSpec", "ImperfectionRanges", "load_camera"]


@dataclass(frozen=True, kw_only=True)
class ImperfectionRanges:
    """Camera imperfections drawn per episode: a real camera, never quite the nominal one.

    Each episode draws, uniformly and independently, an offset of each imperfection, which is
    added to the camera's fixed ``imperfections``. The draw is the env's (its ``np_random``,
    at each reset); the env reports it in ``info["camera_imperfections"]``.

    Attributes
    ----------
    principal_point_offset
        Each of ``du``, ``dv`` in ``[-r, r]`` pixels (``r >= 0``).
    focal_ratio_error
        In ``[-e, e]`` (``0 <= e < 1``): the relative error of ``fy``.
    pixel_noise_std
        ``[low, high]`` pixels: the standard deviation of the pixel noise.
    tilt
        Each of the tilts about x and y in ``[-t, t]`` radians (``0 <= t < pi / 4``).
    """

    principal_point_offset: float = 0.0
    focal_ratio_error: float = 0.0
    pixel_noise_std: tuple[float, float] = (0.0, 0.0)
    tilt: float = 0.0

    def __post_init__(self) -> None:
        bounds = {
            "principal_point_offset": (self.principal_point_offset, math.inf),
            "focal_ratio_error": (self.focal_ratio_error, 1.0),
            "tilt": (self.tilt, math.pi / 4),
        }
        for name, (value, top) in bounds.items():
            if not (math.isfinite(value) and 0.0 <= value < top):
                raise ValueError(f"{name} must be finite, >= 0 and < {top:g}, got {value!r}")
        lo, hi = self.pixel_noise_std
        if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 <= lo <= hi):
            raise ValueError(
                f"pixel_noise_std must be a [low, high] range with 0 <= low <= high, got "
                f"{self.pixel_noise_std!r}"
            )

    def draw(self, rng: np.random.Generator, base: Imperfections) -> Imperfections:
        """Draw one episode's imperfections: ``base`` plus a uniform draw of each range.

        Always draws the same six numbers in the same order (principal point, focal ratio,
        noise, tilts), so the stream does not depend on which ranges are zero.
        """
        r, e, t = self.principal_point_offset, self.focal_ratio_error, self.tilt
        du, dv = rng.uniform(-r, r, 2)
        values = rng.uniform(
            [-e, self.pixel_noise_std[0], -t, -t], [e, self.pixel_noise_std[1], t, t]
        )
        return Imperfections(
            principal_point_offset=(
                base.principal_point_offset[0] + float(du),
                base.principal_point_offset[1] + float(dv),
            ),
            focal_ratio_error=base.focal_ratio_error + float(values[0]),
            pixel_noise_std=base.pixel_noise_std + float(values[1]),
            tilt=(base.tilt[0] + float(values[2]), base.tilt[1] + float(values[3])),
            axis_offset=base.axis_offset,
        )


@dataclass(frozen=True, kw_only=True)
class CameraSpec:
    """A catadioptric camera built from the paper's presets.

    Attributes
    ----------
    mirror
        ``"A"`` or ``"B"``: the paper's hyperbolic mirrors (Section 4.2).
    non_central_offset
        On-axis shift of the pinhole from the mirror's outer focus, metres (0: central).
    imperfections
        Camera imperfections (principal-point offset, focal-ratio error, pixel noise, tilt,
        axis offset).
    imperfection_ranges
        Imperfections drawn per episode on top of ``imperfections`` (``None``: none).
    """

    mirror: Literal["A", "B"] = "A"
    non_central_offset: float = 0.0
    imperfections: Imperfections = field(default_factory=Imperfections)
    imperfection_ranges: ImperfectionRanges | None = None

    def build(self, imperfections: Imperfections | None = None) -> CatadioptricCamera:
        """Construct the camera (with ``imperfections`` instead of the spec's, if given)."""
        imperfect = self.imperfections if imperfections is None else imperfections
        return paper_camera(self.mirror, self.non_central_offset, imperfect)


def load_camera(name_or_path: str | Path, **overrides: Any) -> CameraSpec:
    """Load a camera spec by shipped name (``configs/cameras/<name>.yaml``) or from a path.

    Parameters
    ----------
    name_or_path
        A shipped config name such as ``"paper-a-noncentral"``, or a path to a YAML file.
    **overrides
        Top-level keys replacing those of the file.

    Returns
    -------
    CameraSpec
        The validated spec; call :meth:`CameraSpec.build` for the camera.

    Raises
    ------
    radial_ibvs_gym.config.ConfigError
        For an unknown name (listing the shipped ones), an unknown key or a bad value.
    """
    path = Path(name_or_path)
    if path.suffix not in (".yaml", ".yml"):
        path = config_path("cameras", str(name_or_path))
    return load_yaml(CameraSpec, path, **overrides)
