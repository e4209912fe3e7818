"""Per-leg information for the path operators: which obstacles block each tangent.

The operators of :mod:`hga_jax.search.path_ops` may look at the legs of a path the way
TSP operators look at a distance matrix: for every directed tangent ``a -> c``
between two oriented circles (ids of :mod:`hga_jax.model.tangents`) they may ask which
obstacles its segment passes through. They never search over whole paths.

- ``blockers[a, c, j]``: the segment of the tangent ``a -> c`` comes closer to
  obstacle ``j``'s centre than its model radius (the full criterion of
  :func:`hga_jax.model.collision.segment_obstacles`; a missing tangent's stand-in
  counts too); with :func:`with_end_arcs`, also an obstacle that a goal arc meets.
- ``blocked[a, c]``: some obstacle blocks the segment.
- ``length[a, c]``: the length of the tangent's segment (m), as a TSP distance (with
  :func:`with_end_arcs`, plus the start or goal arc of a first or last leg).
- ``bad[a, c]``: the tangent has a violation of its own (an obstacle, the field,
  a missing tangent: :mod:`hga_jax.model.tangents`; with :func:`with_end_arcs`, or its
  end arc has one).
- ``penalty``: the penalty per violation ``delta`` (m) of the fitness.
- ``listed[a, c]`` and ``count[a, c]``: the blockers of ``a -> c`` in index order
  (the rest after them) and how many there are, so that a move draws a blocker in two
  look-ups (:func:`listed`).

The start and goal arcs are part of the first and last legs (:func:`with_end_arcs`):
the start arc runs from the start pose to where the leg leaving the start circle
departs, the goal arc from where the leg into the goal circle arrives to the goal
pose, so each depends on its one leg. A leg out of a start circle or into a goal
circle counts its arc's length, and the arc's meeting an obstacle or leaving the
field as a violation of its own. The obstacles a goal arc meets are blockers of its
leg too (but the obstacle at the leg's first circle, already touched), so that a wrap
moves the arrival on the goal circle past them; a start arc's are not (measured:
wrapping them as well cost a development scene at 40 obstacles, whose start circle
overlaps an obstacle that most first legs' arcs meet, 89 -> 66 % of runs; docs/results.md).
Nothing else here depends on a path: an arc on an obstacle's circle depends on the
legs before and after it, and only decoding a chromosome gives it.

Under free turns (:func:`free_aware`) a pair whose tangent is bad but whose leg gene 0
runs over a clear free circle (:class:`~hga_jax.model.cars.free_turns.legs.LegTable`) counts as
clear, with that leg's length: the operators see the legs the decoder will take (and
the end arcs are folded in from where those legs leave and arrive).

Host code (numpy), built once per scenario from the float64 tangent table.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import circle_ids
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from .tangents import TangentTable


class Legs(NamedTuple):
    """``blockers`` (C, C, n), ``blocked`` and ``bad`` (C, C) bool, ``length`` (C, C)
    metres, ``penalty`` () metres, ``listed`` (C, C, n) and ``count`` (C, C) int16 (see
    module doc). ``ends``: not None where the path's ends are not the path moves' (a
    reversing car's: the start's and goal's labels go with their gears,
    :mod:`hga_jax.search.end_ops`). ``clearer``: the search's ``wrap_clearer`` share
    (a float32 scalar; None: every wrap takes a random side), set by the GA. ``arcs``
    (C, C, C) bool: True where the arc on circle ``b`` from the tangent ``a -> b`` to the
    tangent ``b -> c`` has a violation of its own (:func:`arcs_from_turns`; None without
    a turn table); ``arc_share``: the search's ``guided_arcs`` (float32), set by the GA."""

    blockers: Any
    blocked: Any
    length: Any = None
    bad: Any = None
    penalty: Any = None
    ends: Any = None
    listed: Any = None
    count: Any = None
    clearer: Any = None
    arcs: Any = None
    arc_share: Any = None


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


