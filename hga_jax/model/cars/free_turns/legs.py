"""Free legs: the free turns that a chromosome with one gene per leg can express.

A tight-rope chromosome lists the circles a path turns on; between two of them it
runs straight. A *free leg* runs instead over a free circle of radius rho that
touches both circles from outside, the path changing circle at both contact points
(so the free circle turns the other way, and both circles must turn the same way).
There are two such circles, one on each side of the line between the centres
(``side`` 0 on the left of ``a -> c``, 1 on the right). A chromosome with a gene per
leg (straight, or free on side 0 or 1) expresses the turn-turn-turn Dubins words and
every free loop that touches its neighbours, but not a free circle held by an
obstacle or a wall that it does not turn on (:mod:`hga_jax.model.cars.free_turns.turns`).

:func:`table` lists every feasible free leg of a scenario; :func:`leg_table` is what
the GA's decoder and turn table read, and :func:`search_arrays` the scenario's device
arrays with both (:mod:`hga_jax.model.cars.free_turns.leg_space` finds the best path of this chromosome
space exactly). Host code (numpy, float64 unless a dtype is given); metres and radians.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import circle_ids as ids
from hga_jax.model import collision as col
from hga_jax.model import geometry as g

from hga_jax.model import legs as leg_info
from hga_jax.model import turns as turn_tables

from hga_jax.model.cars.free_turns import circles
from hga_jax.model.in_time import windows
from hga_jax.model.scenario import Scenario, ScenarioArrays

TOL = g.tolerances(np.float64)


class FreeLegs(NamedTuple):
    """Feasible free legs, one row each: from circle ``S`` to circle ``T`` (ids of
    :mod:`hga_jax.model.tangents`) on ``side``; the free circle's centre ``(fx, fy)``
    and orientation ``sign``, the contact points ``P1`` on S and ``P2`` on T, and the
    free arc's sweep (rad) from P1 to P2."""

    S: np.ndarray
    T: np.ndarray
    side: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    sign: np.ndarray
    p1x: np.ndarray
    p1y: np.ndarray
    p2x: np.ndarray
    p2y: np.ndarray
    sweep: np.ndarray


VARIANTS = 3
"""Leg genes: 0 a straight tangent, 1 a free leg on side 0, 2 on side 1."""


class LegTable(NamedTuple):
    """Every leg of a free-turn chromosome, as arrays shaped ``(VARIANTS, C, C)``: entry
    ``[v, a, c]`` is the leg with gene ``v`` from oriented circle ``a`` to ``c`` (ids of
    :mod:`hga_jax.model.tangents`).

    - Gene 0: the tangent of the scenario's tangent table where it has no violation of
      its own; where it has one (an obstacle, the field, no tangent) and a clear free
      leg joins the two circles, the shorter such free leg instead (so a straight gene
      never keeps a path on a blocked tangent that a free circle gets round).
    - Genes 1 and 2: the free leg on side 0 or 1 where :func:`table` lists one (clear of
      every obstacle and the field), else gene 0's leg (a gene with no free leg to
      express reads as gene 0).

    p1x, p1y: where the leg leaves ``a``; p2x, p2y: where it arrives on ``c``. length:
    the tangent's length or the free arc's ``rho * sweep`` (m). exists, coincident,
    violations: the tangent's (a free leg: 1, 0, 0; violations under the full rule).
    free: the entry is a free leg. fx, fy, sweep: its free circle's centre and the free
    arc's sweep (rad; 0 for tangents). fsign: the free circle's sense (``+1`` CW, ``-1``
    CCW; 0 for a tangent): under free turns it turns against ``a``.
    cusps: a reversing car's cusps of each entry (bit 0: at its first contact, bit 1:
    at its last; :mod:`hga_jax.model.cars.reeds_shepp.legs`); None for a car that only
    drives forward. q1x, q1y, q2x, q2y: a reversing car's legs run straight from P1 to
    Q1, over the free circle to Q2 and straight to P2 (quarter turns); None otherwise.
    """

    p1x: np.ndarray
    p1y: np.ndarray
    p2x: np.ndarray
    p2y: np.ndarray
    length: np.ndarray
    exists: np.ndarray
    coincident: np.ndarray
    violations: np.ndarray
    free: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    sweep: np.ndarray
    fsign: np.ndarray
    cusps: np.ndarray | None = None
    q1x: np.ndarray | None = None
    q1y: np.ndarray | None = None
    q2x: np.ndarray | None = None
    q2y: np.ndarray | None = None


