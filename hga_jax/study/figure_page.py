"""The page a study figure is drawn on: a journal page's width, the PNG's dpi, the text
size; making a figure at that dpi and saving it (PNG and PDF); text measured and
wrapped to fit a width in inches."""
from __future__ import annotations

import textwrap
from functools import lru_cache
from typing import Any

from matplotlib.figure import Figure
from matplotlib.font_manager import FontProperties

from hga_jax.host.plots import save_figure

WIDTH = 7.2  # inches: a journal page
DPI = 140  # the PNG's; a figure is laid out at it, as text widths differ from one dpi to another
TEXT = 7  # points: ticks, legends, notes


def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] | None = None,
             layout: str | None = None, **kwargs: Any) -> tuple[Figure, Any]:
    """``(figure, axes)`` like ``pyplot.subplots`` (``figsize`` in inches, ``layout`` as
    matplotlib's), on a ``Figure`` that no backend or pyplot state holds, at the dpi it
    is saved at (:data:`DPI`: a constrained layout worked out at another dpi may leave
    too little room for text drawn at this one)."""
    fig = Figure(figsize=figsize, layout=layout, dpi=DPI)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def save(fig: Figure, path: str) -> str:
    """Write a PNG and a PDF beside it atomically (:func:`~hga_jax.host.plots.save_figure`);
    return ``path`` (the PNG's)."""
    save_figure(fig, path, dpi=DPI, vector=True)
    return path



@lru_cache(maxsize=1)
def _renderer():
    from matplotlib.backends.backend_agg import RendererAgg  # measures; draws nothing

    return RendererAgg(8, 8, DPI)


@lru_cache(maxsize=4096)
def _line_width(line: str, size: float) -> float:
    if not line.strip():
        return 0.0
    w, _, _ = _renderer().get_text_width_height_descent(line, FontProperties(size=size), False)
    return 1.02 * w / DPI  # as the PNG draws it, and a little room


def text_width(text: str, size: float = TEXT) -> float:
    """Inches the widest line of ``text`` takes at ``size`` points (the default font)."""
    return max(_line_width(line, size) for line in text.split("\n"))


def wrap(text: str, width: float, size: float = TEXT) -> str:
    """``text`` broken at spaces into lines at most ``width`` inches wide at ``size``
    points (a word wider than that is broken too); its own line breaks are kept."""
    out = []
    for line in text.split("\n"):
        full = _line_width(line, size)
        if full <= width:
            out.append(line)
            continue
        chars = max(4, int(len(line) * width / full) + 1)
        while True:
            parts = textwrap.wrap(line, chars, break_on_hyphens=False) or [""]
            if chars <= 4 or all(_line_width(p, size) <= width for p in parts):
                break
            chars -= 1
        out += parts
    return "\n".join(out)


def lines_of(text: str) -> int:
    return text.count("\n") + 1


def height(lines: int, size: float = TEXT) -> float:
    """Inches that ``lines`` lines of text take at ``size`` points."""
    return lines * size * 1.25 / 72