def with_end_arcs(legs: Legs, tb: TangentTable, start, goal, centres, model_radii,
                  bounds, points=None) -> Legs:
    """``legs`` (of :func:`build`) with the start and goal arcs in the legs they belong
    to (module doc): for a leg ``a -> c`` out of a start circle ``a``, the arc on ``a``
    from the start point to the leg's departure point; for a leg into a goal circle
    ``c``, the arc on ``c`` from the leg's arrival point to the goal point (a direct leg
    from a start to a goal circle has both). Each arc adds its length (m) to the leg's
    and makes the leg bad when it meets an obstacle's model circle (the full rule) or
    leaves the field ``bounds``; the obstacles a goal arc meets become blockers of its
    leg, but the obstacle at the leg's first circle. Arcs measured as
    :mod:`hga_jax.model.turns` measures them (float64). ``points``: ``(p1x, p1y, p2x,
    p2y, coincident)`` (C, C) of the legs the path takes, where they are not the
    tangents of ``tb`` (under free turns, gene 0's legs)."""
    f8 = np.float64
    tol = g.tolerances(f8)
    circles = np.asarray(tb.circles, f8)
    ids = np.arange(circles.shape[0])
    centres = np.asarray(centres, f8).reshape(-1, 2)
    obstacles = col.obstacles(centres, np.asarray(model_radii, f8).reshape(-1), ndim=1)
    bounds = np.asarray(bounds, f8)
    if points is None:
        points = (tb.p1x, tb.p1y, tb.p2x, tb.p2y, tb.coincident)
    p1x, p1y, p2x, p2y = (np.asarray(v, f8) for v in points[:4])
    coincident = np.asarray(points[4], bool)
    blockers, bad = legs.blockers.copy(), legs.bad.copy()
    length = np.asarray(legs.length, f8).copy()

    def fold(b, ax, ay, bx, by, rows, cols, other=None):
        """The arcs on circle ``b`` from ``(ax, ay)`` to ``(bx, by)`` (1-D, one per leg
        ``(rows[k], cols[k])``) added to those legs; with ``other`` (the obstacle at
        each leg's other end), their obstacles as blockers but that one."""
        cx, cy, r, sign = circles[b]
        swp = g.sweep(ax - cx, ay - cy, bx - cx, by - cy, sign, tol.angle)
        circle, arc = (cx, cy, r, sign), (ax, ay, bx, by, swp)
        hits = col.arc_obstacles(circle, -1, arc, obstacles, tol.length, "full").T  # (k, n)
        out = col.arc_leaves_field(circle, arc, bounds, tol.length)
        length[rows, cols] += r * swp
        bad[rows, cols] |= hits.any(axis=-1) | out
        if other is not None:
            blockers[rows, cols] |= hits & (np.arange(hits.shape[-1]) != other[:, None])

    sx, sy, gx, gy = float(start[0]), float(start[1]), float(goal[0]), float(goal[1])
    for b in ids[circle_ids.is_start(ids)]:
        bx = np.where(coincident[b], sx, p1x[b])
        by = np.where(coincident[b], sy, p1y[b])
        fold(b, np.full_like(bx, sx), np.full_like(by, sy), bx, by, np.full_like(ids, b), ids)
    for b in ids[circle_ids.is_goal(ids)]:
        ax, ay = p2x[:, b], p2y[:, b]
        fold(b, ax, ay, np.full_like(ax, gx), np.full_like(ay, gy), ids, np.full_like(ids, b),
             np.asarray(tb.obstacle))
    order, count = listed(blockers)
    return legs._replace(blockers=blockers, blocked=np.any(blockers, axis=-1), bad=bad,
                         length=length, listed=order, count=count)


def with_blockers_of(legs: Legs, other: Legs) -> Legs:
    """``legs`` with the blockers of ``other`` (``blockers``, ``blocked``, ``listed``,
    ``count``): among robots that move, the static rules' legs (lengths and violations)
    with the blockers that the moving robots' placed circles add
    (:meth:`~hga_jax.model.scenario.Scenario.guide_radii`)."""
    return legs._replace(blockers=other.blockers, blocked=other.blocked, listed=other.listed,
                         count=other.count)


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


def arcs_from_turns(entries, tangent_violations) -> np.ndarray:
    """Which arcs on circles have a violation of their own (C, C, C) bool, indexed ``[a,
    b, c]`` as the turn :mod:`hga_jax.model.turns` (tight rope) from ``a`` to ``c`` round
    ``b``: the turn's violations less those of its leaving tangent ``b -> c``
    (``tangent_violations`` (C, C), of the same collision rule). The arc of a start or
    goal circle is part of its leg already (:func:`with_end_arcs`)."""
    v = np.asarray(tangent_violations)
    c = v.shape[0]
    turn = np.asarray(entries)[:, 1].reshape(c + 1, c, c + 1)[:c, :, :c]
    return (turn - v[None, :, :]) > 0.5
