"""The quick-start demo: the paper's scene seen through its two hyperbolic mirrors.

It projects the 8 points of eq. (39) with the exact (non-central) forward model of mirrors A
and B, from the start pose and one goal pose of the paper's parking tasks, prints the radial
invariance check (eq. 7 on the projected pixels against eq. 9 on the 3D points), and saves a
figure: the two omnidirectional images, the mirrors drawn to scale with reflected rays, and the
scene from above.
"""

from __future__ import annotations

import io
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from radial_ibvs_agents.io import write_atomic
from radial_ibvs_agents.plotting import save_figure
from radial_ibvs_gym import paper
from radial_ibvs_gym.camera import (
    CatadioptricCamera,
    invariance_errors,
    mirror_circle_pixels,
    paper_camera,
)
from radial_ibvs_gym.geometry import world_to_camera

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["invariance_error", "run_demo", "run_episode_demo"]


def invariance_error(camera: CatadioptricCamera, points_cam: np.ndarray) -> float:
    """Largest ``|x_n(eq. 7 on pixels) - x_n(eq. 9)|`` over the visible points (dimensionless).

    Parameters
    ----------
    camera
        The camera that projects the points (its nominal principal point and ``rho_f`` are used
        to normalise, as a user would).
    points_cam
        ``(N, 3)`` points in the camera frame, metres.

    Returns
    -------
    float
        The maximum error, or NaN if no point is visible.
    """
    errors, visible = invariance_errors(camera, points_cam)
    return float(np.max(errors[visible])) if visible.any() else float("nan")


def run_demo(out: Path | str, task: int = 1, non_central_offset: float = 0.01) -> Path:
    """Run the demo and save its figure.

    Parameters
    ----------
    out
        Path of the figure (the format follows the suffix). Parent folders are created.
    task
        Parking task 0..3 whose goal pose is drawn.
    non_central_offset
        On-axis shift of the pinhole from the mirror's outer focus, metres (0: central).

    Returns
    -------
    pathlib.Path
        The path written.
    """
    import matplotlib.pyplot as plt  # no backend forced: Agg when headless, inline in Jupyter

    out = Path(out)
    start, goal = np.array(paper.START_POSE), np.array(paper.goal_pose(task))
    poses = {"start": start, f"goal (task {task})": goal}
    cameras = {
        name: paper_camera(name, non_central_offset=non_central_offset) for name in ("A", "B")
    }
    print(
        f"eq. (39) scene, camera {paper.CAMERA_HEIGHT_M} m above the floor, pinhole "
        f"{1e3 * non_central_offset:+.1f} mm from the focus (non-central: "
        f"{non_central_offset != 0})"
    )
    fig, axes = plt.subplots(2, 2, figsize=(12, 10.5))
    markers = {"start": "o", f"goal (task {task})": "x"}
    colors = plt.get_cmap("tab10")(np.arange(len(paper.EQ39_POINTS)))
    for ax, (name, cam) in zip(axes[0], cameras.items(), strict=True):
        k = cam.intrinsics
        ax.add_patch(plt.Rectangle((0, 0), k.width, k.height, fc="0.15", ec="k"))
        rim = mirror_circle_pixels(cam, cam.mirror.rim_radius)
        ax.fill(rim[:, 0], rim[:, 1], fc="0.85", ec="0.4", lw=1.5, label="mirror rim")
        blind = mirror_circle_pixels(cam, cam.blind_radius)
        ax.fill(blind[:, 0], blind[:, 1], fc="0.3", ec="none", label="blind zone (lens)")
        for label, pose in poses.items():
            p_cam = world_to_camera(paper.EQ39_POINTS, pose, paper.CAMERA_HEIGHT_M)
            proj = cam.forward(p_cam)
            err = invariance_error(cam, p_cam)
            print(
                f"  mirror {name}, {label:<14}: {int(proj.visible.sum())}/{len(p_cam)} points "
                f"visible, max |x_n(eq. 7) - x_n(eq. 9)| = {err:.1e}"
            )
            ax.scatter(proj.pixels[:, 0], proj.pixels[:, 1], c=colors, marker=markers[label], s=60)
        for i, px in enumerate(
            cam.forward(world_to_camera(paper.EQ39_POINTS, start, paper.CAMERA_HEIGHT_M)).pixels
        ):
            ax.annotate(str(i + 1), px, textcoords="offset points", xytext=(5, 5), fontsize=8)
        ax.set_xlim(0, k.width)
        ax.set_ylim(k.height, 0)
        ax.set_aspect("equal")
        ax.set_title(f"mirror {name}: image of eq. (39), o start, x goal")
        ax.set_xlabel("u [px]")
        ax.set_ylabel("v [px]")
        ax.legend(loc="lower right", fontsize=8)

    _draw_mirrors(axes[1, 0], cameras, start)
    _draw_scene(axes[1, 1], poses, colors)
    fig.suptitle("radial_ibvs_gym demo: the paper's mirrors A and B (non-central)")
    fig.tight_layout()
    return save_figure(fig, out, dpi=90)


