"""What the run figures share: colours, margins, and writing a figure to disk."""
from __future__ import annotations

from pathlib import Path

from matplotlib.figure import Figure

C_ARC, C_LINE, C_START, C_GOAL, C_TOUCH = "tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"
C_OPT, C_BAD, C_FREE = "black", "red", "tab:cyan"
EDGE_PAD_PT = 6.0  # margin (points) between a figure's contents and its edge


def save_figure(fig: Figure, path: str | Path, dpi: int = 140, vector: bool = False) -> Path:
    """Write ``fig`` as PNG to ``path`` atomically (parents created); return the path.
    ``vector``: also a PDF beside it (same name, ``.pdf``), for a paper's figures."""
    from hga_jax.host.output import atomic_write, figure_writer

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    atomic_write(str(path), figure_writer(fig, dpi), binary=True)
    if vector:
        atomic_write(str(path.with_suffix(".pdf")), figure_writer(fig, dpi, "pdf"), binary=True)
    return path
