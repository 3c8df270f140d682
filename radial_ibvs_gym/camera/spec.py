"""Camera configurations as data: the YAML files under ``configs/cameras/``."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera, Imperfections
from radial_ibvs_gym.camera.presets import paper_camera
from radial_ibvs_gym.config import config_path, load_yaml

__all__ = ["CameraSpec", "load_camera"]


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
    """

    mirror: Literal["A", "B"] = "A"
    non_central_offset: float = 0.0
    imperfections: Imperfections = field(default_factory=Imperfections)

    def build(self) -> CatadioptricCamera:
        """Construct the camera."""
        return paper_camera(self.mirror, self.non_central_offset, self.imperfections)


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
