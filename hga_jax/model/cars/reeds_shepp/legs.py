"""Reeds–Shepp chromosomes: free-turn legs driven in either gear, and their tables.

The GA searches the Reeds–Shepp car's paths with the free-turn chromosome
(:mod:`hga_jax.model.cars.free_turns.legs`) and two more values of its leg genes
(:mod:`hga_jax.model.cars.reeds_shepp.reversing` holds the gear rule):

- ``0`` a tangent; ``1``/``2`` a free circle of radius rho touching both circles of
  the leg, on side 0 or 1, turning against the circle it leaves (no cusp there);
  ``3``/``4`` the same free circle turning the same way as that circle (a cusp at
  its first contact). A free leg may join circles of either senses: where the free
  circle turns the same way as the circle it reaches, a cusp there too;
- the start may be left backward (the goal position's gene), on the car's other
  turning circle; the goal is reached in the gear the cusps leave.

A chromosome so expresses every forward free-turn path (genes 0-2, forward start),
every one of them driven backward, cusps where a free circle meets the path's
circles (C|C, C|C|C and CC|C pieces of Reeds and Shepp's words), but not the
quarter-turn circles of the exact model nor two free circles in a row
(docs/model.md). :func:`search_arrays` builds the device arrays: the tangent table
over the ``C + 4`` circles (the scenario's, then the pose circles driven backward),
the leg table of :data:`VARIANTS` genes with the cusps of each leg, its turn table,
and the legs the path operators read. Host code (numpy, float64 unless a dtype is
given); metres and radians.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from hga_jax.model import circle_ids as ids
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from hga_jax.model import legs as leg_info
from hga_jax.model import tangents
from hga_jax.model import turns as turn_tables
from hga_jax.model.cars.free_turns import legs as free_legs
from hga_jax.model.cars.reeds_shepp import reversing
from hga_jax.model.cars.reeds_shepp.graph import quarter_routes
from hga_jax.model.in_time import windows
from hga_jax.model.scenario import Scenario, ScenarioArrays

VARIANTS = 7
"""Leg genes: 0 a tangent, 1-2 a free circle against the leg's first circle, 3-4 with
it, 5 and 6 the quarter turns leaving the start and reaching the goal
(:mod:`hga_jax.model.cars.reeds_shepp.reversing`)."""


def circles(sc: Scenario, dtype: Any = np.float64) -> tuple[np.ndarray, ...]:
    """``(x, y, r, sign, obstacle)`` of the ``C + 4`` circles: the scenario's, then pose
    circle ``k``'s backward twin ``C + k`` (:mod:`hga_jax.model.cars.reeds_shepp.reversing`): the car's
    other turning circle at that pose, travelled in circle ``k``'s sense."""
    x, y, r, sign, own = sc.circles(dtype)
    k = np.arange(ids.POSES) ^ 1  # the other circle of the pose's pair
    return (np.r_[x, x[k]], np.r_[y, y[k]], np.r_[r, r[k]], np.r_[sign, -sign[k]],
            np.r_[own, own[k]].astype(np.int32))


def tangent_table(sc: Scenario, dtype: Any = np.float64) -> tangents.TangentTable:
    """The tangent table over :func:`circles` in ``dtype`` (built once per dtype)."""
    dtype = np.dtype(dtype)

    def build():
        sa = sc.arrays(dtype)
        return tangents.table(circles(sc, dtype), np.asarray(sa.centres),
                              np.asarray(sa.model_radii), np.asarray(sa.bounds))

    return sc.cached(("rs_tangents", dtype.name), build)


def pose_of(circle: np.ndarray, c: int) -> np.ndarray:
    """The pose circle (0-3, :mod:`hga_jax.model.circle_ids`) that each of ``circle`` is
    or is the backward twin of, among ``c + 4`` circles; -1 for the others."""
    return np.where(circle < ids.POSES, circle, np.where(circle >= c, circle - c, -1))


def table(sc: Scenario) -> tuple[free_legs.FreeLegs, np.ndarray, np.ndarray]:
    """Every clear free leg of genes 1-4 over :func:`circles` (float64): ``(legs, genes,
    cusps)``, the gene and the cusps (bit 0 at the first contact, bit 1 at the last)
    of each."""
    circ = circles(sc, np.float64)
    x, y, r, sg, own = circ
    c = ids.count(sc.n)
    src = np.r_[ids.START, c + np.asarray(ids.START), ids.POSES:c]
    dst = np.r_[ids.POSES:c, ids.GOAL, c + np.asarray(ids.GOAL)]
    a, b = (m.ravel() for m in np.meshgrid(src, dst, indexing="ij"))
    keep = ~((own[a] == own[b]) & (own[a] >= 0))
    a, b = a[keep], b[keep]
    against = free_legs.between(sc, circ, a, b, -1.0)
    along = free_legs.between(sc, circ, a, b, 1.0)
    legs = free_legs.FreeLegs(*(np.concatenate(v) for v in zip(against, along)))
    genes = np.r_[against.side + 1, along.side + 3]
    cusps = (legs.sign == sg[legs.S]).astype(int) + 2 * (legs.sign == sg[legs.T])
    return legs, genes, cusps


