"""How numbers and touches are written in every message and summary.

Counts have thousands separators and a noun that agrees (``"1 run"``, ``"1,000
runs"``), percentages two decimals, and the obstacles a path goes round their
numbers from 1 with the turning direction (``"2CW 4CW 5CCW"``).
"""
from __future__ import annotations

from typing import Sequence


def count(k: int, noun: str, plural: str | None = None) -> str:
    """``"1 run"``, ``"1,000 runs"``."""
    return f"{k:,} {noun if k == 1 else plural or noun + 's'}"


def pct(x: float | None) -> str:
    """A fraction as a percentage with two decimals (``"n/a"`` for None)."""
    return "n/a" if x is None else f"{100 * x:.2f}%"


def touches(touched: Sequence[Sequence[int]]) -> str:
    """``"2CW 4CW 5CCW"`` from :class:`~hga_jax.model.touch.Touch` pairs (obstacles
    numbered from 1)."""
    return " ".join(f"{k}{'CW' if s > 0 else 'CCW'}" for k, s in touched) or "no obstacle"
