"""Checks of a finished figure, read from matplotlib itself: every text stays on the
canvas, no legend covers plotted data, no two texts overlap.

A figure is first written as the project writes it (:func:`hga_jax.host.output.figure_writer`,
which works out a constrained layout once and keeps it), so the positions checked
are those of the saved PNG. Coordinates are display pixels.
"""
from __future__ import annotations

import io

import numpy as np
from matplotlib import cbook
from matplotlib.collections import Collection
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.path import Path
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from hga_jax.host.output import figure_writer, fix_layout

TOL = 1.0  # pixels


def rendered(fig: Figure) -> Figure:
    """``fig`` as it is when written as a PNG (its final layout: a constrained layout
    is worked out and kept, without painting the pixels; any other figure is written)."""
    if not fix_layout(fig):
        figure_writer(fig)(io.BytesIO())
    return fig


def _renderer(fig: Figure):
    """An Agg renderer of the figure's size (a bare ``Figure`` has no canvas of its own),
    every artist placed as a draw places it (a draw without painting: what is measured is
    where things are, not their pixels)."""
    if not hasattr(fig.canvas, "get_renderer"):
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
        fig.draw_without_rendering()
    return fig.canvas.get_renderer()


def texts(fig: Figure) -> list[Text]:
    """Every visible, non-empty text of the figure (titles, labels, ticks, legends)."""
    out = []
    for t in fig.findobj(Text):
        if not t.get_visible() or not t.get_text().strip():
            continue
        if any(not a.get_visible() for a in _ancestors(t)):
            continue
        out.append(t)
    return out


def _ancestors(artist):
    ax = getattr(artist, "axes", None)
    return [ax] if ax is not None else []


def _hidden_tick_labels(fig: Figure) -> set[int]:
    """ids of the tick labels matplotlib does not draw (ticks outside the view limits)."""
    hidden = set()
    for ax in fig.axes:
        for axis in ax._axis_map.values():
            ticks = axis.get_major_ticks() + axis.get_minor_ticks()
            drawn = {id(t) for t in axis._update_ticks()}
            for t in ticks:
                if id(t) not in drawn or not t.get_visible():
                    hidden.update({id(t.label1), id(t.label2)})
    return hidden


def text_boxes(fig: Figure) -> list[tuple[Text, Bbox]]:
    r = _renderer(fig)
    hidden = _hidden_tick_labels(fig)
    return [(t, t.get_window_extent(r)) for t in texts(fig) if id(t) not in hidden]


def texts_off_canvas(fig: Figure) -> list[str]:
    """The texts that leave the canvas (empty when all fit), as ``'text' at bbox``."""
    canvas = fig.bbox
    bad = []
    for t, b in text_boxes(fig):
        if (b.x0 < canvas.x0 - TOL or b.y0 < canvas.y0 - TOL or b.x1 > canvas.x1 + TOL
                or b.y1 > canvas.y1 + TOL):
            bad.append(f"{t.get_text()!r} at {np.round(b.extents, 1).tolist()} "
                       f"(canvas {np.round(canvas.extents, 1).tolist()})")
    return bad


def _display_path(artist) -> Path | None:
    if isinstance(artist, Line2D):
        xy = artist.get_xydata()
        if len(xy) == 0:
            return None
        style = artist.get_drawstyle()
        if style in cbook.STEP_LOOKUP_MAP and style != "default":
            x, y = cbook.STEP_LOOKUP_MAP[style](xy[:, 0], xy[:, 1])
            xy = np.column_stack([x, y])
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) == 0:
            return None
        return artist.get_transform().transform_path(Path(xy))
    if isinstance(artist, Patch):
        return artist.get_transform().transform_path(artist.get_path())
    return None


def _data_artists(ax):
    for a in ax.get_children():
        if not a.get_visible() or isinstance(a, (Legend, Text)):
            continue
        if a in (ax.patch,) or a in ax.spines.values():
            continue
        if isinstance(a, (Line2D, Patch, Collection)):
            yield a


def legend_over_data(fig: Figure) -> list[str]:
    """The plotted artists that a legend covers (lines, markers, patches, filled
    bands), within the part of each axes a legend overlaps; empty when none."""
    r = _renderer(fig)
    legends = [leg for leg in fig.findobj(Legend) if leg.get_visible()]
    bad = []
    for leg in legends:
        box = leg.get_window_extent(r)
        for ax in fig.axes:
            if not ax.get_visible():
                continue
            inter = Bbox.intersection(box, ax.bbox)
            if inter is None or inter.width <= 0 or inter.height <= 0:
                continue
            for a in _data_artists(ax):
                if _covers(a, inter):
                    bad.append(f"legend of {ax.get_title() or 'axes'!r} covers "
                               f"{type(a).__name__} {a.get_gid() or a.get_label()!r}")
    return bad


