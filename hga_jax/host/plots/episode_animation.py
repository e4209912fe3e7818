"""An episode as an animation (GIF): the robots, their predicted tracks, the car's trail and plan.

Every ``every``-th frame of an :class:`~hga_jax.loop.episode.Episode` is drawn: each robot's
body where it truly is (numbered from 1 as in the scene) with a dashed line along its
velocity over the next :data:`PREDICT` seconds (what a planner predicts), the car's body
and heading, the way it has driven so far, and the plan it drives in that frame; the title
gives the time, the planner and the plan's status. The last image shows the outcome (a
contact marked by a cross). Written with matplotlib's Pillow writer (matplotlib's own
dependency). Artists' ``gid``: "robot", "robot_track", "car", "trail", "plan".
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from hga_jax.host.poses import at as poses_at
from hga_jax.model.path import segments_length

PREDICT = 1.0
"""Seconds of each robot's predicted track drawn ahead of it."""


def _plan_xy(segments, spacing: float = 0.02):
    if not segments:
        return np.zeros(0), np.zeros(0)
    total = segments_length(segments)
    u = np.linspace(0.0, total, max(2, int(total / spacing) + 1))
    p = poses_at(segments, u)
    return p[:, 0], p[:, 1]


def animate(ep: Any, plans: list, path: str, box=None, every: int = 6, fps: int = 10) -> int:
    """Write ``ep`` (with the plan of each frame, ``plans``) to the GIF ``path``: one image
    every ``every`` frames and the last; ``box`` ``(xmin, xmax, ymin, ymax)`` the field or
    None. Returns the number of images."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.animation import FuncAnimation, PillowWriter
    from matplotlib.patches import Circle, Rectangle

    frames = ep.frames
    shown = list(range(0, len(frames), max(1, int(every))))
    if shown[-1] != len(frames) - 1:
        shown.append(len(frames) - 1)
    ego = np.array([f["ego"] for f in frames])
    robots = [np.asarray(f["obstacles"], float).reshape(-1, 5) for f in frames]
    xs = np.concatenate([ego[:, 0]] + [r[:, 0] for r in robots] + [[ep.goal[0]]])
    ys = np.concatenate([ego[:, 1]] + [r[:, 1] for r in robots] + [[ep.goal[1]]])
    if box is not None and all(np.isfinite(box)):
        lim = (box[0], box[1], box[2], box[3])
    else:
        lim = (xs.min() - 0.4, xs.max() + 0.4, ys.min() - 0.4, ys.max() + 0.4)
    fig, ax = plt.subplots(figsize=(6.4, 6.4 * (lim[3] - lim[2]) / max(lim[1] - lim[0], 1e-9)
                                    if lim[1] > lim[0] else 4.8))
    r_car = ep.car.radius

    def draw(k: int):
        ax.clear()
        ax.set_xlim(lim[0], lim[1])
        ax.set_ylim(lim[2], lim[3])
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        if box is not None and all(np.isfinite(box)):
            ax.add_patch(Rectangle((box[0], box[2]), box[1] - box[0], box[3] - box[2],
                                   fill=False, lw=1.0, color="0.4"))
        gx, gy, gh = ep.goal
        ax.annotate("", (gx + 0.15 * math.cos(gh), gy + 0.15 * math.sin(gh)), (gx, gy),
                    arrowprops={"arrowstyle": "->", "color": "tab:green", "lw": 1.5})
        f = frames[k]
        for j, (x, y, vx, vy, r) in enumerate(robots[k]):
            ax.add_patch(Circle((x, y), r, color="tab:brown", alpha=0.6, gid="robot"))
            ax.plot([x, x + vx * PREDICT], [y, y + vy * PREDICT], ls="--", lw=0.8,
                    color="tab:brown", gid="robot_track")
            ax.text(x, y, str(j + 1), ha="center", va="center", fontsize=7)
        ax.plot(ego[:k + 1, 0], ego[:k + 1, 1], color="0.3", lw=1.2, gid="trail")
        px, py = _plan_xy(plans[k] if k < len(plans) else None)
        ax.plot(px, py, color="tab:blue", lw=1.0, gid="plan")
        x, y, h = f["ego"][:3]
        ax.add_patch(Circle((x, y), r_car, fill=False, color="tab:blue", lw=1.5, gid="car"))
        ax.plot([x, x + 1.5 * r_car * math.cos(h)], [y, y + 1.5 * r_car * math.sin(h)],
                color="tab:blue", lw=1.5)
        last = k == len(frames) - 1
        if last and ep.contact is not None:
            ax.plot([x], [y], marker="x", color="tab:red", ms=12, mew=2)
        status = f"{ep.outcome} at {ep.time:.2f} s" if last else f.get("status", "")
        ax.set_title(f"t = {f['t']:.2f} s, {ep.planner}: {status}", fontsize=9)
        return []

    anim = FuncAnimation(fig, draw, frames=shown, blit=False)
    anim.save(path, writer=PillowWriter(fps=fps))
    plt.close(fig)
    return len(shown)
