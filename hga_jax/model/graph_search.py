"""Shortest walks in a tangent graph: the search both exact solvers share.

A graph's nodes are points on oriented circles, its edges tangent pieces (straight, or
standing for a curve) and arcs along a circle, in compressed sparse rows. Built by
:mod:`hga_jax.model.tangent_graph` for :mod:`hga_jax.model.exact` (the tight rope) and
:mod:`hga_jax.model.cars.free_turns.turns` (free turns). Host code; metres and radians.
"""
from __future__ import annotations

import heapq
import math
from typing import Any, NamedTuple

import numpy as np

from . import circle_ids as ids

MAX_LABELS = 300_000  # label-setting search budget (popped labels)


class Graph(NamedTuple):
    """Nodes (x, y, circle) and edges in CSR order (arc_circle -1 for a tangent)."""

    circles: tuple[np.ndarray, ...]  # x, y, r, sign, obstacle id (-1 start/goal)
    nx: np.ndarray  # node x (m)
    ny: np.ndarray  # node y (m)
    ncirc: np.ndarray  # node's circle
    indptr: list[int]
    dst: list[int]
    w: list[float]
    enter: list[int]  # obstacle a tangent edge enters, else -1
    src: np.ndarray
    arc_circle: np.ndarray
    sweep: np.ndarray
    starts: tuple[int, ...] = ids.START  # the nodes a walk may begin at: the start point
    goals: tuple[int, ...] = ids.GOAL  # on each start circle; it ends at a goal node


def search(gr: Graph, h: list[float], distinct: bool) -> tuple[float, list[int], bool]:
    """A* from the start nodes (``gr.starts``: 0, 1) to a goal node (``gr.goals``: 2, 3);
    edges of the best walk.

    With ``distinct`` the state carries the set of entered obstacles (a bit mask)
    and no obstacle is entered twice (labels dominated by a settled subset are
    dropped). Returns ``(length, edges, complete)``; ``(inf, [], complete)`` when no walk
    exists (``complete``) or the label budget ran out (not ``complete``).
    """
    indptr, dst, w, enter = gr.indptr, gr.dst, gr.w, gr.enter
    heap = [(h[s], 0.0, s, 0, -1) for s in gr.starts]
    goals = frozenset(gr.goals)
    labels: list[tuple[int, int]] = []  # (edge into this label, parent label)
    best: dict[tuple[int, int], float] = {(s, 0): 0.0 for s in gr.starts}
    settled: dict[int, list[int]] = {}
    pops = 0
    while heap and pops < MAX_LABELS:
        _, gc, u, m, lab = heapq.heappop(heap)
        if gc > best[(u, m)]:
            continue
        if distinct:
            done = settled.setdefault(u, [])
            if any(s & ~m == 0 for s in done):
                continue
            done.append(m)
            pops += 1
        if u in goals:
            edges = []
            while lab >= 0:
                edges.append(labels[lab][0])
                lab = labels[lab][1]
            return gc, edges[::-1], True
        for k in range(indptr[u], indptr[u + 1]):
            v, j, m2 = dst[k], enter[k], m
            if distinct and j >= 0:
                if m >> j & 1:
                    continue
                m2 = m | 1 << j
            nd = gc + w[k]
            if nd < best.get((v, m2), math.inf):
                best[(v, m2)] = nd
                labels.append((k, lab))
                heapq.heappush(heap, (nd + h[v], nd, v, m2, len(labels) - 1))
    return math.inf, [], not heap


def walk(gr: Graph, edges: list[int]) -> tuple[list[int], list[dict[str, Any]]]:
    """Oriented circles visited (in order) and docs/model.md segments of a walk."""
    x, y, r, sg, _ = gr.circles
    circs, segs, arc_on = [int(gr.ncirc[gr.src[edges[0]]])] if edges else [], [], -1
    for k in edges:
        u, v, c = int(gr.src[k]), gr.dst[k], int(gr.arc_circle[k])
        if c < 0:
            arc_on = -1
            if gr.w[k] > 0.0:
                segs.append({"type": "line", "start": [float(gr.nx[u]), float(gr.ny[u])],
                             "end": [float(gr.nx[v]), float(gr.ny[v])]})
        elif gr.sweep[k] > 0.0:
            if arc_on != c:
                segs.append({"type": "arc", "center": [float(x[c]), float(y[c])],
                             "radius": float(r[c]), "sweep": 0.0, "start_angle": float(
                                 np.arctan2(gr.ny[u] - y[c], gr.nx[u] - x[c]))})
            segs[-1]["sweep"] -= float(sg[c] * gr.sweep[k])
            arc_on = c
        if int(gr.ncirc[v]) != circs[-1]:
            circs.append(int(gr.ncirc[v]))
    return circs, segs
