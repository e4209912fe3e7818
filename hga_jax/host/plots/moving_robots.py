"""Robots that move, in a path figure (docs/model.md, "Moving robots").

The car drives its path at the scenario's constant speed from time 0, and robot ``j``'s
centre at time ``t`` is ``O_j + t V_j``. A moving robot is drawn where it is when the
car passes closest (:func:`hga_jax.model.in_time.clearance.closest_approach`): its body as a
solid disc and its model circle, in :data:`C_MOVING`, numbered as the other
obstacles; its model circle solid in the violation colour when it meets the car
(clearance < 0), with a cross at the car's point then. Beside it: its track over the
path's duration (a faint line from its centre at time 0 to its centre when the car
reaches the goal), its body at time 0 as a faint outline, an arrow along its velocity,
and the car's point at the moment of closest approach. Time marks along the path
(a tick and a label every :func:`mark_step` seconds) tell where the car is when.

Artists' ``gid``: "moving_robot" (the disc; its centre is the closest-approach
centre), "moving_model_circle", "moving_track", "moving_start", "moving_velocity",
"moving_car", "moving_gap" (from the car's point to the robot's body then),
"moving_collision", "time_mark" (one tick per mark, its point the
car's at that time) and "time_label". A scene where nothing moves draws none of them.
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from matplotlib.axes import Axes
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrowPatch
from matplotlib.text import Text

from hga_jax.model.in_time import clearance
from hga_jax.model.scenario import Scenario
from .labels import _box_at, _into_disc, _overlap, _renderer, _within
from .style import C_BAD

C_MOVING = "tab:brown"  # a moving robot: edges, track, arrow
C_MOVING_FILL = "#ead8cc"  # its body (light, so that its number reads in black)
C_TIME = "0.2"  # time marks along the path
STEPS = (1.0, 2.0, 2.5, 5.0)  # nice intervals between time marks, times a power of 10
MAX_MARKS = 10  # at most this many time marks (the smallest nice step that keeps to it)
MAX_NAMED = 4  # robots named one by one in the legend; more share one entry
__all__ = ["C_MOVING", "Drawn", "TimeMarks", "draw_robots", "draw_time_marks", "mark_step",
           "mark_times", "place_time_labels", "point_at"]


def mark_step(duration: float) -> float:
    """The interval between time marks (s): the smallest of 1, 2, 2.5, 5 times a power
    of 10 that leaves at most :data:`MAX_MARKS` marks strictly inside ``(0, duration)``
    (so at least 4 for any duration > 0: the next smaller step left more than 10)."""
    if not (duration > 0 and math.isfinite(duration)):
        return math.inf
    power = 10.0 ** math.floor(math.log10(duration / MAX_MARKS))
    for scale in (power, 10 * power):
        for s in STEPS:
            step = s * scale
            if len(mark_times(duration, step)) <= MAX_MARKS:
                return step
    return 100 * power  # not reached


def mark_times(duration: float, step: float | None = None) -> list[float]:
    """The times of the marks along a path of ``duration`` seconds: the multiples of
    ``step`` (default :func:`mark_step`) strictly between 0 and ``duration`` (a mark at
    the goal would sit on the goal's marker)."""
    step = mark_step(duration) if step is None else step
    if not math.isfinite(step):
        return []
    out, k = [], 1
    while True:
        t = round(k * step, 12)
        if t >= duration - 1e-9 * max(1.0, duration):
            return out
        out.append(t)
        k += 1


def point_at(segments: Sequence[Mapping[str, Any]], speed: float,
             t: float) -> tuple[float, float, float]:
    """The car's point ``(x, y)`` at time ``t`` along the path and the direction of
    travel there (radians); the path's end after its duration."""
    timed = clearance.timed(segments, speed)
    if not timed:
        raise ValueError("point_at: the path has no segment")
    seg = timed[-1]
    for ts in timed:
        if t <= ts.t1:
            seg = ts
            break
    u = 0.0 if seg.t1 <= seg.t0 else min(1.0, max(0.0, (t - seg.t0) / (seg.t1 - seg.t0)))
    s = seg.segment
    if s["type"] == "line":
        (x0, y0), (x1, y1) = s["start"], s["end"]
        return x0 + u * (x1 - x0), y0 + u * (y1 - y0), math.atan2(y1 - y0, x1 - x0)
    (cx, cy), r, sweep = s["center"], float(s["radius"]), float(s["sweep"])
    a = float(s["start_angle"]) + sweep * u
    return (cx + r * math.cos(a), cy + r * math.sin(a),
            a + math.copysign(math.pi / 2, sweep if sweep else 1.0))


class Drawn(NamedTuple):
    """What :func:`draw_robots` drew, for the path figure: ``numbers`` {obstacle index
    from 0: its number's text}; ``centres`` (n, 2) where each obstacle's number stands
    (a moving robot's centre at its closest approach); ``points`` to keep in view;
    ``crosses`` (the collision marks, which numbers keep off); ``handles`` for the
    legend."""

    numbers: dict[int, Text]
    centres: np.ndarray
    points: list[np.ndarray]
    crosses: list[Line2D]
    handles: list[Line2D]


def duration(scenario: Scenario, segments: Sequence[Mapping[str, Any]]) -> float:
    """The time the car takes to drive ``segments`` (s)."""
    timed = clearance.timed(segments, float(scenario.speed))
    return timed[-1].t1 if timed else 0.0


def draw_robots(ax: Axes, scenario: Scenario, segments: Sequence[Mapping[str, Any]],
                span: float) -> Drawn:
    """Draw each moving robot of ``scenario`` against the path ``segments`` (module
    doc). ``span``: the scene's size (m), which sizes the velocity arrows."""
    centres = np.asarray(scenario.centres, float).reshape(-1, 2).copy()
    radii, model = np.asarray(scenario.radii, float), np.asarray(scenario.model_radii, float)
    vel = np.asarray(scenario.velocities, float).reshape(-1, 2) if scenario.has_motion else None
    end = duration(scenario, segments)
    found = clearance.closest_approach(scenario, segments, start=scenario.start[:2])
    numbers, points, crosses = {}, [], []
    named: list[Line2D] = []
    hits = 0
    arrow = 0.07 * span
    for a in found:
        k = a.obstacle
        o, v, c = centres[k].copy(), vel[k], np.asarray(a.centre, float)
        hit = a.clearance < 0
        hits += hit
        last = o + end * v
        if end > 0:
            ax.plot([o[0], last[0]], [o[1], last[1]], color=C_MOVING, lw=1.0, alpha=0.45,
                    ls="-", zorder=1.5, gid="moving_track", solid_capstyle="butt")
        ax.add_patch(Circle(o, radii[k], fill=False, ec=C_MOVING, lw=0.8, alpha=0.5, ls="-",
                            zorder=1.6, gid="moving_start"))
        ax.add_patch(Circle(c, radii[k], fc=C_MOVING_FILL, ec=C_MOVING, lw=1.0, zorder=2.2,
                            gid="moving_robot"))
        ax.add_patch(Circle(c, model[k], fill=False, ls="-" if hit else "--",
                            lw=2.0 if hit else 0.9, ec=C_BAD if hit else C_MOVING, zorder=3.5,
                            gid="moving_model_circle"))
        speed = float(np.hypot(*v))
        u = v / speed
        tail = c + model[k] * u
        tip = tail + arrow * u
        ax.add_patch(FancyArrowPatch(tuple(tail), tuple(tip), arrowstyle="-|>",
                                     mutation_scale=10, lw=1.3, color=C_MOVING, shrinkA=0,
                                     shrinkB=0, zorder=4, gid="moving_velocity"))
        if a.distance > radii[k]:  # which robot the car's point belongs to
            edge = c + radii[k] * (np.asarray(a.car) - c) / a.distance
            ax.plot([a.car[0], edge[0]], [a.car[1], edge[1]], color=C_MOVING, lw=0.8,
                    ls=(0, (1, 1.5)), zorder=4, gid="moving_gap")
        ax.plot([a.car[0]], [a.car[1]], "o", ms=4.5, mfc="white", mec=C_BAD if hit else C_MOVING,
                mew=1.2, zorder=8, gid="moving_car")
        if hit:
            crosses += ax.plot([a.car[0]], [a.car[1]], "x", color=C_BAD, ms=9, mew=2.2,
                               zorder=9, gid="moving_collision")
        numbers[k] = ax.text(c[0], c[1], str(k + 1), ha="center", va="center", fontsize=8,
                             zorder=10, color="black", gid="obstacle_number")
        centres[k] = c
        for p in (o, last, c):
            points.append(np.asarray([p - model[k], p + model[k]]))
        points.append(np.asarray([tip]))
        what = (f"robot {k + 1} at closest approach\n(t = {a.time:.2f} s, {speed:.3g} m/s)"
                + (": collision" if hit else ""))
        named.append(Line2D([], [], marker="o", ls="", mfc=C_MOVING_FILL, ms=9,
                            mec=C_BAD if hit else C_MOVING, mew=2.0 if hit else 1.0,
                            label=what))
    if not found:
        return Drawn(numbers, centres, points, crosses, [])
    if len(named) > MAX_NAMED:  # one entry: the times are too many to list
        named = [Line2D([], [], marker="o", ls="", mfc=C_MOVING_FILL, mec=C_MOVING, ms=9,
                        label="moving robot at its closest approach to the car")]
        if hits:
            named.append(Line2D([], [], marker="o", ls="", mfc=C_MOVING_FILL, mec=C_BAD,
                                mew=2.0, ms=9, label="moving robot that meets the car"))
    track = [Line2D([], [], color=C_MOVING, lw=1.0, alpha=0.45,
                    label=f"track over the path's duration\n(t = 0 to {end:.2f} s)")]
    handles = named + track[:end > 0] + [
        Line2D([], [], marker="o", ls="", mfc="none", mec=C_MOVING, alpha=0.5, ms=9,
               label="moving robot at t = 0"),
        Line2D([], [], marker=r"$\rightarrow$", ls="", color=C_MOVING, ms=11,
               label="direction of motion"),
        Line2D([], [], marker="o", ls="", mfc="white", mec=C_MOVING, mew=1.2, ms=4.5,
               label="car at closest approach\n(dotted: to its robot)"),
    ]
    if hits:
        handles.append(Line2D([], [], marker="x", ls="", color=C_BAD, ms=8, mew=2.0,
                              label="collision in time"))
    return Drawn(numbers, centres, points, crosses, handles)


class TimeMarks(NamedTuple):
    """What :func:`draw_time_marks` drew: the ticks and labels (one per mark), where
    each tick stands (``points`` (m, 2) on the path, ``normals`` (m, 2) unit vectors
    across it, data coordinates), the tick's half length (m) and the legend's handles."""

    ticks: list[Line2D]
    labels: list[Text]
    points: np.ndarray
    normals: np.ndarray
    half: float
    handles: list[Line2D]


def draw_time_marks(ax: Axes, scenario: Scenario, segments: Sequence[Mapping[str, Any]],
                    span: float) -> TimeMarks:
    """A tick across the path and a label every :func:`mark_step` seconds of the car's
    drive (``span``: the scene's size, m, which sizes the ticks). The labels stand left
    of the path until :func:`place_time_labels` places them."""
    end = duration(scenario, segments)
    times = mark_times(end)
    if not times:
        return TimeMarks([], [], np.zeros((0, 2)), np.zeros((0, 2)), 0.0, [])
    step = mark_step(end)
    half = 0.012 * span
    ticks, labels, points, normals = [], [], [], []
    digits = 0  # as many decimals as the step has: 0.5 s, 1.0 s, 1.5 s
    while digits < 9 and abs(step * 10 ** digits - round(step * 10 ** digits)) > 1e-6:
        digits += 1
    for t in times:
        x, y, a = point_at(segments, float(scenario.speed), t)
        n = np.array([-math.sin(a), math.cos(a)])  # left of travel
        ticks += ax.plot([x - half * n[0], x + half * n[0]], [y - half * n[1], y + half * n[1]],
                         color=C_TIME, lw=1.1, zorder=7, gid="time_mark",
                         solid_capstyle="butt")
        q = np.array([x, y]) + 2 * half * n
        labels.append(ax.text(q[0], q[1], f"{t:.{digits}f} s", fontsize=6.5, color=C_TIME,
                              ha="center", va="center", zorder=10, gid="time_label",
                              bbox=dict(boxstyle="square,pad=0.05", fc="white", ec="none",
                                        alpha=0.7)))
        labels[-1].set_in_layout(False)  # inside the view: nothing for the layout
        points.append((x, y))
        normals.append(n)
    handle = Line2D([], [], marker="|", ls="", color=C_TIME, ms=7, mew=1.1,
                    label=f"time along the path (every {step:g} s,\ncar at {scenario.speed:g} m/s)")
    return TimeMarks(ticks, labels, np.asarray(points), np.asarray(normals), half, [handle])


LABEL_GAP_PT = 1.5  # between a tick's end and its label
LABEL_PAD_PT = 2.0  # room kept round a time label (circles' lines are up to 2 pt wide)
PUSH_PT = 3.0  # a label moves off its tick in steps of this, up to PUSHES of them
PUSHES = 6
AVOID_LINES = ("arc", "free_arc", "line", "optimum_path", "violation_piece", "moving_track",
               "moving_gap")


def place_time_labels(ax: Axes, marks: TimeMarks, circles: np.ndarray) -> None:
    """Put each time label beside its tick, on the side of the path and at the least
    distance from it that keeps the label off the circles ``(x, y, R)`` (the model circles
    as drawn), the other texts, crosses and drawn lines, and inside the axes. Positions
    are chosen in display pixels once the figure is laid out (after
    :func:`~hga_jax.host.plots.labels.place_labels`) and kept in data coordinates."""
    if not marks.labels:
        return
    fig = ax.get_figure(root=True)
    r = _renderer(fig)
    px = fig.dpi / 72
    to_px = ax.transData
    circles = np.asarray(circles, float).reshape(-1, 3)
    centre_px = to_px.transform(circles[:, :2]) if len(circles) else np.zeros((0, 2))
    scale = float(np.hypot(*(to_px.transform([1.0, 0.0]) - to_px.transform([0.0, 0.0]))))
    radius_px = circles[:, 2] * scale
    lines = [ln.get_transform().transform_path(ln.get_path()) for ln in ax.get_lines()
             if ln.get_gid() in AVOID_LINES]
    marks_px = [ln.get_window_extent(r) for ln in ax.get_lines()
                if ln.get_gid() in ("violation_point", "moving_collision", "moving_car",
                                    "start", "goal")]
    mine = set(map(id, marks.labels))
    placed = [t.get_window_extent(r) for t in ax.texts if id(t) not in mine and t.get_visible()]
    placed += marks_px
    last = 1.0  # the side of the label before (labels on one side read best)
    for t, p, n in zip(marks.labels, marks.points, marks.normals):
        box = t.get_window_extent(r)
        w, h = box.width, box.height
        p_px = to_px.transform(p)
        d_px = to_px.transform(p + n) - p_px
        d_px = d_px / max(float(np.hypot(*d_px)), 1e-12)
        reach = marks.half * scale + LABEL_GAP_PT * px
        best = None
        for push in range(PUSHES + 1):
            for side in (1.0, -1.0):
                d = side * d_px
                support = 0.5 * (abs(d[0]) * w + abs(d[1]) * h)
                xy = p_px + d * (reach + push * PUSH_PT * px + support)
                cand = _box_at(xy, (w, h))
                grown = cand.padded(LABEL_PAD_PT * px)
                cost = 3.0 * sum(_into_disc(grown, c, rad) for c, rad in zip(centre_px, radius_px))
                cost += sum(_overlap(grown, b) for b in placed)
                cost += 4.0 * sum(ln.intersects_bbox(cand, filled=False) for ln in lines)
                cost += 50.0 * (not _within(cand, ax.bbox)) + 0.5 * push + (side != last)
                if best is None or cost < best[0]:
                    best = (cost, xy, cand, side)
            if best[0] <= 0.5 * push + 1:  # clear at this distance: no need to go farther
                break
        last = best[3]
        t.set_position(to_px.inverted().transform(best[1]))
        placed.append(best[2])
