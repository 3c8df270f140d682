"""Catadioptric camera models and the radial model (paper Section 2; pure numpy).

- :mod:`.pinhole`: intrinsics ``K`` (eq. 2-3);
- :mod:`.mirrors`: quadric mirrors of revolution (hyperboloid, ellipsoid, paraboloid, sphere,
  cone);
- :mod:`.catadioptric`: exact forward/backward projection, central and non-central,
  visibility and imperfections;
- :mod:`.batch`: the exact projection of many cameras' points at once (one mirror, per-camera
  intrinsics and noise);
- :mod:`.radial`: the radial model, pixels or 3D points to the unit circle (eq. 4-9);
- :mod:`.presets`: the paper's mirrors A and B with a 6 mm lens;
- :mod:`.spec`: camera configs loaded from ``configs/cameras/*.yaml``;
- :mod:`.measurement`: normalised image points as an imperfect, calibrated camera measures
  them (eq. 7 with the nominal calibration);
- :mod:`.diagnostics`: eq. (7) on projected pixels against eq. (9), the mirror's circles in
  the image.
"""

from radial_ibvs_gym.camera.batch import forward_batch, shares_reflection
from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera, Imperfections, Projection
from radial_ibvs_gym.camera.diagnostics import invariance_errors, mirror_circle_pixels
from radial_ibvs_gym.camera.measurement import camera_image, camera_images
from radial_ibvs_gym.camera.mirrors import (
    Cone,
    Ellipsoid,
    Hyperboloid,
    Paraboloid,
    QuadricMirror,
    Sphere,
)
from radial_ibvs_gym.camera.pinhole import Intrinsics
from radial_ibvs_gym.camera.presets import MIRROR_A, MIRROR_B, paper_camera, paper_intrinsics
from radial_ibvs_gym.camera.radial import RadialPoints, normalise_pixels, radial_points
from radial_ibvs_gym.camera.spec import CameraSpec, ImperfectionRanges, load_camera

__all__ = [
    "MIRROR_A",
    "MIRROR_B",
    "CameraSpec",
    "CatadioptricCamera",
    "Cone",
    "Ellipsoid",
    "Hyperboloid",
    "ImperfectionRanges",
    "Imperfections",
    "Intrinsics",
    "Paraboloid",
    "Projection",
    "QuadricMirror",
    "RadialPoints",
    "Sphere",
    "camera_image",
    "camera_images",
    "forward_batch",
    "invariance_errors",
    "load_camera",
    "mirror_circle_pixels",
    "normalise_pixels",
    "paper_camera",
    "paper_intrinsics",
    "radial_points",
    "shares_reflection",
]
