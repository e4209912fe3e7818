"""A line style per configuration of a study (colour, dash, marker), and curves drawn so
that every one shows: markers at sparse, staggered points; curves that coincide drawn
widest first with the others on top, and named."""
from __future__ import annotations

from typing import Any

import matplotlib
import numpy as np
from matplotlib.lines import Line2D

MARKERS = ("o", "s", "^", "D", "v", "<", "p")  # 7 markers with 10 colours: 70 pairs
MARK_STEP = 0.12  # between a line's markers: this fraction of its panel's diagonal
LINE_W = 1.2  # points; a curve under others that coincide with it is wider


def colours(n: int):
    """``n`` distinct colours: tab10's, then (beyond 10) tab20's light shades."""
    if n <= 10:
        cmap = matplotlib.colormaps["tab10"]
        return [cmap(i) for i in range(n)]
    cmap = matplotlib.colormaps["tab20"]
    order = list(range(0, 20, 2)) + list(range(1, 20, 2))
    return [cmap(order[i % 20]) for i in range(n)]


def styles(configs: list[str]) -> dict[str, dict[str, Any]]:
    """A line style per configuration, every one told apart: tab10's colours, solid
    for the first ten, then dashed, dotted and dash-dotted (40 in all, then again), and
    one of seven markers (no two of the first 70 share colour and marker); ``start``
    staggers where a line's sparse markers fall, so lines that meet show each one's."""
    cmap = matplotlib.colormaps["tab10"]
    dashes = ("-", "--", ":", "-.")
    return {c: {"color": cmap(i % 10), "ls": dashes[(i // 10) % 4],
                "marker": MARKERS[i % len(MARKERS)], "start": (i * 0.618034) % 1.0}
            for i, c in enumerate(configs)}


def proxy(style: dict[str, Any]) -> Line2D:
    """A legend entry in a configuration's style (line and marker), drawn nowhere."""
    return Line2D([], [], color=style["color"], ls=style["ls"], lw=LINE_W,
                  marker=style["marker"], ms=4.5, mec="white", mew=0.5)


def coinciding(curves: dict[str, tuple[np.ndarray, np.ndarray]]) -> list[list[str]]:
    """Sets (two or more, in the order of ``curves``) of configurations whose curves
    ``(x, y)`` are the same points (missing values in the same places)."""
    classes: list[list[str]] = []
    for c, (x, y) in curves.items():
        for cls in classes:
            x0, y0 = curves[cls[0]]
            if (np.shape(x) == np.shape(x0) and np.shape(y) == np.shape(y0)
                    and np.allclose(x, x0, rtol=1e-9, atol=0, equal_nan=True)
                    and np.allclose(y, y0, rtol=1e-9, atol=1e-12, equal_nan=True)):
                cls.append(c)
                break
        else:
            classes.append([c])
    return [cls for cls in classes if len(cls) > 1]


def draw(ax, curves: dict[str, tuple[np.ndarray, np.ndarray]], lines: dict,
          step: bool = False) -> list[list[str]]:
    """Draw each configuration's curve (``step``: an ECDF's steps) in its style, with
    markers at sparse points. Curves that coincide: the first one widest, each next one
    narrower on top of it, their markers spread apart, so that every one shows.
    Returns the sets of configurations whose curves coincide."""
    same = coinciding(curves)
    place = {c: (k, len(cls), lines[cls[0]]["start"]) for cls in same for k, c in enumerate(cls)}
    for c, (x, y) in curves.items():
        st = lines[c]
        k, n, start = place.get(c, (0, 1, st["start"]))
        # Markers spaced along the drawn line need a point to measure from.
        some = bool(np.any(np.isfinite(np.asarray(x, float)) & np.isfinite(np.asarray(y, float))))
        ax.plot(x, y, color=st["color"], ls=st["ls"], lw=LINE_W + 1.4 * (n - 1 - k),
                marker=st["marker"] if some else "", ms=4.5, mec="white", mew=0.5,
                markevery=(((start + k / n) % 1.0) * MARK_STEP, MARK_STEP) if some else None,
                drawstyle="steps-post" if step else "default", label=c, gid=c)
    return same


class Drawn:
    """The curves of a figure's panels: per configuration the panels it is drawn in,
    and the sets of configurations whose curves coincide, with the panels where."""

    def __init__(self, lines: dict[str, dict[str, Any]]):
        self.lines = lines
        self.panels: list[str] = []
        self.where: dict[str, set[str]] = {}
        self.same: dict[tuple[str, ...], list[str]] = {}

    def draw(self, ax, panel: str, curves: dict, step: bool = False) -> None:
        """:func:`draw` the ``curves`` in ``ax``, the panel named ``panel``."""
        self.panels.append(panel)
        for c in curves:
            self.where.setdefault(c, set()).add(panel)
        for cls in draw(ax, curves, self.lines, step):
            self.same.setdefault(tuple(cls), []).append(panel)

    def handles(self, configs: list[str]) -> dict[str, Any]:
        """Legend entries of the configurations drawn, in the order given."""
        return {c: proxy(self.lines[c]) for c in configs if c in self.where}

    def note(self) -> str:
        """Words naming the configurations whose curves coincide, and where."""
        parts = []
        for cls, where in self.same.items():
            names = " = ".join(f"\u201c{c}\u201d" for c in cls)
            shared = set.intersection(*(self.where[c] for c in cls))
            if len(self.panels) <= 1:
                parts.append(names)
            elif len(where) == len(self.panels):
                parts.append(f"{names} (every panel)")
            elif len(where) == len(shared):
                parts.append(f"{names} (every panel they are all in)")
            elif len(where) <= 3:
                parts.append(f"{names} ({'; '.join(where)})")
            else:
                parts.append(f"{names} ({len(where)} of {len(self.panels)} panels)")
        if not parts:
            return ""
        return ("Curves that coincide (the first drawn widest, the others on top, markers "
                "apart): " + "; ".join(parts))
