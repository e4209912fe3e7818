"""A planned path in its scene: field, obstacles (numbered from 1), poses with their
turning circles, the path's arcs and lines, the optimum, and violations."""
from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle, FancyArrowPatch, Rectangle

from hga_jax.model import car_model
from hga_jax.model.scenario import Scenario
from .labels import ZOOM_ROOM_IN, place_labels, under_legend
from .moving_robots import draw_robots, draw_time_marks, place_time_labels
from .style import C_ARC, C_BAD, C_FREE, C_GOAL, C_LINE, C_OPT, C_START, C_TOUCH, EDGE_PAD_PT

PTS_PER_RAD = 60  # arc sampling density
REVERSE = "reverse"  # the key of a piece driven backward in the result files (a cusp between)
# The style of each car model's segment flag, in car_model.segment_flags() order: free
# arcs dashed in cyan, pieces driven backward dotted.
FLAG_STYLES = (dict(color=C_FREE, ls=(0, (2, 1))),
               dict(ls=(0, (1, 1.2)), solid_capstyle="butt", dash_capstyle="butt"))
PATH_Z = 5.0  # the path's pieces: over the poses' dots and arrows
POSE_Z = 4.5  # the poses: over obstacles (2) and model circles (3), under the path
POSE_ALPHA = 0.6  # the pose arrows' opacity: a piece of path under one still shows
# A piece shorter than this share of the view, at the start, the goal or a cusp (whose
# marks hide it), is shown again in an enlarged square below the legend.
SHORT_SHARE = 0.03
ZOOM_PAD = 3.0  # an enlarged square's side: this many times what it must show
MIN_ZOOM_SHARE = 0.001  # and at least this share of the view
MAX_ZOOMS = 3


def arc_points(center: Sequence[float], radius: float, start_angle: float, sweep: float) -> np.ndarray:
    """(m, 2) points along an arc from ``start_angle`` to ``start_angle + sweep``."""
    m = max(2, int(np.ceil(abs(sweep) * PTS_PER_RAD)) + 1)
    t = start_angle + sweep * np.linspace(0.0, 1.0, m)
    return np.asarray(center, float) + radius * np.stack([np.cos(t), np.sin(t)], axis=1)


def _pose(ax: Axes, pose: Sequence[float], circles: Iterable[Sequence[float]], colour: str,
          name: str, span: float) -> np.ndarray:
    """Draw a pose arrow and its turning circles ``(x, y, r)`` (from
    :meth:`Scenario.circles`); return the circles' bbox corners."""
    circles = [tuple(float(v) for v in c) for c in circles]
    size = max(0.07 * span, 0.6 * max(c[2] for c in circles))
    _pose_mark(ax, pose, colour, name, size)
    ends = []
    for cx, cy, rho in circles:
        ax.add_patch(Circle((cx, cy), rho, fill=False, ls=":", lw=0.8, ec=colour,
                            gid="turning_circle"))
        ends += [(cx - rho, cy - rho), (cx + rho, cy + rho)]
    return np.asarray(ends)


def _pose_mark(ax: Axes, pose: Sequence[float], colour: str, name: str, size: float,
               label: bool = True) -> None:
    """A pose's dot and its heading's arrow (``size`` m long), under the path
    (:data:`POSE_Z`) and see-through: a short piece of path at the pose, which a forward
    start or end runs along the arrow, stays in sight on top."""
    x, y, th = (float(v) for v in pose)
    ax.plot([x], [y], "o", color=colour, ms=5, zorder=POSE_Z, gid=name,
            label=name if label else "_nolegend_")
    tip = (x + size * np.cos(th), y + size * np.sin(th))
    ax.add_patch(FancyArrowPatch((x, y), tip, arrowstyle="-|>", mutation_scale=12, lw=1.4,
                                 color=colour, alpha=POSE_ALPHA, shrinkA=0, shrinkB=0,
                                 zorder=POSE_Z, gid=name + "_arrow"))


def segment_points(seg: Mapping[str, Any]) -> np.ndarray:
    """(m, 2) points along one segment of the result-file format (metres)."""
    if seg["type"] == "arc":
        return arc_points(seg["center"], float(seg["radius"]), float(seg["start_angle"]),
                          float(seg["sweep"]))
    if seg["type"] == "line":
        return np.asarray([seg["start"], seg["end"]], float)
    raise ValueError(f"unknown segment type {seg['type']!r}")


