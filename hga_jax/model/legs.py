"""Per-leg information for the path operators: which obstacles block each tangent.

The operators of :mod:`hga_jax.search.path_ops` may look at the legs of a path the way
TSP operators look at a distance matrix: for every directed tangent ``a -> c``
between two oriented circles (ids of :mod:`hga_jax.model.tangents`) they may ask which
obstacles its segment passes through. They never search over whole paths.

- ``blockers[a, c, j]``: the segment of the tangent ``a -> c`` comes closer to
  obstacle ``j``'s centre than its model radius (the full criterion of
  :func:`hga_jax.model.collision.segment_obstacles`; a missing tangent's stand-in
  counts too).
- ``blocked[a, c]``: some obstacle blocks the segment.
- ``length[a, c]``: the length of the tangent's segment (m), as a TSP distance.
- ``bad[a, c]``: the tangent has a violation of its own (an obstacle, the field,
  a missing tangent: :mod:`hga_jax.model.tangents`).
- ``penalty``: the penalty per violation ``delta`` (m) of the fitness.
- ``listed[a, c]`` and ``count[a, c]``: the blockers of ``a -> c`` in index order
  (the rest after them) and how many there are, so that a move draws a blocker in two
  look-ups (:func:`listed`).

Nothing here depends on a path: an arc's length and violations depend on the
legs before and after it, and only decoding a chromosome gives them.

Under free turns (:func:`free_aware`) a pair whose tangent is bad but whose leg gene 0
runs over a clear free circle (:class:`~hga_jax.model.free_legs.LegTable`) counts as
clear, with that leg's length: the operators see the legs the decoder will take.

Host code (numpy), built once per scenario from the float64 tangent table.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from .tangents import TangentTable


class Legs(NamedTuple):
    """``blockers`` (C, C, n), ``blocked`` and ``bad`` (C, C) bool, ``length`` (C, C)
    metres, ``penalty`` () metres, ``listed`` (C, C, n) and ``count`` (C, C) int16 (see
    module doc). ``ends``: not None where the path's ends are not the path moves' (a
    reversing car's: the start's and goal's labels go with their gears,
    :mod:`hga_jax.search.end_ops`)."""

    blockers: Any
    blocked: Any
    length: Any = None
    bad: Any = None
    penalty: Any = None
    ends: Any = None
    listed: Any = None
    count: Any = None


def listed(blockers) -> tuple[np.ndarray, np.ndarray]:
    """``(listed, count)`` of a blocker table (C, C, n): per tangent the indices of its
    blockers in increasing order followed by the other obstacles' (int16), and the
    number of blockers (int16). ``listed[a, c, r]`` is the ``r``-th True entry of
    ``blockers[a, c]`` for ``r < count[a, c]``, and obstacle 0 where there is none."""
    b = np.asarray(blockers, bool)
    order = np.argsort(~b, axis=-1, kind="stable").astype(np.int16)
    return order, b.sum(axis=-1).astype(np.int16)


def build(tb: TangentTable, centres, model_radii, penalty: float = 0.0) -> Legs:
    """The legs of a scenario from its tangent table (float64 recommended); ``penalty``:
    the fitness's penalty per violation (m)."""
    f8 = np.float64
    tol = g.tolerances(f8)
    centres = np.asarray(centres, f8).reshape(-1, 2)
    radii = np.asarray(model_radii, f8).reshape(-1)
    ends = tuple(np.asarray(v, f8) for v in (tb.p1x, tb.p1y, tb.p2x, tb.p2y))  # (C, C)
    obstacles = col.obstacles(centres, radii, ndim=2)
    hits = col.segment_obstacles(ends, obstacles, tol.length, "full")  # (n, C, C)
    hits = np.ascontiguousarray(np.moveaxis(np.asarray(hits, bool), 0, -1))
    order, count = listed(hits)
    return Legs(blockers=hits, blocked=np.any(hits, axis=-1),
                length=np.asarray(tb.length, f8), bad=np.asarray(tb.violations_full) > 0,
                penalty=np.asarray(penalty, f8), listed=order, count=count)


def free_aware(legs: Legs, table) -> Legs:
    """``legs`` with the pairs whose gene-0 leg of the float64 leg ``table`` is free
    made clear (no blockers, not bad) and given that leg's length."""
    free = np.asarray(table.free[0], bool)
    hits = legs.blockers & ~free[..., None]
    order, count = listed(hits)
    return legs._replace(blockers=hits, blocked=legs.blocked & ~free, listed=order, count=count,
                         bad=legs.bad & ~free,
                         length=np.where(free, np.asarray(table.length[0], np.float64),
                                         legs.length))
