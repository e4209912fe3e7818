"""Placing a path figure's texts once the figure is laid out, in display pixels: a
title that fits, obstacle numbers off violation crosses, CW/CCW tags clear of other
circles and of each other."""
from __future__ import annotations

import textwrap

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import RendererAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from .style import EDGE_PAD_PT

LABEL_PAD_PT = 1.0  # room (points) kept round a placed label
MIN_TITLE_PT = 7.0  # a path plot's title shrinks down to this size, then is broken up
# Where a CW/CCW tag may go round its obstacle, in order of preference: below (as
# the eye expects), then the angles nearest below, round to above, every 15 degrees.
TAG_ANGLES = np.radians(-90 + np.array([0, 15, -15, 30, -30, 45, -45, 60, -60, 75, -75, 90, -90,
                                        105, -105, 120, -120, 135, -135, 150, -150, 165, -165,
                                        180]))
# Turns from "away from the cross" tried for an obstacle's number that a cross hides.
NUMBER_TURNS = np.radians([0, 30, -30, 60, -60, 90, -90, 120, -120, 150, -150, 180])


def _lay_out(ax: Axes, view: tuple[np.ndarray, np.ndarray]) -> None:
    """Lay the figure out as it will be drawn, then widen the view ``(lo, hi)`` (data
    corners) along x or y to the shape of the box the layout gave the axes: at equal
    aspect they then fill that box, so the title and legend stay where the layout
    measured them (shrinking the box instead would move them), and what is measured
    next is where it will be drawn."""
    fig = ax.get_figure(root=True)
    engine = fig.get_layout_engine()
    if engine is not None:
        engine.execute(fig)
    box = ax.get_position(original=True).transformed(ax.get_figure(root=False).transSubfigure)
    lo, hi = np.asarray(view[0], float), np.asarray(view[1], float)
    mid, size = (lo + hi) / 2, np.maximum(hi - lo, 1e-12)
    shape = box.height / max(box.width, 1e-12)
    if size[1] / size[0] < shape:
        size[1] = size[0] * shape
    else:
        size[0] = size[1] / shape
    ax.set_xbound(mid[0] - size[0] / 2, mid[0] + size[0] / 2)
    ax.set_ybound(mid[1] - size[1] / 2, mid[1] + size[1] / 2)
    ax.apply_aspect()


def _renderer(fig: Figure) -> RendererAgg:
    """A renderer at the figure's size and resolution, to measure texts and markers
    (a text's own cached renderer may be one of an earlier save at another dpi)."""
    return RendererAgg(int(fig.bbox.width), int(fig.bbox.height), fig.dpi)


def _fit_title(ax: Axes) -> bool:
    """Shrink the title's font until the title stays ``EDGE_PAD_PT`` inside the figure,
    down to ``MIN_TITLE_PT``; a title still too wide at that size is broken at spaces
    onto more lines. True if it changed."""
    title, fig = ax.title, ax.get_figure(root=True)
    if not title.get_text().strip():
        return False
    r = _renderer(fig)
    edge = fig.bbox.padded(-EDGE_PAD_PT * fig.dpi / 72)

    def room() -> float:  # the share of its width that the title may have
        box = title.get_window_extent(r)
        mid = (box.x0 + box.x1) / 2
        return 2 * min(mid - edge.x0, edge.x1 - mid) / max(box.width, 1e-9)

    changed = False
    while room() < 1 and title.get_fontsize() > MIN_TITLE_PT:
        title.set_fontsize(max(MIN_TITLE_PT, title.get_fontsize() - 0.5))
        changed = True
    for _ in range(8):
        share = room()
        if share >= 1:
            break
        lines = title.get_text().split("\n")
        # Characters per line, from the widest line's width, with room to spare for
        # the difference in text widths between resolutions.
        chars = max(8, int(max(map(len, lines)) * share * 0.9))
        title.set_text("\n".join(textwrap.fill(line, chars, break_long_words=False)
                                  for line in lines))
        changed = True
    return changed


def _overlap(a: Bbox, b: Bbox) -> float:
    """How far two boxes overlap (pixels; 0 when apart)."""
    return max(0.0, min(a.x1 - b.x0, b.x1 - a.x0, a.y1 - b.y0, b.y1 - a.y0,
                        a.width, b.width, a.height, b.height))


def _into_disc(box: Bbox, centre: np.ndarray, radius: float) -> float:
    """How far the box reaches into a disc (pixels; 0 when apart)."""
    dx = max(box.x0 - centre[0], 0.0, centre[0] - box.x1)
    dy = max(box.y0 - centre[1], 0.0, centre[1] - box.y1)
    return max(0.0, radius - float(np.hypot(dx, dy)))


def _box_at(xy: np.ndarray, size: tuple[float, float]) -> Bbox:
    """The box of ``size`` (width, height) centred on ``xy``."""
    return Bbox.from_bounds(xy[0] - size[0] / 2, xy[1] - size[1] / 2, size[0], size[1])