def leg_table(sc: Scenario, dtype: Any = np.float64) -> LegTable:
    """The :class:`LegTable` of ``sc`` in ``dtype`` (built once per dtype): tangents from
    ``sc.arrays(dtype)``'s tangent table, the free legs computed in float64 and cast."""
    dtype = np.dtype(dtype)
    return sc.cached(("leg_table", dtype.name), lambda: _leg_table(sc, dtype))


def search_arrays(sc: Scenario, dtype: Any = np.float32, with_legs: bool = False
                  ) -> ScenarioArrays:
    """:meth:`Scenario.search_arrays` (full collision rule) for free-turn chromosomes: with
    the :class:`LegTable` (``free_legs``) and its turn table (``turns_free``, None when it
    is too large or centres coincide: the fitness then decodes leg by leg), and with the
    path operators' legs seeing gene 0's free legs (:func:`hga_jax.model.legs.free_aware`)
    and the end arcs those legs make (:func:`hga_jax.model.legs.with_end_arcs`); an end
    leg whose gene-0 arc has a violation counts as clear where another gene's free leg
    and its arc are. ``tight_legs``: the tight rope's legs (the tangents, with their
    end arcs)."""
    dtype = np.dtype(dtype)
    sa = sc.search_arrays(dtype, "full", with_legs)

    def turns():
        if not turn_tables.fits(sc.n, VARIANTS):
            return None
        s64 = sc.arrays(np.float64)
        built = turn_tables.build(s64.tangents, s64.start, s64.goal, s64.centres,
                                  s64.model_radii, s64.bounds, "full", leg_table(sc))
        if not built.usable:
            return None
        if not sc.has_motion:
            return np.asarray(built.entries, dtype)
        timed = windows.for_scenario(sc, built.entries, dtype, leg_table(sc))
        return None if timed is None else np.asarray(timed, dtype)

    sa = sa._replace(free_legs=leg_table(sc, dtype),
                     turns_free=sc.cached(("turns_free", dtype.name), turns))
    if with_legs:
        def aware():
            lg = aware_of(sc.arrays(np.float64).model_radii)
            if sc.has_motion:  # the blockers of the moving robots' placed circles too
                lg = leg_info.with_blockers_of(lg, aware_of(sc.guide_radii()))
            return lg._replace(length=np.asarray(lg.length, dtype),
                               penalty=np.asarray(lg.penalty, dtype))

        def aware_of(radii):
            s64, t = sc.arrays(np.float64), leg_table(sc)
            tb = s64.tangents
            base = leg_info.free_aware(leg_info.build(tb, s64.centres, radii, sc.delta), t)

            def arcs(v, legs):  # with the end arcs of gene v's legs
                pts = (t.p1x[v], t.p1y[v], t.p2x[v], t.p2y[v], t.coincident[v])
                return leg_info.with_end_arcs(legs, tb, s64.start, s64.goal, s64.centres,
                                              radii, s64.bounds, pts)

            lg = arcs(0, base)
            # An end leg whose gene-0 leg meets an obstacle or the field on its end arc,
            # but whose free leg of another gene is clear with its own end arc, counts
            # as clear, with that leg's length (the genes can take it; free_aware's
            # rule for a blocked tangent, carried to the end arcs).
            for v in range(1, VARIANTS):
                free = np.asarray(t.free[v], bool)
                alt = arcs(v, base._replace(length=np.where(free, t.length[v], base.length),
                                            bad=base.bad & ~free))
                take = lg.bad & ~alt.bad
                lg = lg._replace(bad=lg.bad & ~take, length=np.where(take, alt.length,
                                                                        lg.length))
            return lg

        # the tight rope's legs, without the arcs of its turn table (guided_arcs: the
        # tight rope only)
        sa = sa._replace(legs=sc.cached(("legs_free", dtype.name), aware),
                         tight_legs=sa.legs._replace(arcs=None))
    return sa


def _leg_table(sc: Scenario, dtype: np.dtype) -> LegTable:
    legs = table(sc)
    return assemble(sc.arrays(dtype).tangents, legs, legs.side + 1, VARIANTS,
                    float(sc.min_turn_radius), dtype)


