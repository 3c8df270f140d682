"""The paper's catadioptric cameras (Section 4.2): hyperbolic mirrors A and B, a 6 mm lens.

Mirror A: ``a = 20.8485 mm, b = 26.8578 mm`` (``e = 34.0000 mm``); mirror B: ``a = 23.6634 mm,
b = 27.1301 mm`` (``e = 36.0000 mm``); both 50 mm in diameter, read as
``(x^2 + y^2)/a^2 - z^2/b^2 = -1`` (``docs/reading-the-paper.md``). The paper gives neither
the sensor nor the pixel size: we use a 1280 x 1024 sensor with 5.3 um pixels
(a common 1.3 MP machine-vision sensor, consistent with the principal point (643, 535) measured
in the paper), so
``fx = fy = 6 mm / 5.3 um = 1132.1 px``. The lens radius seen in the mirror (the blind zone) is
15 mm.

Vertical field of view (elevation of the limiting world rays, degrees;
``tests/camera/test_catadioptric.py`` recomputes them and checks this table):

======  ==================  ============================
mirror  central             non-central (pinhole +10 mm)
======  ==================  ============================
A       -77.56 to +17.61    -75.46 to +20.15
B       -78.23 to +7.89     -76.35 to +10.47
======  ==================  ============================
"""

from __future__ import annotations

from typing import Literal

from radial_ibvs_gym.camera.catadioptric import CatadioptricCamera, Imperfections
from radial_ibvs_gym.camera.mirrors import Hyperboloid
from radial_ibvs_gym.camera.pinhole import Intrinsics

__all__ = [
    "ELEVATION_RANGE_DEG",
    "LENS_FOCAL_LENGTH",
    "LENS_RADIUS",
    "MIRRORS",
    "MIRROR_A",
    "MIRROR_B",
    "PIXEL_PITCH",
    "paper_camera",
    "paper_intrinsics",
]

#: Mirror A of Section 4.2 (metres).
MIRROR_A = Hyperboloid(a=20.8485e-3, b=26.8578e-3, rim_radius=25e-3)
#: Mirror B of Section 4.2 (metres).
MIRROR_B = Hyperboloid(a=23.6634e-3, b=27.1301e-3, rim_radius=25e-3)
MIRRORS: dict[str, Hyperboloid] = {"A": MIRROR_A, "B": MIRROR_B}

LENS_FOCAL_LENGTH = 6e-3  #: metres (paper)
PIXEL_PITCH = 5.3e-6  #: metres (our choice)
SENSOR_SIZE = (1280, 1024)  #: pixels (our choice)
LENS_RADIUS = 15e-3  #: metres (our choice)

#: Measured vertical fields of view, degrees: {(mirror, non_central_offset_m): (low, high)}.
ELEVATION_RANGE_DEG: dict[tuple[str, float], tuple[float, float]] = {
    ("A", 0.0): (-77.56, 17.61),
    ("A", 0.01): (-75.46, 20.15),
    ("B", 0.0): (-78.23, 7.89),
    ("B", 0.01): (-76.35, 10.47),
}


def paper_intrinsics() -> Intrinsics:
    """Nominal intrinsics of the paper's camera: 6 mm lens, 5.3 um pixels, 1280 x 1024."""
    return Intrinsics.from_lens(LENS_FOCAL_LENGTH, PIXEL_PITCH, *SENSOR_SIZE)


def paper_camera(
    mirror: Literal["A", "B"] | str = "A",
    non_central_offset: float = 0.0,
    imperfections: Imperfections | None = None,
) -> CatadioptricCamera:
    """One of the paper's catadioptric cameras.

    Parameters
    ----------
    mirror
        ``"A"`` or ``"B"``.
    non_central_offset
        On-axis shift of the pinhole from the mirror's outer focus, metres; positive moves it
        towards the mirror. ``0`` is the central configuration.
    imperfections
        Optional camera imperfections.

    Returns
    -------
    CatadioptricCamera
        The camera, with the paper's nominal intrinsics.

    Raises
    ------
    ValueError
        For an unknown mirror name (the message lists the valid ones).
    """
    if mirror not in MIRRORS:
        raise ValueError(f"unknown mirror {mirror!r}; valid: {sorted(MIRRORS)}")
    m = MIRRORS[mirror]
    return CatadioptricCamera(
        m,
        paper_intrinsics(),
        camera_z=m.central_camera_z + float(non_central_offset),
        imperfections=imperfections,
        lens_radius=LENS_RADIUS,
    )
