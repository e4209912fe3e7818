"""The tangent graph of a model: the one assembly both exact solvers search.

Nodes are points on oriented circles (``(x, y, r, sign, own)``, numbered by
:mod:`hga_jax.model.circle_ids`, a model's added circles after the scenario's): the
start point on the start circles (nodes 0, 1), the goal point on the goal circles
(2, 3), then both ends of every straight *piece* (a feasible tangent, or a piece that
stands for a curve, such as a free leg): its start on circle ``S`` (nodes ``4 ..
4 + e - 1``), then its end on circle ``T`` (``4 + e ..``). Edges:

- the pieces, from start to end, of their given length;
- arcs between consecutive nodes of each circle in its direction, all the way round
  (:func:`ring`), judged by the one arc rule (:func:`hga_jax.model.collision.arcs_clear`);
  two nodes within the angle tolerance also get a zero-length reverse edge, since the
  decoder counts a sweep within it of 2 pi as 0.

How the poses' circles are travelled is the model's (``poses``):

- ``"ends"`` (the tight rope): a start circle is only left and a goal circle only
  entered, so the start point begins its circle's order and no arc passes it, and
  the goal point ends its circle's order; a start circle that coincides with a goal
  circle also gets the arc from the start point to the goal point (on the goal circle);
- ``"rings"`` (free turns): the poses' circles are rings like any other, which a path
  may enter and leave anywhere; the start point joins the first node after it, the
  last node before the goal point joins it, and a start circle that coincides with a
  goal circle gets the arc between the two points (on the start circle).

Host code (numpy, float64); metres and radians. Searched by
:mod:`hga_jax.model.graph_search`.
"""
from __future__ import annotations

import numpy as np

from hga_jax.model import circle_ids as ids
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from .graph_search import Graph

TOL = g.tolerances(np.float64)
POSES = ("ends", "rings")


def ring(ncirc: np.ndarray, key: np.ndarray, tie: np.ndarray, nodes: np.ndarray):
    """Consecutive ``nodes`` of each circle in its direction: sorted by circle, then
    ``key`` (a sweep from the circle's reference), then ``tie``; each node to the
    next, and the last of a circle with two or more nodes back to its first. Returns
    ``(a, b)``, node indices."""
    order = nodes[np.lexsort((tie[nodes], key[nodes], ncirc[nodes]))]
    co = ncirc[order]
    same = co[1:] == co[:-1]
    first = np.flatnonzero(np.r_[True, ~same])
    last = np.r_[first[1:] - 1, order.size - 1]
    multi = last > first
    return (np.concatenate([order[:-1][same], order[last[multi]]]),
            np.concatenate([order[1:][same], order[first[multi]]]))


def _sweep(circ, c, ax, ay, bx, by):
    """Sweep (rad) on circles ``c`` from A to B in their direction."""
    x, y, _, sg, _ = circ
    return g.sweep(ax - x[c], ay - y[c], bx - x[c], by - y[c], sg[c], TOL.angle)


def _from_x(circ, c, px, py):
    """Sweep on circles ``c`` from their point towards +x to P."""
    x, y, _, sg, _ = circ
    return g.sweep(np.ones(c.size), np.zeros(c.size), px - x[c], py - y[c], sg[c], TOL.angle)


def _ends(circ, sa, nx, ny, ncirc, coincident=None):
    """Arc pairs of ``poses = "ends"`` (module doc)."""
    x, y = circ[0], circ[1]
    node = np.arange(nx.size)
    on_start, on_goal = ids.is_start(ncirc), ids.is_goal(ncirc)
    st, gl = sa.start, sa.goal
    key = np.where(on_goal, -_sweep(circ, ncirc, nx, ny, np.full(nx.size, gl[0]),
                                    np.full(nx.size, gl[1])),
                   np.where(on_start, _sweep(circ, ncirc, np.full(nx.size, st[0]),
                                             np.full(nx.size, st[1]), nx, ny),
                            _from_x(circ, ncirc, nx, ny)))
    tie = np.where(ids.is_goal(node), nx.size, node)  # the goal point after its equals
    a, b = ring(ncirc, key, tie, node)
    legal = ~ids.is_start(b) & ~ids.is_goal(a)  # no arc into the start, out of the goal
    a, b = a[legal], b[legal]
    same = np.hypot(x[:2] - x[2:4], y[:2] - y[2:4]) < TOL.eps if coincident is None \
        else np.asarray(coincident, bool)
    ac = ncirc[a]
    for s_c in np.flatnonzero(same):  # a start circle that is a goal circle: on the goal's
        g_c = ids.GOAL[0] + s_c
        a, b, ac = np.r_[a, s_c], np.r_[b, g_c], np.r_[ac, g_c]
    return a, b, ac