def assemble(tb: Any, legs: FreeLegs, genes: np.ndarray, variants: int, rho: float,
             dtype: np.dtype, cusps: np.ndarray | None = None) -> LegTable:
    """The :class:`LegTable` of ``variants`` genes over the circles of the tangent table
    ``tb``: gene 0 the tangent (or, where it has a violation, the shorter clear free leg
    without cusps that joins the same circles), gene ``genes[k]`` the free leg ``k`` of
    ``legs``, and gene 0's leg for every gene with no free leg. ``cusps``: the cusps of
    each free leg (a car that reverses; None: the forward car's, none)."""
    c = np.asarray(tb.circles).shape[0]
    straight = {name: np.asarray(getattr(tb, name), dtype) for name in
                ("p1x", "p1y", "p2x", "p2y", "length", "exists", "coincident")}
    straight["violations"] = np.asarray(tb.violations_full, dtype)
    straight["free"] = np.zeros((c, c), bool)
    for name in ("fx", "fy", "sweep", "fsign"):
        straight[name] = np.zeros((c, c), dtype)
    if cusps is not None:
        straight["cusps"] = np.zeros((c, c), dtype)
    free = {"p1x": legs.p1x, "p1y": legs.p1y, "p2x": legs.p2x, "p2y": legs.p2y,
            "length": rho * legs.sweep, "exists": 1.0, "coincident": 0.0, "violations": 0.0,
            "free": True, "fx": legs.fx, "fy": legs.fy, "sweep": legs.sweep,
            "fsign": legs.sign}
    if cusps is not None:
        free["cusps"] = cusps
    # Gene 0 where the tangent is bad: the shorter clear free leg (the longer one first,
    # so that the shorter one is written last and stays).
    smooth = np.ones(legs.S.size, bool) if cusps is None else cusps == 0
    bad = (straight["violations"][legs.S, legs.T] > 0) & smooth
    order = np.argsort(-legs.sweep[bad], kind="stable")
    rows = np.flatnonzero(bad)[order]
    zero = {name: v.copy() for name, v in straight.items()}
    for name, value in free.items():
        zero[name][legs.S[rows], legs.T[rows]] = value if np.ndim(value) == 0 else value[rows]
    cols = {name: np.repeat(v[None], variants, axis=0) for name, v in zero.items()}
    at = (genes, legs.S, legs.T)
    for name, value in free.items():
        cols[name][at] = value
    return LegTable(**cols)


def table(sc: Scenario) -> FreeLegs:
    """Every free leg of ``sc`` whose free arc is clear (obstacles, field): from a start
    or obstacle circle to an obstacle or goal circle of the same orientation, never
    between one obstacle's two circles."""
    x, y, r, sg, own = circ = sc.circles(np.float64)
    c = x.size
    src, dst = ids.sources(c), ids.targets(c)
    a, b = (m.ravel() for m in np.meshgrid(src, dst, indexing="ij"))
    keep = (sg[a] == sg[b]) & ~((own[a] == own[b]) & (own[a] >= 0))
    return between(sc, circ, a[keep], b[keep], -1.0)


def between(sc: Scenario, circ, a: np.ndarray, b: np.ndarray, sense: float) -> FreeLegs:
    """The clear free legs from circles ``a`` to circles ``b`` (indices into ``circ =
    (x, y, r, sign, own)``, float64), their free circle turning ``sense`` times the way
    ``a`` turns (-1: against it, a smooth change of circle; +1: the same way, a cusp)."""
    x, y, r, sg, own = circ
    rho = float(sc.min_turn_radius)
    fx, fy, k = circles.pair_centres(x[a], y[a], r[a] + rho, x[b], y[b], r[b] + rho)
    side = (np.arange(fx.size) >= fx.size // 2).astype(np.int32)  # + solution first: left
    a, b = a[k], b[k]
    fs = sense * sg[a]

    def contact(i):  # the point of circle i on the way to the free circle's centre
        return (x[i] + r[i] * (fx - x[i]) / (r[i] + rho),
                y[i] + r[i] * (fy - y[i]) / (r[i] + rho))

    (p1x, p1y), (p2x, p2y) = contact(a), contact(b)
    swp = g.sweep(p1x - fx, p1y - fy, p2x - fx, p2y - fy, fs, TOL.angle)
    free = (fx, fy, np.full(fx.size, rho), fs, np.full(fx.size, -1))
    sa = sc.arrays(np.float64)
    ok = col.arcs_clear(free, np.arange(fx.size), (p1x, p1y, p2x, p2y, swp), sa.centres,
                        sa.model_radii, sa.bounds, TOL.length)
    return FreeLegs(*(v[ok] for v in (a, b, side, fx, fy, fs, p1x, p1y, p2x, p2y, swp)))
