"""The best path of the leg-gene chromosome space, found exactly.

A free-turn chromosome (:mod:`hga_jax.model.cars.free_turns.legs`) expresses the tight-rope paths
and, leg by leg, free circles that touch both neighbouring circles. :func:`shortest`
searches that space's tangent graph (the scenario's clear tangents plus the clear free
legs, each obstacle touched at most once, as a chromosome does), so that the share of
free-turn optima it reaches can be measured, and so that a scene family can keep only
scenes a GA run can hit. Host code (numpy, float64); metres and radians.
"""
from __future__ import annotations

import math

import numpy as np

from hga_jax.model import circle_ids as ids
from hga_jax.model.cars.free_turns import turns
from hga_jax.model.cars.free_turns.legs import table
from hga_jax.model.graph_search import search, walk
from hga_jax.model.scenario import Scenario
from hga_jax.model.touch import Touch


def graph(sc: Scenario):
    """The tangent graph of the leg space: the scenario's clear tangents, then the clear
    free legs (each a piece standing for its free arc), the poses' circles as rings, each
    piece counted as entering its target's obstacle. Returns ``(graph, tangents, legs)``:
    the number of tangent pieces and the :class:`~hga_jax.model.cars.free_turns.legs.FreeLegs`."""
    from hga_jax.model.exact import _tangents

    sa = sc.arrays(np.float64)
    circ = sc.circles(np.float64)
    S, T, t, ok = _tangents(sa, True)
    legs = table(sc)
    rho = float(sc.min_turn_radius)
    e = int(ok.sum())
    pieces = (np.r_[S[ok], legs.S], np.r_[T[ok], legs.T], np.r_[t.p1x[ok], legs.p1x],
              np.r_[t.p1y[ok], legs.p1y], np.r_[t.p2x[ok], legs.p2x], np.r_[t.p2y[ok], legs.p2y],
              np.r_[t.length[ok], rho * legs.sweep])
    return turns.graph(sc, circ, pieces, enter=circ[4][pieces[1]]), e, legs


def shortest(sc: Scenario):
    """The best path a chromosome with free legs expresses: ``(length, segments, touched,
    free_arcs)`` as :func:`hga_jax.model.cars.free_turns.turns.shortest` (inf and empty lists when
    none is feasible or the label budget of the search runs out)."""
    gr, e, legs = graph(sc)
    circ, rho = gr.circles, float(sc.min_turn_radius)
    h = np.hypot(gr.nx - float(sc.goal[0]), gr.ny - float(sc.goal[1])).tolist()
    length, edges, _ = search(gr, h, distinct=True)
    if not edges:
        return math.inf, [], [], 0
    circs, segs = walk(gr, edges)
    lines = iter(i for i, s in enumerate(segs) if s["type"] == "line")
    free = 0
    for k in edges:
        u = int(gr.src[k])
        if gr.arc_circle[k] >= 0 or gr.w[k] <= 0.0:
            continue
        i = next(lines)
        if ids.POSES + e <= u < ids.POSES + e + len(legs.S):  # a free leg: its free arc
            j = u - ids.POSES - e
            segs[i] = {"type": "arc", "center": [float(legs.fx[j]), float(legs.fy[j])],
                       "radius": rho, "sweep": float(-legs.sign[j] * legs.sweep[j]),
                       "start_angle": float(math.atan2(legs.p1y[j] - legs.fy[j],
                                                       legs.p1x[j] - legs.fx[j])),
                       "free": True}
            free += 1
    own, sg = circ[4], circ[3]
    touched = [Touch(int(own[c]) + 1, int(sg[c])) for c in circs if not ids.is_pose(c)]
    return float(length), segs, touched, free
