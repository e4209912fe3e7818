"""Laying a path figure out: the figure sized to its scene, its enlarged squares below
the legend, and its texts placed once it is laid out, in display pixels: a title that
fits, obstacle numbers off violation crosses, CW/CCW tags clear of other circles and of
each other."""
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
MIN_BOX_IN = 2.5  # inches: the least a path figure sized to its scene leaves its axes
FIT_SLACK = 0.01  # a box this much larger than the view's shape is left as it is
FIT_ROUNDS = 4  # layouts tried while sizing a figure to its scene
ZOOM_ROOM_IN = 1.3  # inches kept below a path figure's legend for its enlarged squares
ZOOM_MAX_IN = 1.8  # an enlarged square's greatest side (inches)
ZOOM_GAP_PT = 4.0  # points between the legend, the enlarged squares and their titles
ZOOM_TITLE_PT = 20.0  # points an enlarged square's title (two lines) takes above it
# Where a CW/CCW tag may go round its obstacle, in order of preference: below (as
# the eye expects), then the angles nearest below, round to above, every 15 degrees.
TAG_ANGLES = np.radians(-90 + np.array([0, 15, -15, 30, -30, 45, -45, 60, -60, 75, -75, 90, -90,
                                        105, -105, 120, -120, 135, -135, 150, -150, 165, -165,
                                        180]))
# Turns from "away from the cross" tried for an obstacle's number that a cross hides.
NUMBER_TURNS = np.radians([0, 30, -30, 60, -60, 90, -90, 120, -120, 150, -150, 180])


def under_legend(ax: Axes, k: int, count: int):
    """An axes locator that puts an inset, the ``k``-th of ``count``, below the legend of
    ``ax`` (outside on its right): squares as large as the room between the legend and
    the axes' bottom allows (at most :data:`ZOOM_MAX_IN`), within the legend's width,
    each with room for its title; in a row, or one above the other where that makes
    them larger."""
    def locate(inset: Axes, renderer) -> Bbox:
        fig = ax.get_figure(root=False)
        px = fig.dpi / 72
        gap, title = ZOOM_GAP_PT * px, ZOOM_TITLE_PT * px
        box = ax.get_window_extent(renderer)
        leg = ax.get_legend()
        lb = (leg.get_window_extent(renderer) if leg is not None
              else Bbox.from_bounds(box.x1 + gap, box.y1, ZOOM_MAX_IN * fig.dpi, 0))
        top = lb.y0 - gap - title
        width, most = max(lb.width, 1.0), ZOOM_MAX_IN * fig.dpi
        row = min(most, top - box.y0, (width - (count - 1) * gap) / count)
        column = min(most, width, (top - box.y0 - (count - 1) * (gap + title)) / count)
        if column > row:  # one above the other: larger squares
            side = max(1.0, column)
            x0, y1 = lb.x0, top - k * (side + gap + title)
        else:
            side = max(1.0, row)
            x0, y1 = lb.x0 + k * (side + gap), top
        return Bbox.from_bounds(x0, y1 - side, side, side).transformed(
            fig.transSubfigure.inverted())

    return locate


def _fit_figure(ax: Axes, view: tuple[np.ndarray, np.ndarray], room: float = 0.0) -> None:
    """Size a figure that holds ``ax`` alone to the view ``(lo, hi)``: lay it out, then
    take from its height (or width) what the axes' box has beyond the view's shape at
    equal aspect, so that the view fills the box without widening (the margins the
    layout keeps for title, labels and legend stay). The box keeps at least the
    legend's height and ``room`` inches more (for what goes below the legend), and
    :data:`MIN_BOX_IN`; what is left over widens the view."""
    fig = ax.get_figure(root=True)
    engine = fig.get_layout_engine()
    if engine is None or fig is not ax.get_figure(root=False):
        return
    size = np.maximum(np.asarray(view[1], float) - np.asarray(view[0], float), 1e-12)
    shape = size[1] / size[0]  # height over width of the view
    legend = ax.get_legend()
    for _ in range(FIT_ROUNDS):
        engine.execute(fig)
        w, h = fig.get_size_inches()
        pos = ax.get_position(original=True)
        bw, bh = pos.width * w, pos.height * h
        tall = MIN_BOX_IN
        if legend is not None:
            tall = max(tall, legend.get_window_extent(_renderer(fig)).height / fig.dpi
                       + 0.1 + room)
        if bh > bw * shape * (1 + FIT_SLACK) and bh > tall:  # room to spare in height
            h -= bh - max(bw * shape, tall)
        elif bw > bh / shape * (1 + FIT_SLACK) and bw > MIN_BOX_IN:  # in width
            w -= bw - max(bh / shape, MIN_BOX_IN)
        else:
            break
        fig.set_size_inches(w, h)


def _lay_out(ax: Axes, view: tuple[np.ndarray, np.ndarray], fit: bool = False,
            room: float = 0.0) -> None:
    """Lay the figure out as it will be drawn (``fit``: first size it to the view,
    :func:`_fit_figure`), then widen the view ``(lo, hi)`` (data corners) along x or y
    to the shape of the box the layout gave the axes: at equal aspect they then fill
    that box, so the title and legend stay where the layout measured them (shrinking
    the box instead would move them), and what is measured next is where it will be
    drawn."""
    fig = ax.get_figure(root=True)
    engine = fig.get_layout_engine()
    if fit:
        _fit_figure(ax, view, room)
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


def _is_path(gid: str | None) -> bool:
    """Whether an artist's gid is that of a drawn piece of path: ``arc``, ``line``, a car
    model's kinds of them (``free_arc``, ``reverse_line``, ...), the optimum's, a
    violating piece."""
    return bool(gid) and (gid in ("arc", "line", "optimum_path", "violation_piece")
                          or gid.endswith(("_arc", "_line")))


def place_labels(ax: Axes, view: tuple[np.ndarray, np.ndarray], centres: np.ndarray,
                  radii: np.ndarray, model: np.ndarray, numbers: list[Text],
                  tags: dict[int, Text], crosses: list[Line2D], fit: bool = False,
                  room: float = 0.0) -> None:
    """Lay the figure out (``fit``: a figure of this axes alone, sized to the view:
    :func:`_fit_figure`, keeping ``room`` inches below the legend) and fit the title,
    then move obstacle numbers off the violation crosses and put each CW/CCW tag where
    it meets no other obstacle's circle or label. Positions are chosen in display
    pixels, once the figure is laid out as it will be saved, and kept in data
    coordinates."""
    _lay_out(ax, view, fit, room)
    for _ in range(4):  # a smaller title changes the layout, which moves the title
        if not _fit_title(ax):
            break
        _lay_out(ax, view, fit, room)
    _lay_out(ax, view, fit, room)  # again: the new limits may have changed the tick labels
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
             if _is_path(ln.get_gid())]
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
