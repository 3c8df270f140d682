"""The pixel pipeline on show: a rendered image with its measurement drawn, and its accuracy."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from radial_ibvs_gym.geometry import world_to_camera
from radial_ibvs_gym.scenarios import load_scenario
from radial_ibvs_gym.vision import ImageQuality, OmniRenderer
from radial_ibvs_gym.vision.detect import Measurement, measure
from radial_ibvs_gym.vision.pipeline import room_scene
from radial_ibvs_gym.vision.track import assign

__all__ = ["MeasuredImage", "detection_accuracy", "measured_image", "plot_measured"]

#: the degraded image of the figure and of the accuracy figures
DEGRADED = ImageQuality(noise_std=6.0, blur_sigma=0.8, exposure=0.7)


@dataclass(frozen=True)
class MeasuredImage:
    """A rendered image, its measurement and the truth.

    Attributes
    ----------
    image
        ``(S, S)`` uint8 image.
    measurement
        What :func:`~radial_ibvs_gym.vision.detect.measure` found.
    expected
        ``(K, 2)`` forward projections of the visible beacon centres, image pixels.
    principal_point
        ``(2,)`` true principal point, image pixels.
    pose
        ``(3,)`` robot pose, metres and radians.
    """

    image: NDArray[np.uint8]
    measurement: Measurement
    expected: NDArray[np.float64]
    principal_point: NDArray[np.float64]
    pose: NDArray[np.float64]

    def errors(self, gate: float = 3.0) -> NDArray[np.float64]:
        """Distances ``(K,)`` from each expected centre to its detection, pixels (NaN: missed)."""
        match = assign(self.expected, self.measurement.centres, gate)
        out = np.full(len(self.expected), np.nan)
        found = match >= 0
        out[found] = np.linalg.norm(
            self.measurement.centres[match[found]] - self.expected[found], axis=-1
        )
        return out


def measured_image(
    scenario: str = "paper-lab",
    seed: int = 0,
    image_size: int = 384,
    beacon_radius: float = 0.08,
    quality: ImageQuality | None = None,
    pose: NDArray[np.float64] | None = None,
    **scenario_overrides: Any,
) -> MeasuredImage:
    """Render the view from an episode's start pose (or ``pose``) and measure it.

    Parameters
    ----------
    scenario
        Scenario name or YAML path.
    seed
        Seed of the episode (room, landmarks, start pose) and of the sensor noise.
    image_size
        Side of the image, pixels.
    beacon_radius
        Beacon radius, metres.
    quality
        Image imperfections (default: none).
    pose
        ``(3,)`` robot pose ``(x, y, yaw)``, metres and radians (default: the episode's start).
    **scenario_overrides
        Passed to :func:`~radial_ibvs_gym.scenarios.load_scenario` (e.g. ``camera=...``).

    Returns
    -------
    MeasuredImage
    """
    sc = load_scenario(scenario, **scenario_overrides)
    rng = np.random.default_rng(seed)
    episode = sc.sample(rng)
    pose = episode.start if pose is None else np.asarray(pose, dtype=np.float64)
    height = episode.camera_height
    renderer = OmniRenderer(sc.camera, image_size, height)
    scene = room_scene(episode.room, episode.landmarks, beacon_radius)
    image = renderer.render(pose, scene, quality, rng)
    projection = sc.camera.forward(world_to_camera(episode.landmarks, pose, height))
    expected = renderer.sensor_to_image(projection.pixels[projection.visible])
    truth = renderer.sensor_to_image(sc.camera.true_intrinsics.principal_point)
    return MeasuredImage(image, measure(image), expected, truth, pose)


def detection_accuracy(
    scenario: str = "paper-lab",
    n_images: int = 50,
    image_size: int = 256,
    beacon_radius: float = 0.08,
    quality: ImageQuality | None = None,
) -> dict[str, float]:
    """Measure detection and calibration accuracy over ``n_images`` random start poses.

    Returns
    -------
    dict
        ``detected`` (fraction of the visible beacons found), ``spurious`` (extra blobs per
        image), ``median_px`` / ``p95_px`` / ``max_px`` (centre errors, image pixels),
        ``principal_point_px`` (largest border-centre error) and ``rho_f_error`` (largest).
    """
    errors, found, total, extra, pp, rho = [], 0, 0, 0, 0.0, 0.0
    for seed in range(n_images):
        m = measured_image(scenario, seed, image_size, beacon_radius, quality)
        e = m.errors()
        errors.extend(e[np.isfinite(e)].tolist())
        found += int(np.isfinite(e).sum())
        total += len(e)
        extra += len(m.measurement.centres) - int(np.isfinite(e).sum())
        border = m.measurement.border
        if border is not None:
            pp = max(pp, float(np.linalg.norm(border.centre - m.principal_point)))
            rho = max(rho, abs(border.rho_f - 1.0))
    err = np.asarray(errors)
    return {
        "detected": found / max(total, 1),
        "spurious": extra / n_images,
        "median_px": float(np.median(err)) if len(err) else float("nan"),
        "p95_px": float(np.percentile(err, 95)) if len(err) else float("nan"),
        "max_px": float(err.max()) if len(err) else float("nan"),
        "principal_point_px": pp,
        "rho_f_error": rho,
    }


def _draw(ax: Any, m: MeasuredImage, title: str) -> None:
    from matplotlib.patches import Ellipse

    ax.imshow(m.image, cmap="gray", vmin=0, vmax=255, interpolation="nearest")
    border = m.measurement.border
    if border is not None:
        ax.add_patch(
            Ellipse(
                tuple(border.centre),
                2 * border.semi_axes[0],
                2 * border.semi_axes[1],
                fill=False,
                color="C1",
                lw=1.2,
                label="fitted mirror border",
            )
        )
        ax.plot(*border.centre, "+", color="C1", ms=10, mew=1.5)
    ax.plot(*m.expected.T, "o", mfc="none", mec="C2", ms=9, mew=1.2, label="projected centres")
    if len(m.measurement.centres):
        ax.plot(*m.measurement.centres.T, "x", color="C3", ms=6, mew=1.5, label="detected")
    e = m.errors()
    ax.set_title(
        f"{title}\n{int(np.isfinite(e).sum())}/{len(e)} found, max error "
        f"{np.nanmax(e) if np.isfinite(e).any() else float('nan'):.2f} px",
        fontsize=9,
    )
    ax.set_axis_off()


def plot_measured(path: Path | str, scenario: str = "paper-lab", seed: int = 0) -> Path:
    """Save a figure: a clean and a degraded image with the border fit and centres drawn.

    Parameters
    ----------
    path
        Output image (PNG, PDF or SVG).
    scenario
        Scenario name.
    seed
        Episode seed (the pose is the episode's start).

    Returns
    -------
    pathlib.Path
        The written file.
    """
    from radial_ibvs_agents.plotting import pyplot, save_figure

    plt = pyplot()
    clean = measured_image(scenario, seed)
    degraded = measured_image(scenario, seed, quality=DEGRADED)
    fig, axes = plt.subplots(1, 2, figsize=(9.5, 5.2))
    _draw(axes[0], clean, f"{scenario}, 384 px, clean")
    _draw(axes[1], degraded, "noise 6 grey levels, blur 0.8 px, exposure 0.7")
    axes[0].legend(loc="lower left", fontsize=7, framealpha=0.8)
    fig.tight_layout()
    return save_figure(fig, path)