def _covers(artist, box: Bbox) -> bool:
    if isinstance(artist, Collection):
        offsets = artist.get_offsets()
        paths = artist.get_paths()
        if len(paths) and (len(offsets) <= 1):
            t = artist.get_transform()
            return any(t.transform_path(p).intersects_bbox(box, filled=True) for p in paths)
        pts = artist.get_offset_transform().transform(np.asarray(offsets))
        return bool(np.any((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1)
                           & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)))
    path = _display_path(artist)
    if path is None:
        return False
    filled = isinstance(artist, Patch) and artist.get_fill()
    if path.intersects_bbox(box, filled=filled):
        return True
    if isinstance(artist, Line2D) and artist.get_marker() not in (None, "None", "", " "):
        pts = path.vertices
        return bool(np.any((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1)
                           & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)))
    return False


def overlapping_texts(fig: Figure, within=None) -> list[str]:
    """Pairs of texts whose boxes overlap (``within``: only texts for which
    ``within(text)`` is true, e.g. the texts drawn in one axes)."""
    boxes = [(t, b) for t, b in text_boxes(fig) if within is None or within(t)]
    bad = []
    for i, (t1, b1) in enumerate(boxes):
        for t2, b2 in boxes[i + 1:]:
            inter = Bbox.intersection(b1, b2)
            if inter is not None and inter.width > TOL and inter.height > TOL:
                bad.append(f"{t1.get_text()!r} overlaps {t2.get_text()!r}")
    return bad


def problems(fig: Figure) -> list[str]:
    """Every problem found in the written figure: texts off the canvas, legends over data."""
    rendered(fig)
    return texts_off_canvas(fig) + legend_over_data(fig)


def edge_margins(fig: Figure, artist) -> tuple[float, float, float, float]:
    """Distances (pixels) from ``artist``'s drawn box to the canvas's left, bottom,
    right and top edges; negative where it leaves the canvas."""
    b = artist.get_window_extent(_renderer(fig))
    c = fig.bbox
    return (b.x0 - c.x0, b.y0 - c.y0, c.x1 - b.x1, c.y1 - b.y1)


def legend_margin(fig: Figure) -> float:
    """The least distance (points) between a legend and the canvas edge (``inf``
    without legends)."""
    legends = [leg for leg in fig.findobj(Legend) if leg.get_visible()]
    if not legends:
        return float("inf")
    return min(min(edge_margins(fig, leg)) for leg in legends) * 72.0 / fig.dpi


def marker_boxes(fig: Figure, line: Line2D) -> list[Bbox]:
    """The drawn box of each marker of ``line`` (marker size plus edge width)."""
    if line.get_marker() in (None, "None", "", " "):
        return []
    half = (line.get_markersize() + line.get_markeredgewidth()) / 2 * fig.dpi / 72.0
    xy = line.get_transform().transform(line.get_xydata())
    return [Bbox.from_extents(x - half, y - half, x + half, y + half)
            for x, y in xy if np.isfinite(x) and np.isfinite(y)]


def texts_on_markers(fig: Figure, within=None) -> list[str]:
    """Texts of an axes whose boxes meet a marker drawn in it (a cross on a number),
    whichever is on top: either hides the other. ``within`` as in
    :func:`overlapping_texts`."""
    boxes = text_boxes(fig)
    bad = []
    for ax in fig.axes:
        for line in ax.get_lines():
            if not line.get_visible():
                continue
            for mb in marker_boxes(fig, line):
                for t, b in boxes:
                    if t.axes is not ax or (within is not None and not within(t)):
                        continue
                    inter = Bbox.intersection(b, mb)
                    if inter is not None and inter.width > TOL and inter.height > TOL:
                        name = line.get_gid() or line.get_label()
                        bad.append(f"{t.get_text()!r} meets a marker of {name!r}")
    return bad


def drawn_over(a, b) -> bool:
    """Whether artist ``a`` is drawn after, so on top of, artist ``b`` of the same axes
    (matplotlib draws an axes' children by zorder, in the order added among equals)."""
    ax = a.axes
    assert ax is not None and ax is b.axes, "the artists must share an axes"
    order = ax.get_children()
    return (a.get_zorder(), order.index(a)) > (b.get_zorder(), order.index(b))


def saved_dpi() -> float:
    """The dpi the project writes its PNGs at (``save_figure``'s default)."""
    import inspect

    from hga_jax.host.plots import save_figure

    return inspect.signature(save_figure).parameters["dpi"].default


def written(fig: Figure) -> Figure:
    """``fig`` laid out as its PNG is written, then measured at the PNG's dpi."""
    rendered(fig)
    fig.set_dpi(saved_dpi())
    return fig


def by_gid(ax, gid: str) -> list:
    """The artists of ``ax`` tagged ``gid``."""
    return [a for a in ax.get_children() if a.get_gid() == gid]


def legend_labels(ax) -> list[str]:
    """The texts of ``ax``'s legend, in order."""
    return [t.get_text() for t in ax.get_legend().get_texts()]