def piece_words(seg: Mapping[str, Any], gears: bool = False) -> str:
    """A path piece's legend words: what it is (``"arc"``, ``"line"``, ``"free turn
    (radius rho)"``) and, on a path with gears (``gears``: some piece of it is driven
    backward), which way the car drives it (``"arc, driven forward"``, ``"line, driven
    backward"``); on a forward path ``"path arc"``, ``"path line"``. A flag of another
    car model adds that model's words."""
    kind = seg["type"]
    free = car_model.segment_flags()[0]  # the flag of a turn in free space (radius rho)
    base = r"free turn (radius $\rho$)" if seg.get(free) else (
        kind if gears else f"path {kind}")
    if gears:
        base += ", driven backward" if seg.get(REVERSE) else ", driven forward"
    _, other = car_model.segment_kind({k: v for k, v in seg.items() if k not in (free, REVERSE)})
    return base if other is None else f"{base}; {other}"


def _touches(touched: Iterable[Any], n: int, copies: bool = False) -> dict[int, int]:
    """``touched`` -> {obstacle index from 0: label}.

    Items are the result files' ``{"obstacle": number from 1, "label": +1 | -1}`` or
    ``(number from 1, label)`` pairs (``Path.touched``, ``ExactResult.touched``).
    ``copies``: numbers past ``n`` are frozen copies of moving robots (the exact
    solver's path among robots that move, :mod:`hga_jax.model.in_time.optimum`), which
    the result files do not place: left out.
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
        if copies and k >= n:
            continue
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

    The title may be long (several lines): its font shrinks until it fits the
    figure with a margin, and only a title too wide even at 7 pt is broken onto more
    lines. The legend lists only what is drawn. Labels are placed once the figure is
    laid out as it will be saved: an obstacle's number moves off a violation cross
    that would hide it, and each CW/CCW tag takes the place round its obstacle,
    between body and model circle, clearest of the other obstacles' circles and of
    the other labels. A figure drawn here (no ``ax`` given) is sized to the scene, so
    that at equal aspect the view fits it with a small margin; otherwise the view widens
    along x or y to fill the axes.

    The path lies over the start and goal marks, whose arrows are see-through. Its
    pieces are named by kind (``"path arc"``, ``"path line"``, ``"free turn (radius
    rho)"``) and, on a path that is driven backward somewhere, by gear (``"arc, driven
    forward"``, ``"line, driven backward"``). A piece too short to see at the start, the
    goal or a cusp (under their marks) is shown again, enlarged, in a square below the
    legend, framed in the colour of the pose (a cusp's: black) as the same square on the
    scene is; not in a scene with robots that move.

    Robots that move (``scenario.has_motion``; :mod:`.moving_robots`): each is drawn
    where it is when the car, driving the path at ``scenario.speed`` from time 0, passes
    closest, with its track over the path's duration, its place at time 0, its direction
    of motion and the car's point then; its model circle is red where it meets the car.
    Time marks along the path say when the car is where. A scene where nothing moves is
    drawn without any of these.
    """
    owned = ax is None  # a figure of its own: sized to the scene
    if ax is None:
        fig = Figure(figsize=(8.0, 5.6), layout="constrained")
        fig.get_layout_engine().set(w_pad=EDGE_PAD_PT / 72, h_pad=EDGE_PAD_PT / 72)
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
    touch = _touches(touched, scenario.n, copies=scenario.has_motion)
    numbers, tags = [], {}
    still = ~scenario.moving
    robots = None
    if scenario.has_motion:  # arrows sized by the scene at time 0
        ext = np.concatenate(pts + [centres - model[:, None], centres + model[:, None]])
        robots = draw_robots(ax, scenario, segments, float(np.ptp(ext, axis=0).max()) or 1.0)
    for i, (c, ri, Ri) in enumerate(zip(centres, radii, model)):
        if not still[i]:  # where it is when the car passes closest
            numbers.append(robots.numbers[i])
            continue
        hit = i in touch
        ax.add_patch(Circle(c, ri, fc="0.86", ec="0.55", lw=0.8, zorder=2, gid="obstacle"))
        ax.add_patch(Circle(c, Ri, fill=False, ls="-" if hit else "--", lw=2.0 if hit else 0.8,
                            ec=C_TOUCH if hit else "0.45", zorder=3, gid="model_circle"))
        numbers.append(ax.text(c[0], c[1], str(i + 1), ha="center", va="center", fontsize=8,
                               zorder=10, color=C_TOUCH if hit else "black",
                               fontweight="bold" if hit else "normal", gid="obstacle_number"))
        if hit:  # tag in the ring between body and model circle, which the path never enters
            tags[i] = ax.text(c[0], c[1] - 0.5 * (ri + Ri), "CW" if touch[i] > 0 else "CCW",
                              color=C_TOUCH, fontsize=6, fontweight="bold", ha="center",
                              va="center", zorder=7, gid="touched",
                              bbox=dict(boxstyle="square,pad=0.05", fc="white", ec="none",
                                        alpha=0.75))  # legible on a line it may sit on
        pts.append(np.asarray([c - Ri, c + Ri]))
    if robots is not None:
        pts += robots.points
    span0 = np.ptp(np.concatenate(pts), axis=0).max() if len(pts) > 1 else 1.0
    span = float(span0) if span0 > 0 else 1.0
    turning = list(zip(*scenario.circles(np.float64)[:3]))  # start CCW, CW, goal CCW, CW
    pts.append(_pose(ax, scenario.start, turning[0:2], C_START, "start", span))
    pts.append(_pose(ax, scenario.goal, turning[2:4], C_GOAL, "goal", span))
    drawn = _draw_path(ax, segments)
    pts += drawn
    if optimum is not None:
        pts += _draw_optimum(ax, optimum)
    crosses = _violations(ax, list(violations_at), drawn, centres, model)
    marks = None
    if robots is not None:
        crosses += robots.crosses
        marks = draw_time_marks(ax, scenario, segments, span)
    allp = np.concatenate(pts)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 0.03 * float(max(hi - lo))
    # Equal aspect by widening the view, not by narrowing the axes' box: a narrowed box
    # would leave its title and legend where the layout did not measure them. The
    # bounds are set with autoscaling left on, which lets the aspect widen them.
    ax.set_xbound(lo[0] - pad, hi[0] + pad)
    ax.set_ybound(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(scenario.name if title is None else title)
    handles = []  # what is drawn, and only that
    n_still = int(still.sum())
    if n_still:
        handles.append(Line2D([], [], marker="o", ls="", mfc="0.86", mec="0.55", ms=9,
                              label="obstacle (robot)"))
    if sum(bool(still[k]) for k in touch) < n_still:
        handles.append(Line2D([], [], ls="--", color="0.45", lw=0.8, label="model circle"))
    handles.append(Line2D([], [], ls=":", color="0.3", lw=0.8, label=r"turning circles ($\rho$)"))
    if any(still[k] for k in touch):
        handles.append(Line2D([], [], color=C_TOUCH, lw=2.0, label="touched (CW/CCW)"))
    if f is not None:
        handles.append(Line2D([], [], color="black", lw=1.2, label="field"))
        if f.keep_inside:
            handles.append(Line2D([], [], color="0.4", lw=0.8, ls="-.", label="field shrunk by r"))
    if robots is not None:
        handles += robots.handles + marks.handles
    zooms = [] if robots is not None else _zooms(segments, drawn, scenario, float(max(hi - lo)))
    if zooms:
        handles.append(Line2D([], [], marker="s", ls="", mfc="none", mec="0.3", ms=8,
                              label="shown enlarged below"))
    h, _ = ax.get_legend_handles_labels()
    ax.legend(handles=h + handles, loc="upper left", bbox_to_anchor=(1.02, 1.0),
              fontsize=8, frameon=False)
    insets = [_draw_zoom(ax, z, scenario, segments, optimum, span, k, len(zooms))
              for k, z in enumerate(zooms)]
    for t in numbers + list(tags.values()):  # inside the view: nothing for the layout
        t.set_in_layout(False)
    place_labels(ax, (lo - pad, hi + pad), centres if robots is None else robots.centres,
                 radii, model, numbers, tags, crosses, fit=owned,
                 room=ZOOM_ROOM_IN if insets else 0.0)
    if marks is not None:  # off the circles and labels, as laid out
        place_time_labels(ax, marks, np.c_[robots.centres, model])
    return fig


def _draw_path(ax: Axes, segments: Sequence[Mapping[str, Any]], legend: bool = True
               ) -> list[np.ndarray]:
    """Draw the path's pieces in their styles (arcs blue, lines orange, free turns cyan
    dashed, pieces driven backward dotted), one legend entry per kind (``legend``), and
    a ring at each cusp; returns each piece's points."""
    kinds_seen: set[str] = set()
    drawn = []
    gears = any(seg.get(REVERSE) for seg in segments)  # the path drives backward somewhere
    for seg in segments:
        xy = segment_points(seg)
        kind, _ = car_model.segment_kind(seg)  # a car model's own kinds: their own style
        style = (dict(color=C_ARC, lw=2.6, solid_capstyle="round") if seg["type"] == "arc"
                 else dict(color=C_LINE, lw=2.0))
        for k, flag in enumerate(car_model.segment_flags()):  # free arcs, reversed pieces
            if seg.get(flag):
                style.update(FLAG_STYLES[k % len(FLAG_STYLES)])
        if _length(xy) <= 0.0:  # a piece of no length is drawn nowhere: no entry
            label = "_nolegend_"
        else:
            label = ("_nolegend_" if kind in kinds_seen or not legend
                     else piece_words(seg, gears))
            kinds_seen.add(kind)
        ax.plot(xy[:, 0], xy[:, 1], zorder=PATH_Z, gid=kind.replace(" ", "_"), label=label,
                **style)
        drawn.append(xy)
    for p in cusps(segments, drawn):
        ax.plot([p[0]], [p[1]], marker="o", ms=6, mfc="white", mec="black", mew=1.2,
                ls="", zorder=9, gid="cusp",
                label="cusp" if "cusp" not in kinds_seen and legend else "_nolegend_")
        kinds_seen.add("cusp")
    return drawn


def cusps(segments: Sequence[Mapping[str, Any]], drawn: Sequence[np.ndarray]) -> list[np.ndarray]:
    """The points where the gear changes between consecutive pieces (``drawn``: their
    points)."""
    return [drawn[k][-1] for k, (a, b) in enumerate(zip(segments, segments[1:]))
            if bool(a.get(REVERSE)) != bool(b.get(REVERSE))]


def _draw_optimum(ax: Axes, optimum: Sequence[Mapping[str, Any]], legend: bool = True
                  ) -> list[np.ndarray]:
    """The optimum dashed in black over the path; returns its pieces' points."""
    label = "optimum" if legend else "_nolegend_"
    out = []
    for seg in optimum:
        xy = segment_points(seg)
        ax.plot(xy[:, 0], xy[:, 1], color=C_OPT, lw=1.2, ls="--", zorder=8,
                gid="optimum_path", label=label)
        label = "_nolegend_"
        out.append(xy)
    return out


def _length(xy: np.ndarray) -> float:
    return float(np.sum(np.hypot(*np.diff(xy, axis=0).T)))


def _zooms(segments: Sequence[Mapping[str, Any]], drawn: list[np.ndarray],
           scenario: Scenario, span: float) -> list[dict[str, Any]]:
    """The places to show enlarged: where a piece shorter than :data:`SHORT_SHARE` of
    the view's ``span`` starts or ends at the start, the goal or a cusp, whose marks
    would hide it. Each: ``{"where": "start" | "goal" | "cusp", "colour", "centre",
    "side"}`` (a square, m), places whose squares meet merged; at most
    :data:`MAX_ZOOMS` (those of the shortest pieces), in travel order."""
    ends = [("start", C_START, np.asarray(scenario.start[:2], float))]
    ends += [("cusp", "black", p) for p in cusps(segments, drawn)]
    ends.append(("goal", C_GOAL, np.asarray(scenario.goal[:2], float)))
    near = SHORT_SHARE * span
    places = []
    for order, (where, colour, p) in enumerate(ends):
        short = [xy for xy in drawn if 0.0 < _length(xy) < near
                 and min(np.hypot(*(xy[0] - p)), np.hypot(*(xy[-1] - p))) < 1e-9 + 1e-6 * span]
        if not short:
            continue
        every = np.concatenate(short + [p[None]])
        lo, hi = every.min(axis=0), every.max(axis=0)
        side = max(ZOOM_PAD * float(max(hi - lo)), MIN_ZOOM_SHARE * span)
        places.append({"where": where, "colour": colour, "centre": (lo + hi) / 2,
                       "side": side, "shortest": min(_length(xy) for xy in short),
                       "order": order})
    merged: list[dict[str, Any]] = []
    for z in places:  # one square for places whose squares meet
        for m in merged:
            if np.all(np.abs(z["centre"] - m["centre"]) < (z["side"] + m["side"]) / 2):
                lo = np.minimum(m["centre"] - m["side"] / 2, z["centre"] - z["side"] / 2)
                hi = np.maximum(m["centre"] + m["side"] / 2, z["centre"] + z["side"] / 2)
                m.update(centre=(lo + hi) / 2, side=float(max(hi - lo)),
                         shortest=min(m["shortest"], z["shortest"]))
                if z["where"] not in m["where"]:
                    m["where"] += " and " + z["where"]
                break
        else:
            merged.append(dict(z))
    merged.sort(key=lambda m: m["shortest"])
    return sorted(merged[:MAX_ZOOMS], key=lambda m: m["order"])  # in travel order


def _draw_zoom(ax: Axes, zoom: Mapping[str, Any], scenario: Scenario,
               segments: Sequence[Mapping[str, Any]],
               optimum: Sequence[Mapping[str, Any]] | None, span: float, k: int,
               count: int) -> Axes:
    """A square of the scene enlarged in an inset below the legend (placed by
    :func:`.labels.under_legend`), framed in the colour of the pose or cusp it shows,
    and the same square framed on the scene: the path's pieces, poses, cusps, the
    optimum and the circles there, without ticks."""
    c, side, colour = np.asarray(zoom["centre"]), float(zoom["side"]), zoom["colour"]
    ax.add_patch(Rectangle(c - side / 2, side, side, fill=False, ec=colour, lw=1.0,
                           zorder=9.5, gid="zoom_box"))
    inset = ax.inset_axes([1.02, 0.0, 0.3, 0.3], zorder=5)
    inset.set_axes_locator(under_legend(ax, k, count))
    inset.set_gid("zoom")
    for a, Ri, r in zip(np.asarray(scenario.centres, float).reshape(-1, 2),
                        np.asarray(scenario.model_radii, float), np.asarray(scenario.radii, float)):
        inset.add_patch(Circle(a, r, fc="0.86", ec="0.55", lw=0.8, zorder=2))
        inset.add_patch(Circle(a, Ri, fill=False, ls="--", lw=0.8, ec="0.45", zorder=3))
    turning = list(zip(*scenario.circles(np.float64)[:3]))
    for (cx, cy, rho), col in zip(turning, (C_START, C_START, C_GOAL, C_GOAL)):
        inset.add_patch(Circle((cx, cy), rho, fill=False, ls=":", lw=0.8, ec=col))
    size = max(0.07 * span, 0.6 * float(scenario.min_turn_radius))
    _pose_mark(inset, scenario.start, C_START, "start", size, label=False)
    _pose_mark(inset, scenario.goal, C_GOAL, "goal", size, label=False)
    _draw_path(inset, segments, legend=False)
    if optimum is not None:
        _draw_optimum(inset, optimum, legend=False)
    inset.set_xlim(c[0] - side / 2, c[0] + side / 2)
    inset.set_ylim(c[1] - side / 2, c[1] + side / 2)
    inset.set_aspect("equal", adjustable="datalim")
    inset.set_xticks([])
    inset.set_yticks([])
    for spine in inset.spines.values():
        spine.set_edgecolor(colour)
        spine.set_linewidth(1.0)
    inset.set_title(f"{zoom['where']}\n{_metres(side)} square", fontsize=7, pad=2,
                    color=colour if colour != "black" else "0.2", linespacing=1.1)
    return inset


def _metres(v: float) -> str:
    """A length for a zoom's title: mm under 1 cm, then cm, then m."""
    if v < 0.01:
        return f"{1000 * v:.2g} mm"
    return f"{100 * v:.2g} cm" if v < 1 else f"{v:.2g} m"


def _violations(ax: Axes, where: list[Mapping[str, Any]], drawn: list[np.ndarray],
                centres: np.ndarray, model: np.ndarray) -> list[Line2D]:
    """Mark each violation: the piece in red; an obstacle's model circle and the
    piece's point closest to its centre (a cross). Returns the crosses."""
    label = "violation: piece"
    crosses = []
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
            crosses += ax.plot([p[0]], [p[1]], "x", color=C_BAD, ms=9, mew=2.2, zorder=9,
                               gid="violation_point")
    label = "violation: obstacle met"
    for k in sorted({int(v["obstacle"]) - 1 for v in where if v.get("kind") == "obstacle"}):
        ax.add_patch(Circle(centres[k], model[k], fill=False, ec=C_BAD, lw=2.0, zorder=4,
                            gid="violation_obstacle", label=label))
        label = "_nolegend_"
    return crosses