def _rings(circ, sa, nx, ny, ncirc, pose_nodes):
    """Arc pairs of ``poses = "rings"`` (module doc); ``pose_nodes``: ``(node, is_start)``
    of every pose point (the last ones after the pieces' ends)."""
    x, y, r, sg = circ[:4]
    node = np.arange(nx.size)
    ring_nodes = np.setdiff1d(node, [k for k, _ in pose_nodes])
    key = np.zeros(nx.size)
    key[ring_nodes] = _from_x(circ, ncirc[ring_nodes], nx[ring_nodes], ny[ring_nodes])
    a, b = ring(ncirc, key, node, ring_nodes)
    a, b = [a], [b]
    order = ring_nodes[np.lexsort((ring_nodes, key[ring_nodes], ncirc[ring_nodes]))]
    co = ncirc[order]
    for pose, is_start in pose_nodes:
        on = order[co == ncirc[pose]]
        if not on.size:
            continue
        here, c = np.full(on.size, pose), np.full(on.size, ncirc[pose])
        if is_start:  # the start point to the first node after it
            swp = _sweep(circ, c, nx[here], ny[here], nx[on], ny[on])
            a.append(here[:1])
            b.append(on[np.argmin(swp)][None])
        else:  # the last node before the goal point to it
            swp = _sweep(circ, c, nx[on], ny[on], nx[here], ny[here])
            a.append(on[np.argmin(swp)][None])
            b.append(here[:1])
    a, b = np.concatenate(a).astype(np.int64), np.concatenate(b).astype(np.int64)
    ac = ncirc[a]
    for s_n, s_start in pose_nodes:  # a start circle that is a goal circle (same turn)
        for g_n, g_start in pose_nodes:
            c, d = ncirc[s_n], ncirc[g_n]
            if s_start and not g_start and sg[c] == sg[d] and abs(r[c] - r[d]) < TOL.eps \
                    and np.hypot(x[c] - x[d], y[c] - y[d]) < TOL.eps:
                a, b, ac = np.r_[a, s_n], np.r_[b, g_n], np.r_[ac, c]
    return a, b, ac


def assemble(sa, circ, pieces, poses: str, collision: str = "full", enter=None,
             coincident=None, more_poses=()) -> Graph:
    """The tangent graph (module doc) over the circles ``circ`` of float64 scenario
    arrays ``sa`` from its feasible straight ``pieces`` ``(S, T, p1x, p1y, p2x, p2y,
    length)``; arcs judged under ``collision``. ``enter``: per piece the obstacle it
    enters (a search that enters each obstacle once counts them), else -1 for all.
    ``coincident`` (``"ends"``): which start circles (0, 1) coincide with the goal circle
    of their sign and get the arc from the start point to the goal point (default:
    measured). ``more_poses`` (``"rings"``): ``(circle, is_start)`` of more circles a
    walk may begin on at the start point or end on at the goal point (a car that also
    reverses leaves its pose on its turning circles travelled the other way); their
    pose nodes come after the pieces' ends, and the graph's ``starts`` and ``goals``
    list them."""
    x, y, r, sg, own = circ
    S, T, p1x, p1y, p2x, p2y, tlen = pieces
    e = S.size
    st, gl = sa.start, sa.goal
    extra = [st if is_start else gl for _, is_start in more_poses]
    nx = np.concatenate([[st[0]] * 2, [gl[0]] * 2, p1x, p2x, [p[0] for p in extra]])
    ny = np.concatenate([[st[1]] * 2, [gl[1]] * 2, p1y, p2y, [p[1] for p in extra]])
    ncirc = np.concatenate([np.arange(ids.POSES), S, T, [c for c, _ in more_poses]]
                           ).astype(np.int64)
    pose_nodes = [(k, bool(ids.is_start(k))) for k in range(ids.POSES)] + [
        (ids.POSES + 2 * e + k, is_start) for k, (_, is_start) in enumerate(more_poses)]
    if poses not in POSES:
        raise ValueError(f"poses: must be one of {', '.join(POSES)}, got {poses!r}")
    if poses == "ends":
        if more_poses:
            raise ValueError("more_poses: only with poses = 'rings'")
        a, b, ac = _ends(circ, sa, nx, ny, ncirc, coincident)
    else:
        a, b, ac = _rings(circ, sa, nx, ny, ncirc, pose_nodes)
    swp = _sweep(circ, ac, nx[a], ny[a], nx[b], ny[b])
    aok = col.arcs_clear(circ, ac, (nx[a], ny[a], nx[b], ny[b], swp), sa.centres,
                         sa.model_radii, sa.bounds, TOL.length, collision)
    a, b, ac, swp = a[aok], b[aok], ac[aok], swp[aok]
    at_pose = np.isin(np.arange(nx.size), [k for k, _ in pose_nodes])
    tie = (swp < TOL.angle) & ~at_pose[a] & ~at_pose[b]  # zero reverse edge b -> a
    nt, tan = int(tie.sum()), np.arange(e) + ids.POSES
    es = np.concatenate([tan, a, b[tie]])
    ed = np.concatenate([tan + e, b, a[tie]])
    ew = np.concatenate([tlen, r[ac] * swp, np.zeros(nt)])
    earc = np.concatenate([np.full(e, -1), ac, ac[tie]])
    eswp = np.concatenate([np.zeros(e), swp, np.zeros(nt)])
    eent = np.concatenate([np.full(e, -1) if enter is None else enter,
                           np.full(a.size + nt, -1)])
    srt = np.argsort(es, kind="stable")
    indptr = np.concatenate([[0], np.cumsum(np.bincount(es, minlength=nx.size))])
    return Graph(circ, nx, ny, ncirc, indptr.tolist(), ed[srt].tolist(), ew[srt].tolist(),
                 eent[srt].tolist(), es[srt], earc[srt], eswp[srt],
                 tuple(k for k, is_start in pose_nodes if is_start),
                 tuple(k for k, is_start in pose_nodes if not is_start))