def _within(inner: Bbox, outer: Bbox) -> bool:
    return (inner.x0 >= outer.x0 and inner.x1 <= outer.x1 and inner.y0 >= outer.y0
            and inner.y1 <= outer.y1)


def place_labels(ax: Axes, view: tuple[np.ndarray, np.ndarray], centres: np.ndarray,
                  radii: np.ndarray, model: np.ndarray, numbers: list[Text],
                  tags: dict[int, Text], crosses: list[Line2D]) -> None:
    """Lay the figure out and fit the title, then move obstacle numbers off the
    violation crosses and put each CW/CCW tag where it meets no other obstacle's
    circle or label. Positions are chosen in display pixels, once the figure is laid
    out as it will be saved, and kept in data coordinates."""
    _lay_out(ax, view)
    for _ in range(4):  # a smaller title changes the layout, which moves the title
        if not _fit_title(ax):
            break
        _lay_out(ax, view)
    _lay_out(ax, view)  # again: the new limits may have changed the tick labels
    if not numbers:
        return
    fig = ax.get_figure(root=True)
    r = _renderer(fig)
    px = fig.dpi / 72  # pixels per point
    pad = LABEL_PAD_PT * px
    to_px = ax.transData
    centre_px = to_px.transform(centres)
    scale = float(np.hypot(*(to_px.transform([1.0, 0.0]) - to_px.transform([0.0, 0.0]))))
    model_px = model * scale
    lines = [ln.get_transform().transform_path(ln.get_path()) for ln in ax.get_lines()
             if ln.get_gid() in ("arc", "free_arc", "line", "optimum_path", "violation_piece")]
    cross_boxes = [c.get_window_extent(r).padded(c.get_markeredgewidth() / 2 * px + pad)
                   for c in crosses]

    def crossed(box: Bbox) -> int:  # how many drawn pieces of path run through the box
        return sum(p.intersects_bbox(box, filled=False) for p in lines)

    def put(t: Text, xy: np.ndarray) -> None:
        t.set_position(to_px.inverted().transform(xy))

    # An obstacle's number that a cross would hide moves to the nearest place round
    # its centre free of crosses, preferring the side away from the cross, then off the
    # path and the other numbers.
    boxes = [t.get_window_extent(r) for t in numbers]
    for k, t in enumerate(numbers):
        under = [b for b in cross_boxes if _overlap(boxes[k], b) > 0]
        if not under:
            continue
        size = (boxes[k].width, boxes[k].height)
        away = centre_px[k] - np.mean([b.get_points().mean(axis=0) for b in under], axis=0)
        a0 = float(np.arctan2(away[1], away[0])) if np.hypot(*away) > 0.5 else np.pi / 2
        others = boxes[:k] + boxes[k + 1:]
        best = None
        for d in np.arange(1, 13) * 0.25 * max(size):
            for da in NUMBER_TURNS:
                xy = centre_px[k] + d * np.array([np.cos(a0 + da), np.sin(a0 + da)])
                cand = _box_at(xy, size)
                cost = (100.0 * sum(_overlap(cand.padded(pad), b) > 0 for b in cross_boxes)
                        + crossed(cand) + sum(_overlap(cand, b) > 0 for b in others))
                if best is None or cost < best[0]:
                    best = (cost, xy, cand)
            if best[0] == 0:
                break
        put(t, best[1])
        boxes[k] = best[2]
    # Each CW/CCW tag in its obstacle's ring, at the angle clearest of the other
    # obstacles' circles and of the labels (numbers, crosses, the tags placed so far);
    # just outside the model circle only where the whole ring is taken.
    placed = boxes + cross_boxes
    for k, t in tags.items():
        box = t.get_window_extent(r)
        size = (box.width, box.height)
        mid, half = 0.5 * (radii[k] + model[k]) * scale, 0.25 * (model[k] - radii[k]) * scale
        outside = model_px[k] + 0.5 * float(np.hypot(*size)) + pad
        rings = ((mid, 0.0), (mid - half, 0.5), (mid + half, 0.5),  # between body and model circle
                 (outside, 4.0), (outside + 0.5 * size[1], 6.0))  # just outside it
        near = [j for j in range(len(centres)) if j != k  # the circles it could meet
                and np.hypot(*(centre_px[j] - centre_px[k])) < model_px[j] + 2 * outside]
        best = None
        for radius, cost0 in rings:
            for a in TAG_ANGLES:  # the first free place in order of preference
                xy = centre_px[k] + radius * np.array([np.cos(a), np.sin(a)])
                cand = _box_at(xy, size)
                grown = cand.padded(pad)
                cost = cost0 + sum(_into_disc(grown, centre_px[j], model_px[j]) for j in near)
                cost += sum(_overlap(grown, b) for b in placed)
                cost += 2.0 * crossed(cand) + 10.0 * (not _within(cand, ax.bbox))
                if best is None or cost < best[0]:
                    best = (cost, xy, cand)
                if cost == 0:
                    break
            if best[0] == 0:
                break
        put(t, best[1])
        placed.append(best[2])
