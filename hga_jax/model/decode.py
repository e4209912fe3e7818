"""Decoding a batch of chromosomes into tight-rope paths: length and violations.

A chromosome (docs/model.md, paper 3.3) is stored as
- ``perm``: (n,) int32, the obstacle indices 0..n-1 in upper-module order
  (the upper module is ``[0, perm + 1, n + 1]``);
- ``labels``: (n + 2,) int32, the lower module: start, one label per permutation
  position, goal; ``+1`` CW, ``-1`` CCW, ``0`` not touched.

``decode_batch`` works on a batch ``(B, n)`` / ``(B, n + 2)`` with fixed shapes:
the ids of the path's oriented circles are compacted to the front of a slot axis
(log-step shifts, no Python loop over genes), then a ``lax.scan`` over the
``n + 1`` possible legs looks each tangent up in the scenario's tangent table
(:mod:`hga_jax.model.tangents`: touch points, length and segment violations, computed
once per scenario) and does the arc work, with the batch axis innermost (the
layout XLA vectorises well), masking legs past the last touched circle.

Violations: the rules of :mod:`hga_jax.model.collision` (segments against
obstacles by the criterion of ``collision``, arcs against every obstacle but their
own circle in ``"full"`` mode, pieces leaving the kept field, missing tangents);
the segments' are in the tangent table, the arcs' are counted here. Among robots that
move (``ScenarioArrays.motion``), the violations in time of :mod:`hga_jax.model.in_time.clearance`
are added.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import jax
import jax.numpy as jnp

from hga_jax.model import circle_ids
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from hga_jax.model.cars.reeds_shepp import reversing
from hga_jax.model.in_time import clearance
from .scenario import ScenarioArrays


class Decoded(NamedTuple):
    """Decoded paths of a batch of B chromosomes (leading axis B everywhere).

    length: (B,) path length in metres (arcs + segments).
    violations: (B,) int32 violation count.
    count: (B,) number of circles on the path (start and goal included).
    circles: (B, S, 4) per slot ``cx, cy, r, sign``; slot ``s < count`` is the
      s-th circle of the path (S = n + 2); ``obstacle``: (B, S) obstacle index or -1.
    arcs: (B, S, 5) per slot: arrival point ``ax, ay``, departure ``bx, by``, sweep
      (rad, >= 0); slot ``count - 1`` is the goal arc ending at the goal point.
    lines: (B, S - 1, 5) per leg ``p1x, p1y, p2x, p2y, exists``; leg s joins slot s
      to slot s + 1 and is real for ``s < count - 1``.
    free: (B, S - 1, 4) per leg ``fx, fy, sweep, sense`` when decoded with leg genes:
      a leg with ``sense`` +1 (CW) or -1 (CCW) runs from P1 to P2 over the free circle
      of centre ``(fx, fy)`` and radius rho, turning that way by ``sweep`` (rad); 0 for
      a tangent. A reversing car's has 9 columns: then ``q1x, q1y, q2x, q2y, cusps``:
      the leg runs straight from P1 to Q1, over the free circle to Q2, straight to P2,
      with a cusp at Q1 (``cusps`` bit 0) and at Q2 (bit 1)
      (:mod:`hga_jax.model.cars.reeds_shepp.legs`). None without leg genes.
    gears: (B, 2) bool, whether the path leaves the start and arrives at the goal
      driven backward (a car that reverses, :mod:`hga_jax.model.cars.reeds_shepp.legs`);
      None for the forward car.
    """

    length: Any
    violations: Any
    count: Any
    circles: Any
    obstacle: Any
    arcs: Any
    lines: Any
    free: Any = None
    gears: Any = None


def position_circles(perm, labels):
    """The oriented circle (id of :mod:`hga_jax.model.tangents`) of every position.

    Returns ``ids`` and ``touched``, both (S, B) (S = n + 2, batch innermost):
    position 0 is the start circle, 1..n the obstacles in permutation order (the
    circle of their label, any circle where the label is 0), S-1 the goal circle;
    ``touched`` is False where the label is 0.
    """
    return circles_along(perm.T, labels.T)


def circles_along(perm, labels):
    """:func:`position_circles` of chromosomes laid out positions first: ``perm`` (n, ...)
    and ``labels`` (n + 2, ...), any batch after; ``ids`` and ``touched`` (n + 2, ...)."""
    n = perm.shape[0]
    lab = labels.astype(jnp.int32)
    side = circle_ids.side(lab)  # 0 for CCW (-1), 1 for CW (+1)
    obstacle_ids = circle_ids.obstacle(perm.astype(jnp.int32), side[1:n + 1])
    start, goal = circle_ids.START[0] + side[:1], circle_ids.GOAL[0] + side[n + 1:]
    return jnp.concatenate([start, obstacle_ids, goal]), lab != 0


def _path_circles(perm, labels, legs=None):
    """The oriented circles of the path (ids of :mod:`hga_jax.model.tangents`), compacted.

    Returns ``count`` (B,), ``ids`` (S, B) (S = n + 2) and the leg genes of the slots
    (S, B) (None without ``legs``, (B, S) positional): slot 0 is the start circle,
    slots 1..count-2 the touched obstacles in order, slot count-1 the goal circle. Only
    the circle ids are compacted; the circles are looked up after.
    """
    ids, touched = position_circles(perm, labels)
    if legs is None:
        count, (ids,) = _compact(touched, ids)
        return count, ids, None
    count, (ids, genes) = _compact(touched, ids, legs.T.astype(jnp.int32))
    return count, ids, genes


def _compact(active, *columns):
    """Move the active rows of (L, B) columns to the front, keeping their order.

    Each active row moves up by the number of inactive rows above it; the move
    is done in ``ceil(log2 L)`` steps of ``2**k`` rows (bit k of the shift, lowest
    bit first), which never lets two active rows meet. Rows from ``count`` on
    hold leftovers (finite values of other rows) and must be masked by the caller.
    Returns ``(count, columns)``.
    """
    length = active.shape[0]
    shift = jnp.cumsum(~active, axis=0, dtype=jnp.int32)
    valid = active
    cols = (shift,) + columns
    step, k = 1, 0
    while step < length:
        moving = valid & (((cols[0] >> k) & 1) == 1)
        incoming = jnp.concatenate([moving[step:], jnp.zeros_like(moving[:step])])
        valid = incoming | (valid & ~moving)
        cols = tuple(jnp.where(incoming, jnp.concatenate([c[step:], c[-step:]]), c)
                     for c in cols)
        step, k = 2 * step, k + 1
    return jnp.sum(active, axis=0, dtype=jnp.int32), cols[1:]


def decode_batch(sa: ScenarioArrays, perm, labels, collision: str = "full",
                 legs=None) -> Decoded:
    """Decode ``perm`` (B, n) and ``labels`` (B, n + 2) against scenario ``sa``.

    Pure and jit/vmap-able; ``collision`` is static. The float dtype is the
    scenario's (float32 for the search, float64 for exact re-evaluation). Each leg
    looks its tangent up in ``sa.tangents``; each arc is tested against every
    obstacle (:func:`hga_jax.model.collision.arc_violations`). ``legs`` (B, n + 2)
    int32 in 0..2, positional: the leg gene of each position (free turns,
    :mod:`hga_jax.model.cars.free_turns.legs`; the gene of a touched position picks the leg to
    the next touched circle); each leg then looks up ``sa.free_legs`` instead.
    """
    sa = jax.tree.map(jnp.asarray, sa)
    tb = sa.tangents
    dt = sa.centres.dtype
    tol = g.tolerances(dt)
    c = tb.circles.shape[0]
    count, ids, genes = _path_circles(perm, labels, legs)
    gears = None
    if genes is not None and sa.free_legs.cusps is not None:  # a car that reverses
        ids, gears = reversing.compacted(ids, genes, count, tb.circles[:, 3], legs[:, -1], c)
    cx, cy, r, sign = (tb.circles[:, i][ids] for i in range(4))
    oid = tb.obstacle[ids]
    obstacles = col.obstacles(sa.centres, sa.model_radii, ndim=1)  # (n, 1) against (B,) pieces
    bounds = sa.bounds
    full = collision == "full"
    # One row of 8 values per ordered pair: one gather per leg (gathers are slow on
    # the CPU, ~20-30 ns each, whatever their width; small integers are exact in floats).
    if genes is None:
        table = jnp.stack([m.reshape(-1).astype(dt) for m in (
            tb.p1x, tb.p1y, tb.p2x, tb.p2y, tb.length, tb.exists, tb.coincident,
            tb.violations_full if full else tb.violations_paper)], axis=-1)
    else:  # rows (gene * C + a) * C + b, the free circle's centre, sweep and sense after
        fl = sa.free_legs
        more = () if fl.cusps is None else (fl.q1x, fl.q1y, fl.q2x, fl.q2y, fl.cusps)
        table = jnp.stack([m.reshape(-1).astype(dt) for m in (
            fl.p1x, fl.p1y, fl.p2x, fl.p2y, fl.length, fl.exists, fl.coincident,
            fl.violations, fl.fx, fl.fy, fl.sweep, fl.fsign) + more], axis=-1)

    def arc_violations(circle, a, b, swp):
        ccx, ccy, cr, cs, cid, _ = circle
        return col.arc_violations((ccx, ccy, cr, cs), cid, (a[0], a[1], b[0], b[1], swp),
                                  obstacles, bounds, tol.length, collision)

    def leg(carry, xs):
        ax, ay, length, viol = carry
        circle, nxt, real, gene = xs
        c1x, c1y, c1r, c1s, _, c1 = circle
        c2x, c2y, c2r, c2s, _, c2 = nxt
        row = table[c1 * c + c2 if gene is None else (gene * c + c1) * c + c2]  # (B, 8 or 12)
        p1x, p1y, p2x, p2y, tlen = (row[:, i] for i in range(5))
        exists, coincident, tviol = row[:, 5] > 0, row[:, 6] > 0, row[:, 7].astype(jnp.int32)
        # Coincident centres: the tangent lies on the ray through the arrival point, so
        # equal circles of one orientation go on from there; a missing tangent's
        # stand-in joins the two circles along that ray (its length is the table's).
        wx, wy = ax - c1x, ay - c1y
        norm = jnp.sqrt(wx * wx + wy * wy)
        norm = jnp.where(norm > 0, norm, 1.0)
        wx, wy, turn = wx / norm, wy / norm, c1s * c2s * c2r
        p1x = jnp.where(coincident, c1x + c1r * wx, p1x)
        p1y = jnp.where(coincident, c1y + c1r * wy, p1y)
        p2x = jnp.where(coincident, c2x + turn * wx, p2x)
        p2y = jnp.where(coincident, c2y + turn * wy, p2y)
        swp = g.sweep(ax - c1x, ay - c1y, p1x - c1x, p1y - c1y, c1s, tol.angle)
        v = arc_violations(circle, (ax, ay), (p1x, p1y), swp) + tviol
        zero = jnp.zeros_like(swp)
        new = (
            jnp.where(real, p2x, ax),
            jnp.where(real, p2y, ay),
            length + jnp.where(real, c1r * swp + tlen, zero),
            viol + jnp.where(real, v, 0),
        )
        arc = jnp.stack([ax, ay, p1x, p1y, jnp.where(real, swp, zero)])
        line = jnp.stack([p1x, p1y, p2x, p2y, exists.astype(dt)])
        if gene is None:
            return new, (arc, line, None)
        return new, (arc, line, jnp.stack([row[:, k] for k in range(8, row.shape[1])]))

    cols = (cx, cy, r, sign, oid, ids)
    first = tuple(col[:-1] for col in cols)
    real = jnp.arange(cx.shape[0] - 1)[:, None] < (count - 1)[None]
    batch = perm.shape[0]
    sx = jnp.broadcast_to(sa.start[0], (batch,)).astype(dt)
    sy = jnp.broadcast_to(sa.start[1], (batch,)).astype(dt)
    init = (sx, sy, jnp.zeros((batch,), dt), jnp.zeros((batch,), jnp.int32))
    second = tuple(col[1:] for col in cols)
    leg_genes = None if genes is None else genes[:-1]
    (ax, ay, length, viol), (arcs, lines, free) = jax.lax.scan(
        leg, init, (first, second, real, leg_genes))

    # The goal arc: on the last circle, from the arrival point to the goal point.
    last = count - 1
    goal_c = tuple(jnp.take_along_axis(col, last[None], axis=0)[0] for col in cols)
    gx = jnp.broadcast_to(sa.goal[0], (batch,)).astype(dt)
    gy = jnp.broadcast_to(sa.goal[1], (batch,)).astype(dt)
    gswp = g.sweep(ax - goal_c[0], ay - goal_c[1], gx - goal_c[0], gy - goal_c[1], goal_c[3],
                   tol.angle)
    viol = viol + arc_violations(goal_c, (ax, ay), (gx, gy), gswp)
    length = length + goal_c[2] * gswp

    # Per-slot arcs: slot s < count - 1 from the scan, slot count - 1 the goal arc.
    slots = jnp.arange(cx.shape[0])[:, None]
    goal_arc = jnp.stack([ax, ay, gx, gy, gswp])  # (5, B)
    pad = jnp.zeros((1,) + arcs.shape[1:], dt)
    arcs = jnp.concatenate([arcs, pad])  # (S, 5, B)
    arcs = jnp.where((slots == last[None])[:, None, :], goal_arc[None], arcs)
    decoded = Decoded(
        length=length,
        violations=viol,
        count=count,
        circles=jnp.stack([cx, cy, r, sign], axis=-1).transpose(1, 0, 2),
        obstacle=oid.T,
        arcs=arcs.transpose(2, 0, 1),
        lines=lines.transpose(2, 0, 1),
        free=None if free is None else free.transpose(2, 0, 1),
        gears=gears,
    )
    if sa.motion is None:
        return decoded
    return decoded._replace(violations=viol + clearance.violations(
        decoded, sa.motion, sa.centres.shape[0], clearance.subarcs_of(dt)))
