"""The turn table of a scenario: every turn of a path, with the tangent that leaves it, judged once.

A tight-rope path is a chain of oriented circles ``c_0 (start), c_1, ..., c_m (goal)``
(ids of :mod:`hga_jax.model.tangents`). Its length is the sum, over the circles, of the
arc on ``c_k`` from where the tangent ``c_{k-1} -> c_k`` arrives to where the tangent
``c_k -> c_{k+1}`` leaves, plus that leaving tangent; its violations add up the same
way. When no two circles that can follow one another share a centre, an arrival
point depends only on the pair ``(c_{k-1}, c_k)`` and a departure point only on
``(c_k, c_{k+1})``, so each term is a function of the triple ``(a, b, c)`` alone and
is computed here once per scenario:

``length[a, b, c] = r_b * sweep + |tangent b -> c|`` and
``violations[a, b, c]`` = the arc's violations (obstacles other than b's own, the
field) + the tangent's (:mod:`hga_jax.model.tangents`),

with ``a = C`` standing for the start point (the first arc begins there) and
``c = C`` for the goal point (the last arc ends there, and no tangent follows). A
path's length is then ``sum_k length[c_{k-1}, c_k, c_{k+1}]``: one lookup per
circle of the path, whatever the number of obstacles. The sums equal
:func:`hga_jax.model.decode.decode_batch`'s (tested chromosome by chromosome); a scenario
with coincident centres that can follow one another (``usable`` is False) is
decoded leg by leg instead.

The arcs are judged by the rule of :func:`hga_jax.model.collision.arc_violations` in
float64, each against the obstacles that can reach its circle at all (the others
cannot come within their radius of any of its points). Host code (numpy); units are
metres.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import circle_ids
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from .tangents import TangentTable

MAX_ENTRIES = 2**24  # turns; 134 MB in float32 (n = 100 needs 8.6 million)


def entries(n: int, variants: int = 1) -> int:
    """Number of turns of a scenario with ``n`` obstacles and ``variants`` legs per pair
    of circles (1 for the tight rope, 3 under free turns): ``(V C + 1) * C * (V C + 1)``."""
    c = circle_ids.count(n)
    return (variants * c + 1) * c * (variants * c + 1)


def fits(n: int, variants: int = 1) -> bool:
    """Whether a table is built for ``n`` obstacles (tight rope: up to about 125; free
    turns: about 58; beyond that the fitness decodes leg by leg rather than hold a table
    of more than ``MAX_ENTRIES``)."""
    return entries(n, variants) <= MAX_ENTRIES


class TurnTable(NamedTuple):
    """``(V C + 1) * C * (V C + 1)`` turns, flattened (index ``(i * C + b) * (V C + 1) + d``:
    the leg ``i = v_a C + a`` arrives on ``b``, the leg ``d = v_b C + c`` leaves it, leg
    genes ``v`` of :mod:`hga_jax.model.cars.free_turns.legs`; ``V = 1`` for the tight rope, whose
    index is ``(a * C + b) * (C + 1) + c``; ``V C`` stands for the start and goal point).

    entries: ``(T, 2)`` per turn: length (m) and violations (a small integer, exact
    in floats) under the collision mode of the table. usable: whether lookups give
    the decoder's values (no coincident centres along any possible path).
    """

    entries: Any
    usable: bool


def usable(tb: TangentTable, back: int | None = None) -> bool:
    """No two circles that can follow one another on a path share a centre. ``back``:
    the first of four more pose circles (start, start, goal, goal: a car that reverses,
    :mod:`hga_jax.model.cars.reeds_shepp.reversing`), or None."""
    c = tb.circles.shape[0]
    ids = np.arange(c)
    obstacle = np.asarray(tb.obstacle)
    pose = ids if back is None else np.where(ids >= back, ids - back, ids)
    follows = ((ids[:, None] != ids[None, :])
               & ~((obstacle[:, None] == obstacle[None, :]) & (obstacle[:, None] >= 0))
               & ~circle_ids.is_goal(pose)[:, None]  # nothing leaves a goal circle
               & ~circle_ids.is_start(pose)[None, :])  # nothing arrives at a start circle
    return not bool(np.any(np.asarray(tb.coincident) & follows))


def build(tb: TangentTable, start, goal, centres, model_radii, bounds,
          collision: str, legs=None, back: int | None = None) -> TurnTable:
    """The turn table of a scenario from its float64 tangent table (see module doc).

    ``collision``: ``"full"`` tests every arc against the obstacles' model circles;
    ``"paper"`` only against the field (the paper's criterion judges segments only).
    ``legs``: a float64 :class:`~hga_jax.model.cars.free_turns.legs.LegTable` (free turns, the
    full rule): the legs between two circles are its ``V`` variants instead of the
    tangent alone. ``back``: as :func:`usable`.
    """
    f8 = np.float64
    tol = g.tolerances(f8)
    circles = np.asarray(tb.circles, f8)
    c = circles.shape[0]
    cx, cy, r, sign = (circles[:, i] for i in range(4))
    obstacle = np.asarray(tb.obstacle)
    centres = np.asarray(centres, f8).reshape(-1, 2)
    model_radii = np.asarray(model_radii, f8).reshape(-1)
    bounds = np.asarray(bounds, f8)
    start, goal = np.asarray(start, f8), np.asarray(goal, f8)
    if legs is None:
        t_vio = tb.violations_full if collision == "full" else tb.violations_paper
        parts = (tb.p1x, tb.p1y, tb.p2x, tb.p2y, tb.length, t_vio, tb.coincident)
    else:
        parts = (legs.p1x, legs.p1y, legs.p2x, legs.p2y, legs.length, legs.violations,
                 legs.coincident)
    p1x, p1y, p2x, p2y, t_len, t_vio, coincident = (
        np.asarray(v).reshape(-1, c, c) for v in parts)
    v = p1x.shape[0]

    def arriving(m):  # (V, C, C) by (gene, a, b) -> (V C, C): rows i = v C + a
        return m.reshape(v * c, c)

    def leaving(m):  # (V, C, C) by (gene, b, c) -> (C, V C): columns d = v C + c
        return m.transpose(1, 0, 2).reshape(c, v * c)

    # Arrival points on b (rows i = 0..VC-1, and i = VC: the start point) and departure
    # points from b (columns d = 0..VC-1, and d = VC: the goal point).
    arr_x = np.vstack([arriving(p2x.astype(f8)), np.full((1, c), start[0])])  # (VC+1, C)
    arr_y = np.vstack([arriving(p2y.astype(f8)), np.full((1, c), start[1])])
    dep_x = np.hstack([leaving(p1x.astype(f8)), np.full((c, 1), goal[0])])  # (C, VC+1)
    dep_y = np.hstack([leaving(p1y.astype(f8)), np.full((c, 1), goal[1])])
    t_len = np.hstack([leaving(t_len.astype(f8)), np.zeros((c, 1))])
    t_vio = np.hstack([leaving(t_vio.astype(f8)), np.zeros((c, 1))])
    # A departure from a circle into a coincident one is the arrival point itself
    # (the decoder's rule); such turns only occur when the table is not usable,
    # but give them the decoder's value anyway.
    coincident = np.hstack([leaving(coincident.astype(bool)), np.zeros((c, 1), bool)])

    out = np.empty((v * c + 1, c, v * c + 1, 2), f8)
    for b in range(c):
        ax, ay = arr_x[:, b][:, None], arr_y[:, b][:, None]  # (VC+1, 1)
        bx = np.where(coincident[b], ax, dep_x[b][None, :])  # (VC+1, VC+1)
        by = np.where(coincident[b], ay, dep_y[b][None, :])
        ax, ay = np.broadcast_to(ax, bx.shape), np.broadcast_to(ay, by.shape)
        swp = g.sweep(ax - cx[b], ay - cy[b], bx - cx[b], by - cy[b], sign[b], tol.angle)
        circle = (cx[b], cy[b], r[b], sign[b])
        near = col.arc_candidates(circle, obstacle[b], centres, model_radii)
        obs = col.obstacles(centres[near], model_radii[near], ndim=2, index=near)
        vio = col.arc_violations(circle, obstacle[b], (ax, ay, bx, by, swp), obs, bounds,
                                 tol.length, collision).astype(f8)
        out[:, b, :, 0] = r[b] * swp + t_len[b][None, :]
        out[:, b, :, 1] = vio + t_vio[b][None, :]
    return TurnTable(entries=out.reshape(-1, 2), usable=usable(tb, back))
