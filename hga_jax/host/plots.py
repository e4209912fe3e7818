"""Figures: a planned path in its scene, and GA convergence over generations.

Host code on matplotlib's object API (``matplotlib.figure.Figure``, no pyplot),
so it runs headless and the figures display in notebooks. Artists carry a
``gid`` ("field", "field_inner", "obstacle", "model_circle", "turning_circle",
"start", "start_arrow", "goal", "goal_arrow", "arc", "free_arc", "line", "touched",
"optimum_path", "violation_piece", "violation_obstacle", "violation_point",
"best_median", "best_band", "mean_median", "optimum", "length_median",
"optimum_length") so callers and tests can find them. Obstacles are labelled
with their numbers, counted from 1 (docs/model.md).
"""
from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrowPatch, Rectangle

from hga_jax.model.scenario import Scenario

C_ARC, C_LINE, C_START, C_GOAL, C_TOUCH = "tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"
C_OPT, C_BAD, C_FREE = "black", "red", "tab:cyan"
PTS_PER_RAD = 60  # arc sampling density


def arc_points(center: Sequence[float], radius: float, start_angle: float, sweep: float) -> np.ndarray:
    """(m, 2) points along an arc from ``start_angle`` to ``start_angle + sweep``."""
    m = max(2, int(np.ceil(abs(sweep) * PTS_PER_RAD)) + 1)
    t = start_angle + sweep * np.linspace(0.0, 1.0, m)
    return np.asarray(center, float) + radius * np.stack([np.cos(t), np.sin(t)], axis=1)


def _pose(ax: Axes, pose: Sequence[float], circles: Iterable[Sequence[float]], colour: str,
          name: str, span: float) -> np.ndarray:
    """Draw a pose arrow and its turning circles ``(x, y, r)`` (from
    :meth:`Scenario.circles`); return the circles' bbox corners."""
    x, y, th = (float(v) for v in pose)
    circles = [tuple(float(v) for v in c) for c in circles]
    ax.plot([x], [y], "o", color=colour, ms=5, zorder=6, gid=name, label=name)
    size = max(0.07 * span, 0.6 * max(c[2] for c in circles))
    tip = (x + size * np.cos(th), y + size * np.sin(th))
    ax.add_patch(FancyArrowPatch((x, y), tip, arrowstyle="-|>", mutation_scale=14, lw=1.8,
                                 color=colour, shrinkA=0, shrinkB=0, zorder=6, gid=name + "_arrow"))
    ends = []
    for cx, cy, rho in circles:
        ax.add_patch(Circle((cx, cy), rho, fill=False, ls=":", lw=0.8, ec=colour,
                            gid="turning_circle"))
        ends += [(cx - rho, cy - rho), (cx + rho, cy + rho)]
    return np.asarray(ends)


def segment_points(seg: Mapping[str, Any]) -> np.ndarray:
    """(m, 2) points along one segment of the result-file format (metres)."""
    if seg["type"] == "arc":
        return arc_points(seg["center"], float(seg["radius"]), float(seg["start_angle"]),
                          float(seg["sweep"]))
    if seg["type"] == "line":
        return np.asarray([seg["start"], seg["end"]], float)
    raise ValueError(f"unknown segment type {seg['type']!r}")


def _touches(touched: Iterable[Any], n: int) -> dict[int, int]:
    """``touched`` -> {obstacle index from 0: label}.

    Items are the result files' ``{"obstacle": number from 1, "label": +1 | -1}`` or
    ``(number from 1, label)`` pairs (``Path.touched``, ``ExactResult.touched``).
    """
    out = {}
    for item in touched:
        if isinstance(item, Mapping) and set(item) == {"obstacle", "label"}:
            k, label = int(item["obstacle"]) - 1, int(item["label"])
        elif not isinstance(item, (Mapping, str)) and len(item) == 2:
            k, label = int(item[0]) - 1, int(item[1])
        else:
            raise TypeError("touched: items must be {'obstacle': number from 1, 'label': +1 "
                            f"or -1}} as in result.json, or (number from 1, label), got {item!r}")
        if not 0 <= k < n:
            raise ValueError(f"touched: obstacle must be in 1..{n}, got number {k + 1}")
        out[k] = label
    return out


