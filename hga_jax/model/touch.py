"""The obstacles a path goes round, numbered as users read them.

An obstacle's number counts from 1, in the order of the scenario file's
``[[obstacles]]`` tables: the same in the result files, messages, plots and the
Python results (``Path.touched``, ``ExactResult.touched``).
"""
from __future__ import annotations

from typing import NamedTuple, Sequence


class Touch(NamedTuple):
    """An obstacle a path goes round: its number (from 1, as in the scenario file,
    the result files, messages and plots) and the label (+1 CW, -1 CCW)."""

    obstacle: int
    label: int


def touch_list(pairs: Sequence[Sequence[int]]) -> list[dict[str, int]]:
    """``touched`` of the result files from :class:`Touch` pairs."""
    return [{"obstacle": int(k), "label": int(s)} for k, s in pairs]
