"""``radial-ibvs render``: a video (GIF, or MP4 with ffmpeg) of a policy in an env."""

from __future__ import annotations

import io
import shutil
import tempfile
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np

from radial_ibvs_agents import make_policy
from radial_ibvs_agents.io import write_atomic
from radial_ibvs_agents.rollouts import make_env, run_episode

__all__ = ["render_episode"]


def render_episode(
    policy_name: str,
    out: Path | str,
    scenario: str = "paper-sim",
    *,
    task: int | None = None,
    seed: int = 0,
    env_kwargs: Mapping[str, Any] | None = None,
    fps: int = 10,
    max_steps: int = 600,
    trust_model: bool = False,
    progress: bool = True,
) -> tuple[Path, dict[str, Any]]:
    """Run one episode with ``render_mode="rgb_array"`` and save it as a GIF or an MP4.

    Parameters
    ----------
    policy_name
        A policy name or model directory (:func:`radial_ibvs_agents.make_policy`).
    out
        ``.gif`` (always available) or ``.mp4`` (needs ``ffmpeg`` on the ``PATH``).
    scenario, task, seed, env_kwargs
        The episode.
    fps
        Frames per second of the video (one frame per control step).
    max_steps
        Step budget.
    trust_model
        Allow a model directory that holds only a pickled ``model.zip``
        (:func:`radial_ibvs_agents.learned.load`'s ``trust_pickle``).
    progress
        A progress bar over the rendered steps, then over the encoded frames.

    Returns
    -------
    tuple
        The path written and the last ``info``.

    Raises
    ------
    ValueError
        For an unknown format or policy, or ``.mp4`` without ``ffmpeg``: before running.
    """
    out = Path(out)
    suffix = out.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"--out must end in .gif or .mp4, got {out.name!r}")
    if suffix == ".mp4" and shutil.which("ffmpeg") is None:
        raise ValueError("an .mp4 needs ffmpeg on the PATH; install it or write a .gif")
    if fps <= 0 or max_steps <= 0:
        raise ValueError(f"fps and max_steps must be positive, got {fps!r}, {max_steps!r}")
    policy = make_policy(policy_name, trust_pickle=trust_model)
    overrides = {**(env_kwargs or {}), **({"task": task} if task is not None else {})}
    from tqdm.auto import tqdm

    env = make_env(policy, scenario, overrides, render_mode="rgb_array")
    bar = tqdm(total=max_steps, desc=f"render {policy_name}", unit="step", disable=not progress)
    try:
        log = run_episode(
            policy,
            _Counted(env, bar.update),
            seed=seed,
            policy_name=policy_name,
            max_steps=max_steps,
            record_frames=True,
        )
    finally:
        bar.close()
        env.close()
    frames, info = log.frames, log.info
    frames.extend([frames[-1]] * fps)  # hold the last frame for a second
    if progress:
        print(f"encoding {len(frames)} frames as {suffix[1:].upper()}...", flush=True)
    data = _gif(frames, fps) if suffix == ".gif" else _mp4(frames, fps)
    return write_atomic(out, data), info


class _Counted(gym.Wrapper):
    """Calls ``tick(1)`` at each step (the render's progress bar)."""

    def __init__(self, env: gym.Env, tick: Callable[[int], Any]) -> None:
        super().__init__(env)
        self._tick = tick

    def step(self, action: Any) -> Any:
        self._tick(1)
        return self.env.step(action)


def _gif(frames: list[np.ndarray], fps: int) -> bytes:
    from PIL import Image

    images = [Image.fromarray(frame) for frame in frames]
    buffer = io.BytesIO()
    images[0].save(
        buffer,
        format="GIF",
        save_all=True,
        append_images=images[1:],
        duration=round(1000 / fps),
        loop=0,
    )
    return buffer.getvalue()


def _mp4(frames: list[np.ndarray], fps: int) -> bytes:
    import matplotlib.pyplot as plt  # no backend forced: Agg when headless, inline in Jupyter
    from matplotlib.animation import FFMpegWriter

    h, w = frames[0].shape[:2]
    fig = plt.figure(figsize=(w / 100, h / 100), dpi=100)
    ax = fig.add_axes((0, 0, 1, 1))
    ax.set_axis_off()
    image = ax.imshow(frames[0])
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "video.mp4"
        writer = FFMpegWriter(fps=fps)
        with writer.saving(fig, str(path), dpi=100):
            for frame in frames:
                image.set_data(frame)
                writer.grab_frame()
        plt.close(fig)
        return path.read_bytes()