def _closest(xy: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The point of the polyline ``xy`` (m, 2) closest to ``q`` (2,)."""
    a, b = xy[:-1], xy[1:]
    v = b - a
    vv = np.maximum(np.einsum("ij,ij->i", v, v), 1e-300)
    t = np.clip(np.einsum("ij,ij->i", q - a, v) / vv, 0.0, 1.0)
    p = a + t[:, None] * v
    return p[np.argmin(np.hypot(*(p - q).T))]


def plot_path(scenario: Scenario, segments: Sequence[Mapping[str, Any]], *,
              touched: Iterable[Any] = (), title: str | None = None,
              ax: Axes | None = None, optimum: Sequence[Mapping[str, Any]] | None = None,
              violations_at: Iterable[Mapping[str, Any]] = ()) -> Figure:
    """Draw the scene (field, obstacles, start and goal poses) and a path.

    ``segments``: travel-ordered arc/line dicts of the result-file format
    (docs/model.md); may be empty. ``touched``: the result files' items
    ``{"obstacle": number from 1, "label": +1 CW / -1 CCW}`` (``best["touched"]`` of
    a result.json) or ``(number from 1, label)`` pairs (``Path.touched``), highlighted
    on the picture.
    ``optimum``: another segment list (the exact optimum) drawn dashed over the
    path. ``violations_at``: ``Path.violations_at`` items; each offending piece is
    redrawn in red, each obstacle it meets gets a red model circle and a cross at
    the piece's point closest to its centre.
    """
    if ax is None:
        fig = Figure(figsize=(8.0, 5.6), layout="constrained")
        ax = fig.add_subplot()
    else:
        fig = ax.figure
    f = scenario.field
    centres = np.asarray(scenario.centres, float).reshape(-1, 2)
    radii, model = np.asarray(scenario.radii, float), np.asarray(scenario.model_radii, float)
    pts = [np.asarray([scenario.start[:2], scenario.goal[:2]], float)]
    if f is not None:
        ax.add_patch(Rectangle((f.xmin, f.ymin), f.xmax - f.xmin, f.ymax - f.ymin,
                               fill=False, ec="black", lw=1.2, gid="field"))
        if f.keep_inside:  # the box every path point must stay within
            x0, x1, y0, y1 = scenario.bounds
            ax.add_patch(Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, ec="0.4", lw=0.8,
                                   ls="-.", gid="field_inner"))
        pts.append(np.asarray([[f.xmin, f.ymin], [f.xmax, f.ymax]]))
    touch = _touches(touched, scenario.n)
    for i, (c, ri, Ri) in enumerate(zip(centres, radii, model)):
        hit = i in touch
        ax.add_patch(Circle(c, ri, fc="0.86", ec="0.55", lw=0.8, zorder=2, gid="obstacle"))
        ax.add_patch(Circle(c, Ri, fill=False, ls="-" if hit else "--", lw=2.0 if hit else 0.8,
                            ec=C_TOUCH if hit else "0.45", zorder=3, gid="model_circle"))
        ax.text(c[0], c[1], str(i + 1), ha="center", va="center", fontsize=8, zorder=4,
                color=C_TOUCH if hit else "black", fontweight="bold" if hit else "normal")
        if hit:  # tag in the ring between body and model circle, which the path never enters
            ax.text(c[0], c[1] - 0.5 * (ri + Ri), "CW" if touch[i] > 0 else "CCW", color=C_TOUCH,
                    fontsize=6, fontweight="bold", ha="center", va="center", zorder=7, gid="touched")
        pts.append(np.asarray([c - Ri, c + Ri]))
    span0 = np.ptp(np.concatenate(pts), axis=0).max() if len(pts) > 1 else 1.0
    span = float(span0) if span0 > 0 else 1.0
    turning = list(zip(*scenario.circles(np.float64)[:3]))  # start CCW, CW, goal CCW, CW
    pts.append(_pose(ax, scenario.start, turning[0:2], C_START, "start", span))
    pts.append(_pose(ax, scenario.goal, turning[2:4], C_GOAL, "goal", span))
    kinds_seen: set[str] = set()
    drawn = []
    for seg in segments:
        xy = segment_points(seg)
        kind = "free arc" if seg.get("free") else seg["type"]
        style = (dict(color=C_ARC, lw=2.6, solid_capstyle="round") if kind == "arc"
                 else dict(color=C_FREE, lw=2.6, ls=(0, (2, 1)), solid_capstyle="round")
                 if kind == "free arc" else dict(color=C_LINE, lw=2.0))
        label = "_nolegend_" if kind in kinds_seen else (
            "free turn (radius $\\rho$)" if kind == "free arc" else f"path {kind}")
        kinds_seen.add(kind)
        ax.plot(xy[:, 0], xy[:, 1], zorder=5, gid=kind.replace(" ", "_"), label=label, **style)
        pts.append(xy)
        drawn.append(xy)
    if optimum is not None:
        label = "optimum"
        for seg in optimum:
            xy = segment_points(seg)
            ax.plot(xy[:, 0], xy[:, 1], color=C_OPT, lw=1.2, ls="--", zorder=8,
                    gid="optimum_path", label=label)
            label = "_nolegend_"
            pts.append(xy)
    _violations(ax, list(violations_at), drawn, centres, model)
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 0.03 * float(max(hi - lo))
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(scenario.name if title is None else title)
    handles = [Line2D([], [], marker="o", ls="", mfc="0.86", mec="0.55", ms=9, label="obstacle (robot)"),
               Line2D([], [], ls="--", color="0.45", lw=0.8, label="model circle"),
               Line2D([], [], ls=":", color="0.3", lw=0.8, label=r"turning circles ($\rho$)")]
    if touch:
        handles.append(Line2D([], [], color=C_TOUCH, lw=2.0, label="touched (CW/CCW)"))
    if f is not None:
        handles.append(Line2D([], [], color="black", lw=1.2, label="field"))
        if f.keep_inside:
            handles.append(Line2D([], [], color="0.4", lw=0.8, ls="-.", label="field shrunk by r"))
    h, _ = ax.get_legend_handles_labels()
    ax.legend(handles=h + handles, loc="upper left", bbox_to_anchor=(1.02, 1.0),
              fontsize=8, frameon=False)
    return fig


def _violations(ax: Axes, where: list[Mapping[str, Any]], drawn: list[np.ndarray],
                centres: np.ndarray, model: np.ndarray) -> None:
    """Mark each violation: the piece in red; an obstacle's model circle and the
    piece's point closest to its centre (a cross)."""
    label = "violation: piece"
    for v in where:
        seg = v.get("segment")
        if seg is None:
            continue
        xy = drawn[seg]
        ax.plot(xy[:, 0], xy[:, 1], color=C_BAD, lw=3.4, alpha=0.75, zorder=6,
                gid="violation_piece", label=label)
        label = "_nolegend_"
        if v.get("kind") == "obstacle":
            k = int(v["obstacle"]) - 1
            p = _closest(xy, centres[k])
            ax.plot([p[0]], [p[1]], "x", color=C_BAD, ms=9, mew=2.2, zorder=9,
                    gid="violation_point")
    label = "violation: obstacle met"
    for k in sorted({int(v["obstacle"]) - 1 for v in where if v.get("kind") == "obstacle"}):
        ax.add_patch(Circle(centres[k], model[k], fill=False, ec=C_BAD, lw=2.0, zorder=4,
                            gid="violation_obstacle", label=label))
        label = "_nolegend_"


def _band(ax: Axes, gens: np.ndarray, data: np.ndarray, colour: str, label: str, gid: str) -> None:
    """Median over runs (line) and interquartile band of a (G+1, runs) array."""
    q1, med, q3 = np.percentile(data, [25, 50, 75], axis=1)
    ax.fill_between(gens, q1, q3, color=colour, alpha=0.22, lw=0, gid=gid + "_band")
    ax.plot(gens, med, color=colour, lw=1.8, label=label, gid=gid + "_median")


def headroom(ax: Any, y: float, share: float = 0.08) -> None:
    """Keep a horizontal line at ``y`` off the frame: widen the y range to leave
    ``share`` of it on the far side of ``y``."""
    lo, hi = ax.get_ylim()
    span = (hi - lo) or abs(y) or 1.0
    if y >= hi - 0.02 * span:
        ax.set_ylim(lo, y + share * span)
    if y <= lo + 0.02 * span:
        ax.set_ylim(y - share * span, ax.get_ylim()[1])


def plot_convergence(best_fitness: np.ndarray, mean_fitness: np.ndarray, *,
                     optimum_fitness: float | None = None, best_length: np.ndarray | None = None,
                     optimum_length: float | None = None, title: str | None = None,
                     length_label: str = "best path length (m)",
                     reached: dict[str, np.ndarray] | None = None,
                     population: int | None = None) -> Figure:
    """Fitness over generation (paper Fig. 5) from arrays shaped (G+1, runs).

    Row ``g`` is generation ``g`` (0 = initial population). Draws the median
    over runs and the interquartile band of the best and the mean fitness, the
    optimum's fitness as a line when given, and, when ``best_length`` is given,
    a second panel of the best-so-far path length against the optimum length
    (``length_label`` names its axis). ``reached`` (label -> per run the first
    generation it got there, -1 never) adds a panel of the share of runs there by
    each number of evaluations (``population`` per generation), on a log axis: it
    still tells a story when every run finds the optimum in generation 0.
    """
    best = np.asarray(best_fitness, float).reshape(len(best_fitness), -1)
    mean = np.asarray(mean_fitness, float).reshape(len(mean_fitness), -1)
    runs, gens = best.shape[1], np.arange(best.shape[0])
    what = "median, IQR over %d runs" % runs if runs > 1 else "1 run"
    count = 1 + (best_length is not None) + (reached is not None)
    fig = Figure(figsize=(3.6 + 3.4 * (count - 1) if count > 1 else 6.0, 3.8),
                 layout="constrained")
    axes = fig.subplots(1, count, squeeze=False)[0]
    two = best_length is not None
    ax = axes[0]
    _band(ax, gens, best, C_ARC, f"best fitness ({what})", "best")
    _band(ax, gens, mean, C_LINE, f"mean fitness ({what})", "mean")
    if optimum_fitness is not None:
        ax.axhline(float(optimum_fitness), color="black", ls="--", lw=1.0,
                   label="optimum", gid="optimum")
        headroom(ax, float(optimum_fitness))
    ax.set_xlabel("generation")
    ax.set_ylabel("fitness  10000 / (Dist$_m$ + 1)")
    ax.set_xlim(gens[0], max(gens[-1], 1))
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    if two:
        ax2 = axes[1]
        length = np.asarray(best_length, float).reshape(len(best_length), -1)
        _band(ax2, gens, length, C_ARC, f"best so far ({what})", "length")
        if optimum_length is not None:
            ax2.axhline(float(optimum_length), color="black", ls="--", lw=1.0,
                        label="optimum length", gid="optimum_length")
            headroom(ax2, float(optimum_length))
        ax2.set_xlabel("generation")
        ax2.set_ylabel(length_label)
        ax2.set_xlim(gens[0], max(gens[-1], 1))
        ax2.grid(alpha=0.3)
        ax2.legend(fontsize=8, loc="best")
    if reached is not None:
        ax3 = axes[-1]
        pop = population or 1
        evals = pop * (gens + 1)
        for (label, first), colour, ls in zip(reached.items(), (C_LINE, C_ARC, "tab:green"),
                                              ("-", "--", ":")):
            first = np.asarray(first)
            share = [100 * np.mean((first >= 0) & (first <= g)) for g in gens]
            ax3.step(evals, share, where="post", color=colour, ls=ls, label=label,
                     gid=f"reached_{label}")
        ax3.set_xscale("log")
        ax3.set_ylim(-3, 103)
        ax3.set_xlabel(f"evaluations ({pop} per generation)")
        ax3.set_ylabel("runs there (%)")
        ax3.grid(alpha=0.3)
        ax3.legend(fontsize=8, loc="lower right")
    if title is not None:
        fig.suptitle(title, fontsize=9)
    return fig


def save_figure(fig: Figure, path: str | Path, dpi: int = 140, vector: bool = False) -> Path:
    """Write ``fig`` as PNG to ``path`` atomically (parents created); return the path.
    ``vector``: also a PDF beside it (same name, ``.pdf``), for a paper's figures."""
    from .output import atomic_write, figure_writer

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write(str(path), figure_writer(fig, dpi), binary=True)
    if vector:
        atomic_write(str(path.with_suffix(".pdf")), figure_writer(fig, dpi, "pdf"), binary=True)
    return path
