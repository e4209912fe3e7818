"""Free turns: the car's shortest path, with turns on circles of radius rho in free space.

The paper's model (``turns = "tight-rope"``) turns only on the model circles: the
start and goal turning circles and the obstacles' model circles. A car with
minimum turning radius rho may also turn on any circle of radius rho in free space
(``turns = "free"``); between two close poses the shortest Dubins path is then
often turn-turn-turn, which no tight rope can express. The free circles an optimum
needs are those pinned by two contacts (:mod:`hga_jax.model.cars.free_turns.circles`).

Free circles have no obstacle of their own: their arcs are judged against every
obstacle and the field. Start and goal circles may also be entered and left in the
middle of a path. Circles that touch are joined at their contact point by a tangent
of length exactly 0 (:func:`hga_jax.model.geometry.tangent`).

:func:`build` makes the tangent graph over all these circles in the layout of
:mod:`hga_jax.model.exact` (searched by :mod:`hga_jax.model.graph_search`); the collision rule is
always ``"full"`` (the paper's criterion judges no arc against an obstacle, which
would let a free arc run through one). Host code (numpy, float64); metres and radians.
"""
from __future__ import annotations

import math

import numpy as np

from hga_jax.model import collision as col
from hga_jax.model import geometry as g

from hga_jax.model import circle_ids as ids
from hga_jax.model import tangent_graph
from hga_jax.model.cars.free_turns.circles import circles, reach
from hga_jax.model.graph_search import search, walk
from hga_jax.model.scenario import Scenario
from hga_jax.model.touch import Touch

TOL = g.tolerances(np.float64)


def _tangents(sc: Scenario, circ, bound: float = math.inf):
    """Every feasible directed tangent between two circles of ``circ``: ``(S, T, p1x,
    p1y, p2x, p2y, length)``. Never between the two orientations of one model circle,
    nor between circles with coincident centres, nor where a path from the start point
    through both circles' discs to the goal point is longer than ``bound`` (m) even in
    straight lines (so no path shorter than ``bound`` loses a tangent). Feasible: the full rule of
    :func:`hga_jax.model.collision.segment_violations` (exists, in the field, clear of
    every obstacle), applied one obstacle at a time to the tangents still clear, nearest
    obstacles first (most tangents are blocked, and soon: 6x faster at n = 40)."""
    x, y, r, sg, own = circ
    c = x.size
    sa = sc.arrays(np.float64)
    a, b = (m.ravel() for m in np.meshgrid(np.arange(c), np.arange(c), indexing="ij"))
    keep = (a != b) & ~((own[a] == own[b]) & (own[a] >= 0))
    gap = np.hypot(x[b] - x[a], y[b] - y[a])
    keep &= gap >= TOL.eps
    if math.isfinite(bound):
        to, back = reach(sc, x, y, r)
        keep &= to[a] + np.maximum(gap - r[a] - r[b], 0.0) + back[b] <= bound
    a, b = a[keep], b[keep]
    one, zero = np.ones(a.size), np.zeros(a.size)
    t = g.tangent(x[a], y[a], r[a], sg[a], x[b], y[b], r[b], sg[b], one, zero, TOL.eps)
    ends = (t.p1x, t.p1y, t.p2x, t.p2y)
    no_obstacles = col.obstacles(np.zeros((0, 2)), np.zeros(0), ndim=1)
    clear = col.segment_violations(ends, t.exists, no_obstacles, sa.bounds, TOL.length,
                                   "full") == 0
    if math.isfinite(bound):  # the same bound through the tangent's own touch points
        clear &= (np.hypot(t.p1x - sc.start[0], t.p1y - sc.start[1]) + t.length
                  + np.hypot(t.p2x - sc.goal[0], t.p2y - sc.goal[1]) <= bound)
    alive = np.flatnonzero(clear)
    centres, radii = np.asarray(sa.centres), np.asarray(sa.model_radii)
    if centres.size:
        mid = np.array([np.mean(x), np.mean(y)])
        for j in np.argsort(np.hypot(*(centres - mid).T)):
            e = tuple(v[alive] for v in ends)
            hit = col.segment_hits(*e, centres[j, 0], centres[j, 1], radii[j], TOL.length)
            alive = alive[~hit]
    return a[alive], b[alive], t.p1x[alive], t.p1y[alive], t.p2x[alive], t.p2y[alive], \
        t.length[alive]


def build(sc: Scenario, bound: float = math.inf):
    """The free-turn tangent graph of ``sc`` (an :class:`hga_jax.model.graph_search.Graph`, by
    :func:`graph`) over every circle of :func:`circles` and every feasible tangent
    between them. With a finite ``bound`` (m) it leaves out the circles and tangents
    that no path shorter than ``bound`` can use (:func:`hga_jax.model.cars.free_turns.circles.circles`, :func:`_tangents`)."""
    circ = circles(sc, bound)
    return graph(sc, circ, _tangents(sc, circ, bound))


def graph(sc: Scenario, circ, pieces, enter=None):
    """A free-turn tangent graph over the circles ``circ`` (``(x, y, r, sign, own)``) from
    its straight ``pieces`` ``(S, T, p1x, p1y, p2x, p2y, length)`` (feasible, from circle
    S at P1 to circle T at P2; any length, so a piece may stand for a curve): the one
    assembly (:func:`hga_jax.model.tangent_graph.assemble`) with the poses' circles as
    rings that a path may enter and leave anywhere. ``enter``: per piece the obstacle it
    enters (for a search that enters each obstacle once), else -1."""
    return tangent_graph.assemble(sc.arrays(np.float64), circ, pieces, "rings", "full",
                                  enter=enter)


def _arc_circles(gr, edges: list[int]) -> list[int]:
    """The circle of each arc segment of :func:`hga_jax.model.exact._walk`'s segments, in
    order (the walk merges consecutive arc edges on one circle into one segment)."""
    out, arc_on = [], -1
    for k in edges:
        c = int(gr.arc_circle[k])
        if c < 0:
            arc_on = -1
        elif gr.sweep[k] > 0.0:
            if arc_on != c:
                out.append(c)
            arc_on = c
    return out


def shortest(sc: Scenario, bound: float = math.inf):
    """The free-turn optimum of ``sc``: ``(length, segments, touched, free_arcs)``, with
    ``length`` inf and empty lists when no path exists (or, with a finite ``bound`` in
    metres, none shorter than it: pass a known path's length, such as the tight-rope
    optimum's, a little raised). Segments are those of the
    result files; an arc on a free circle carries ``"free": true``. ``touched``: the
    :class:`~hga_jax.model.path.Touch` ``(obstacle number from 1, label)`` model circles
    the path turns on, in travel order."""
    gr = build(sc, bound)
    gx, gy = float(sc.goal[0]), float(sc.goal[1])
    h = np.hypot(gr.nx - gx, gr.ny - gy).tolist()
    length, edges, _ = search(gr, h, distinct=False)
    if not edges:
        return float("inf"), [], [], 0
    circs, segs = walk(gr, edges)
    first_free = ids.count(sc.n)
    arcs = iter(_arc_circles(gr, edges))
    free = 0
    for seg in segs:
        if seg["type"] == "arc" and next(arcs) >= first_free:
            seg["free"] = True
            free += 1
    own, sg = gr.circles[4], gr.circles[3]
    touched = [Touch(int(own[c]) + 1, int(sg[c])) for c in circs
               if not ids.is_pose(c) and c < first_free]
    return float(length), segs, touched, free