def _draw_mirrors(ax: Axes, cameras: dict[str, CatadioptricCamera], pose: np.ndarray) -> None:
    """Meridian sections of the mirrors, to scale (mm), with the rays of two scene points."""
    p_cam = world_to_camera(paper.EQ39_POINTS, pose, paper.CAMERA_HEIGHT_M)
    for (name, cam), color in zip(cameras.items(), ("C0", "C3"), strict=True):
        rho = np.linspace(-cam.mirror.rim_radius, cam.mirror.rim_radius, 201)
        z = cam.mirror.profile_z(np.abs(rho)) - cam.camera_z
        ax.plot(1e3 * rho, 1e3 * z, color=color, lw=2, label=f"mirror {name}")
        proj = cam.forward(p_cam)
        for i in (0, 4):
            if not proj.visible[i]:
                continue
            m = proj.mirror_points[i]
            r_m = np.hypot(m[0], m[1])
            # draw the ray in the meridian plane of point i (signed radius on the +rho side)
            direction = np.array([np.hypot(*p_cam[i, :2]), p_cam[i, 2]]) - np.array([r_m, m[2]])
            direction /= np.linalg.norm(direction)
            far = np.array([r_m, m[2]]) + 0.04 * direction
            ax.plot(1e3 * np.array([0.0, r_m]), 1e3 * np.array([0.0, m[2]]), color=color, lw=0.8)
            ax.plot(
                1e3 * np.array([r_m, far[0]]),
                1e3 * np.array([m[2], far[1]]),
                color=color,
                lw=0.8,
                ls="--",
            )
        ax.plot(0, 0, "k^", ms=8)
    ax.annotate("pinhole", (0, 0), textcoords="offset points", xytext=(6, -12), fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlabel("radial distance [mm]")
    ax.set_ylabel("height above the pinhole [mm]")
    ax.set_title("mirrors to scale, rays to points 1 and 5 (dashed: towards the scene)")
    ax.legend(fontsize=8)


def _draw_scene(ax: Axes, poses: dict[str, np.ndarray], colors: np.ndarray) -> None:
    """Top-down view of the eq. (39) points and the poses."""
    pts = paper.EQ39_POINTS
    ax.scatter(pts[:, 0], pts[:, 1], c=colors, s=60, zorder=3)
    for i, p in enumerate(pts):
        ax.annotate(
            f"{i + 1} (z={p[2]:.2f})", p[:2], textcoords="offset points", xytext=(5, 5), fontsize=8
        )
    for label, (x, y, yaw) in poses.items():
        ax.arrow(x, y, 0.8 * np.cos(yaw), 0.8 * np.sin(yaw), width=0.08, color="k")
        ax.annotate(label, (x, y), textcoords="offset points", xytext=(-20, -18), fontsize=9)
    ax.set_aspect("equal")
    ax.set_xlim(-1, 17)
    ax.set_ylim(-1, 17)
    ax.grid(alpha=0.3)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("scene of eq. (39) from above")


def run_episode_demo(out: Path | str, task: int = 1, seed: int = 0) -> Path:
    """Park the robot of ``RadialIBVS/Parking-v0`` (paper-sim) with the paper's IBVS; save a frame.

    The policy sees only the image points and the goal depths (``agents.IBVSPolicy``); the
    rendered frame shows the room from above with the driven path, beside the omnidirectional
    image at the end.

    Parameters
    ----------
    out
        Path of the picture (PNG).
    task
        Parking task 0..3 (goal yaw 0, 90, 180, 270 deg).
    seed
        Seed of the episode.

    Returns
    -------
    pathlib.Path
        The path written.
    """
    from PIL import Image

    from radial_ibvs_agents import IBVSPolicy
    from radial_ibvs_agents.rollouts import make_env, run_episode

    policy = IBVSPolicy()
    env = make_env(policy, "paper-sim", {"task": task}, render_mode="rgb_array")
    try:
        log = run_episode(policy, env, seed=seed, policy_name="ibvs")
        frame = np.asarray(env.render())
    finally:
        env.close()
    info, steps = log.info, log.steps
    outcome = "parked" if info["is_success"] else "did not park"
    print(
        f"the paper's IBVS, paper-sim task {task}: {outcome} in {0.1 * steps:.1f} s, position "
        f"error {100 * info['position_error_m']:.1f} cm, heading error "
        f"{info['heading_error_deg']:.2f} deg, {info['n_visible']}/8 points visible"
    )
    buffer = io.BytesIO()
    Image.fromarray(frame).save(buffer, format="PNG")
    return write_atomic(out, buffer.getvalue())