def quarters(sc: Scenario):
    """The quarter-turn legs (genes 5 and 6), one per pair of circles: ``(gene, S, T, P1,
    Q1, Q2, P2, F, sign, sweep, length, violations)``, from the routes of
    :func:`hga_jax.model.cars.reeds_shepp.graph.quarter_routes`. Of several routes joining
    one pair, the one with fewest violations (its quarter turn and tangent against the
    obstacles and the field), then the shortest with the arc on the pose circle
    between the route and the start or goal point."""
    circ = circles(sc, np.float64)
    x, y, r, sg, own = circ
    c = ids.count(sc.n)
    q = quarter_routes(sc, circ, c)
    pose = pose_of(q.b, c)  # a leaving route ends on no start circle, an arriving one
    keep = np.where(q.leaves, (pose < 0) | (pose >= 2), pose < 2)  # comes from no goal circle
    q = type(q)(*(v[keep] for v in q))
    tol = g.tolerances(np.float64)
    rho = float(sc.min_turn_radius)
    sa = sc.arrays(np.float64)
    # The arc on F: from P (leaving) or from the tangent's end on F (arriving).
    fa = np.where(q.leaves, q.px, q.t2x), np.where(q.leaves, q.py, q.t2y)
    fb = np.where(q.leaves, q.t1x, q.px), np.where(q.leaves, q.t1y, q.py)
    free = (q.fx, q.fy, np.full(q.fx.size, rho), q.sign, np.full(q.fx.size, -1))
    ok = col.arcs_clear(free, np.arange(q.fx.size), (*fa, *fb, q.sweep), sa.centres,
                        sa.model_radii, sa.bounds, tol.length)
    obstacles = col.obstacles(np.asarray(sa.centres), np.asarray(sa.model_radii), ndim=1)
    seg = col.segment_violations((q.t1x, q.t1y, q.t2x, q.t2y), np.ones(q.fx.size, bool),
                                 obstacles, sa.bounds, tol.length, "full")
    violations = (~ok).astype(float) + np.asarray(seg, float)
    # The arc on the pose circle: start point to P, or P to the goal point.
    (sx, sy, _), (gx, gy, _) = sc.start, sc.goal
    a = q.a
    on = np.where(q.leaves, g.sweep(sx - x[a], sy - y[a], q.px - x[a], q.py - y[a], sg[a],
                                     tol.angle),
                  g.sweep(q.px - x[a], q.py - y[a], gx - x[a], gy - y[a], sg[a], tol.angle))
    length = rho * q.sweep + q.length
    cost = length + r[a] * on
    S = np.where(q.leaves, q.a, q.b)
    T = np.where(q.leaves, q.b, q.a)
    gene = np.where(q.leaves, reversing.LEAVING, reversing.ARRIVING)
    order = np.lexsort((cost, violations, T, S, gene))[::-1]  # the best of a pair last
    p1 = np.where(q.leaves, q.px, q.t1x), np.where(q.leaves, q.py, q.t1y)
    p2 = np.where(q.leaves, q.t2x, q.px), np.where(q.leaves, q.t2y, q.py)
    rows = (gene, S, T, p1[0], p1[1], fa[0], fa[1], fb[0], fb[1], p2[0], p2[1], q.fx, q.fy,
            q.sign, q.sweep, length, violations, np.where(q.leaves, 1, 2))
    return tuple(np.asarray(v)[order] for v in rows)


