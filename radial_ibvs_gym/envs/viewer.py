"""Rendering of the parking envs: the room from above beside the omnidirectional image.

matplotlib is imported lazily (only when an env renders), with the Agg canvas for
``rgb_array`` frames; the figure is built once per episode and its artists updated per frame.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from radial_ibvs_gym.geometry import world_to_camera

if TYPE_CHECKING:
    from radial_ibvs_gym.scenarios import Episode, Scenario

__all__ = ["ParkingRenderer"]


def _footprint(pose: np.ndarray, length: float, width: float) -> np.ndarray:
    """Corners ``(5, 2)`` (closed) of the robot's rectangle at ``pose``."""
    x, y, th = pose
    corners = 0.5 * np.array(
        [[length, width], [length, -width], [-length, -width], [-length, width]]
    )
    c, s = math.cos(th), math.sin(th)
    pts = corners @ np.array([[c, s], [-s, c]]) + np.array([x, y])
    return np.vstack([pts, pts[:1]])


class ParkingRenderer:
    """Draws one episode: top-down view (room, landmarks, robot, goal, trail) and the image.

    Parameters
    ----------
    scenario
        The env's scenario (its camera, height and robot size are used).
    episode
        The episode to draw.
    robot_size
        ``(length, width)`` of the robot, metres.
    """

    def __init__(
        self, scenario: Scenario, episode: Episode, robot_size: tuple[float, float]
    ) -> None:
        try:
            import matplotlib

            matplotlib.use("Agg", force=False)
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure
        except ImportError as exc:  # pragma: no cover - matplotlib is a core dependency
            raise ImportError("rendering needs matplotlib: pip install matplotlib") from exc
        self.scenario, self.episode, self.robot_size = scenario, episode, robot_size
        cam = scenario.episode_cameras(episode.mirror)[0]
        k = cam.intrinsics
        colors = matplotlib.colormaps["tab10"](np.arange(len(episode.landmarks)) % 10)
        self.figure = Figure(figsize=(10, 5), dpi=64, layout="constrained")
        self.canvas = FigureCanvasAgg(self.figure)
        top, omni = self.figure.subplots(1, 2)
        w, d = episode.room
        top.add_patch(matplotlib.patches.Rectangle((0, 0), w, d, fc="0.97", ec="k", lw=2))
        for ox, oy, radius in episode.obstacles.tolist():
            top.add_patch(matplotlib.patches.Circle((ox, oy), radius, fc="0.6", ec="0.3"))
        top.scatter(episode.landmarks[:, 0], episode.landmarks[:, 1], c=colors, s=40, zorder=3)
        goal = _footprint(episode.goal, *robot_size)
        self._trail_line = top.plot([], [], "-", color="C0", lw=1)[0]
        self._robot_line = top.plot([], [], "-", color="C3", lw=2)[0]
        self._heading = top.plot([], [], "-", color="C3", lw=2)[0]
        # the goal over the robot (dashed): still seen when the robot is parked on it
        top.plot(goal[:, 0], goal[:, 1], "--", color="C2", lw=1.5, zorder=4)
        gx, gy, gyaw = episode.goal.tolist()
        arrow = 0.6 * robot_size[0]
        top.annotate(
            "",
            (gx + arrow * math.cos(gyaw), gy + arrow * math.sin(gyaw)),
            (gx, gy),
            arrowprops={"arrowstyle": "->", "color": "C2", "lw": 1.5},
            zorder=4,
        )
        self._status = top.text(
            0.02,
            0.97,
            "",
            transform=top.transAxes,
            va="top",
            fontsize=10,
            bbox={"fc": "white", "ec": "0.7", "alpha": 0.9},
            zorder=5,
        )
        top.set_xlim(-0.5, w + 0.5)
        top.set_ylim(-0.5, d + 0.5)
        top.set_aspect("equal")
        top.set_title("room (green: goal)")
        omni.add_patch(matplotlib.patches.Rectangle((0, 0), k.width, k.height, fc="0.1"))
        phi = np.linspace(0.0, 2.0 * np.pi, 121)
        for radius, face in ((cam.visible_radius, "0.8"), (cam.blind_radius, "0.3")):
            z = float(cam.mirror.profile_z(radius)) - cam.camera_z
            ring = k.project(np.stack([np.cos(phi), np.sin(phi)], -1) * radius / z)
            omni.fill(ring[:, 0], ring[:, 1], fc=face)
        goal_px = self._pixels(episode.goal, scenario.episode_cameras(episode.mirror)[1])
        omni.scatter(goal_px[:, 0], goal_px[:, 1], c=colors, marker="x", s=50)
        self._points = omni.scatter(goal_px[:, 0], goal_px[:, 1], c=colors, s=40)
        omni.set_xlim(0, k.width)
        omni.set_ylim(k.height, 0)
        omni.set_aspect("equal")
        omni.set_axis_off()
        omni.set_title("omnidirectional image (x: goal image)")
        # the layout once (titles inside the frame), then frozen: a frame redraws no layout
        self.canvas.draw()
        self.figure.set_layout_engine("none")

    def _pixels(self, pose: np.ndarray, camera: Any) -> np.ndarray:
        p_cam = world_to_camera(self.episode.landmarks, pose, self.episode.camera_height)
        return np.asarray(camera.forward(p_cam).pixels)

    def frame(self, pose: np.ndarray, trail: list[np.ndarray], status: str = "") -> np.ndarray:
        """Draw the robot at ``pose`` with its ``trail`` (past ``(x, y)``) as ``(H, W, 3)`` RGB.

        ``status`` (e.g. the time and the errors) is written above the room.
        """
        self._status.set_text(status)
        path = np.array(trail)
        self._trail_line.set_data(path[:, 0], path[:, 1])
        body = _footprint(pose, *self.robot_size)
        self._robot_line.set_data(body[:, 0], body[:, 1])
        tip = pose[:2] + 0.6 * self.robot_size[0] * np.array([math.cos(pose[2]), math.sin(pose[2])])
        self._heading.set_data([pose[0], tip[0]], [pose[1], tip[1]])
        pixels = self._pixels(pose, self.scenario.episode_cameras(self.episode.mirror)[0])
        self._points.set_offsets(np.where(np.isfinite(pixels), pixels, -1e4))
        self.canvas.draw()
        return np.asarray(self.canvas.buffer_rgba())[..., :3].copy()