def leg_table(sc: Scenario, dtype: Any = np.float64) -> free_legs.LegTable:
    """The :class:`~hga_jax.model.cars.free_turns.legs.LegTable` of Reeds–Shepp chromosomes in
    ``dtype`` (built once per dtype), with the cusps of every entry and the points
    Q1, Q2 of its free circle. A gene that promises a change of gear (an odd parity,
    :func:`hga_jax.model.cars.reeds_shepp.reversing.odd_leg`) where no such leg exists reads as gene 0
    with one more violation."""
    dtype = np.dtype(dtype)

    def build():
        legs, genes, cusps = table(sc)
        lt = free_legs.assemble(tangent_table(sc, dtype), legs, genes, VARIANTS,
                                float(sc.min_turn_radius), dtype, cusps.astype(dtype))
        lt = lt._replace(q1x=lt.p1x.copy(), q1y=lt.p1y.copy(), q2x=lt.p2x.copy(),
                         q2y=lt.p2y.copy())
        cols = lt._asdict()
        (gene, S, T, p1x, p1y, q1x, q1y, q2x, q2y, p2x, p2y, fx, fy, fs, swp, length, vio,
         cusp) = quarters(sc)
        for name, value in (("p1x", p1x), ("p1y", p1y), ("q1x", q1x), ("q1y", q1y),
                            ("q2x", q2x), ("q2y", q2y), ("p2x", p2x), ("p2y", p2y),
                            ("fx", fx), ("fy", fy), ("fsign", fs), ("sweep", swp),
                            ("length", length), ("violations", vio), ("cusps", cusp),
                            ("exists", 1.0), ("coincident", 0.0), ("free", True)):
            cols[name][gene, S, T] = value  # a pair's best route is written last
        lt = free_legs.LegTable(**cols)
        sg = circles(sc)[3]
        c = ids.count(sc.n)
        have = np.zeros(lt.length.shape, bool)
        have[genes, legs.S, legs.T] = True
        have[gene, S, T] = True
        v = np.arange(VARIANTS)[:, None, None]
        pose = pose_of(np.arange(sg.size), c)
        start, goal = (pose >= 0) & (pose < 2), pose >= 2
        odd = reversing.odd_leg(v, sg[:, None][None], sg[None, :][None],
                                start[None, :, None], goal[None, None, :])
        return lt._replace(violations=lt.violations + (odd & ~have).astype(dtype))

    return sc.cached(("rs_leg_table", dtype.name), build)


def fits(n: int) -> bool:
    """Whether a turn table is built for ``n`` obstacles (30 at most)."""
    c = ids.count(n) + ids.POSES
    return (VARIANTS * c + 1) * c * (VARIANTS * c + 1) <= turn_tables.MAX_ENTRIES


def search_arrays(sc: Scenario, dtype: Any = np.float32, with_legs: bool = False
                  ) -> ScenarioArrays:
    """The scenario's device arrays for Reeds–Shepp chromosomes in ``dtype``: the tangent
    table over :func:`circles`, the leg table (``free_legs``) and its turn table
    (``turns_free``; None where too large or centres coincide: the fitness then decodes
    leg by leg), and with ``with_legs`` the legs the path operators read
    (:func:`hga_jax.model.legs.free_aware` of gene 0; the path's ends left to the end
    move)."""
    dtype = np.dtype(dtype)
    c = ids.count(sc.n)

    def turns():
        if not fits(sc.n):
            return None
        s64 = sc.arrays(np.float64)
        built = turn_tables.build(tangent_table(sc), s64.start, s64.goal, s64.centres,
                                  s64.model_radii, s64.bounds, "full", leg_table(sc), back=c)
        if not built.usable:
            return None
        if not sc.has_motion:
            return np.asarray(built.entries, dtype)
        timed = windows.for_scenario(sc, built.entries, dtype, leg_table(sc),
                                          tangent_table(sc))
        return None if timed is None else np.asarray(timed, dtype)

    sa = sc.arrays(dtype)._replace(tangents=tangent_table(sc, dtype),
                                   free_legs=leg_table(sc, dtype),
                                   turns_free=sc.cached(("rs_turns", dtype.name), turns))
    if with_legs:
        def tangents():  # the tangents' legs in float64, built once for both
            s64 = sc.arrays(np.float64)
            built = leg_info.build(tangent_table(sc), s64.centres, s64.model_radii, sc.delta)
            if not sc.has_motion:
                return built
            # among robots that move: the blockers of their placed circles too
            return leg_info.with_blockers_of(built, leg_info.build(
                tangent_table(sc), s64.centres, sc.guide_radii(), sc.delta))

        def device(lg):  # in dtype; the path's ends are left to the end move
            return lg._replace(length=np.asarray(lg.length, dtype),
                               penalty=np.asarray(lg.penalty, dtype), ends=np.asarray(True))

        base = sc.cached(("rs_tangent_legs",), tangents)
        sa = sa._replace(
            legs=sc.cached(("rs_legs", dtype.name),
                           lambda: device(leg_info.free_aware(base, leg_table(sc)))),
            tight_legs=sc.cached(("rs_tight_legs", dtype.name), lambda: device(base)))
    return sa
