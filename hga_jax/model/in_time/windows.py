"""Windows in time: when a piece of fixed geometry meets a moving robot, as a turn table's columns.

Among robots that move (docs/model.md, "Robots that move") a piece of a path collides with
robot ``j`` or not depending on when the car starts it. For a piece whose geometry is fixed
(a tangent, an arc between two given touch points) and a robot at constant velocity, the
start times at which it collides form a set known before any chromosome is seen:

- a line driven at constant speed from ``P0`` to ``P1`` in ``h`` seconds collides iff the
  robot, seen from the car's point at the start, lies within ``R`` of the segment from 0 to
  the relative displacement ``E = (P1 - P0) - V h``: the robot's track ``O + V T`` meets
  that segment's capsule, which is convex, so the start times form **one open interval**
  (:func:`line_window`, closed form: the track against the two end discs and the slab);
- an arc is judged as :mod:`hga_jax.model.in_time.clearance` judges it: ``K`` sub-arcs, each its chord
  with the reach widened by the chord error ``r (theta / K)^2 / 8``; the union of the
  chords' intervals, shifted to the arc's start, is closed to at most :data:`ARC_WINDOWS`
  intervals by filling its smallest gaps (:func:`merge`; sound: it only ever adds start
  times that collide);
- an arc round a moving robot's own circle is judged by
  :func:`hga_jax.model.in_time.clearance.own_reach`'s bound, whose superlevel set is one interval of
  the time since the circle's moment per sub-arc and sign (:func:`own_windows`).

:func:`build` gives every turn ``(a, b, c)`` of :mod:`hga_jax.model.turns` these windows for
each moving robot: the arc on ``b`` (:data:`ARC_WINDOWS` of them) and the leg that leaves
it (the tangent ``b -> c``: one; a free leg: its lines and free arc), in metres the car has
driven when it arrives on ``b`` (time times speed), so that the look-up
(:func:`hga_jax.model.fitness.looked_up`), which already adds up the length, counts a
robot for each window that holds the length so far. A (piece, robot) pair's windows are
disjoint, so the count is the decoder's: one violation per pair that collides. A window
that ends before any path can arrive at its turn (:func:`soonest`: the shortest walk over
the table) is dropped, and each turn keeps only its windows that hold some time
(:func:`compact`): the table is as wide as its busiest turn. Host code (numpy, float64);
units are metres and seconds.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import geometry as g

ARC_WINDOWS = 2
"""Windows per (arc, moving robot) in the table: the union of its sub-chords' intervals
with all but its largest gap filled (exact where at most two intervals remain)."""
EMPTY = -1.0
SOONEST_MARGIN = 1e-6
"""Metres taken off the least distance driven on arrival before windows that end earlier
are dropped (the decoder's sums of a path's pieces differ from the table's by up to
about 1e-7 m)."""
BLOCK = 4
"""The windows kept per turn are a multiple of this (:func:`compact`): scenes whose
busiest turns differ by less share a compiled program."""
"""``lo = hi = EMPTY``: a window that holds no start time (the car's times are >= 0)."""
MAX_WINDOWS = 2**22
"""The most windows a table holds (turns times moving robots times windows per turn and
robot; 32 MB in float32): above it the fitness decodes leg by leg."""


def per_turn(movers: int, legs: bool = False) -> int:
    """Windows of one turn before :func:`compact`: per moving robot ``ARC_WINDOWS`` for its
    arc and one for its tangent, or with leg genes (``legs``) ``ARC_WINDOWS + 2`` for its
    leg (the lines to and from a free circle, and the free arc)."""
    return movers * (ARC_WINDOWS + (ARC_WINDOWS + 2 if legs else 1))


def fits(entries: int, movers: int, legs: bool = False) -> bool:
    """Whether a table of ``entries`` turns among ``movers`` robots is given its windows
    (the Reeds–Shepp car's turn table at 9 robots is not: 870,000 turns; its fitness
    decodes leg by leg)."""
    return entries * per_turn(movers, legs) <= MAX_WINDOWS


def _linear(a, b, lo_val, hi_val):
    """The open interval of ``T`` where ``lo_val < a T + b < hi_val`` (``(inf, -inf)``
    when empty, ``(-inf, inf)`` when every ``T``)."""
    safe = np.where(a != 0, a, 1.0)
    t1, t2 = (lo_val - b) / safe, (hi_val - b) / safe
    lo = np.where(a > 0, t1, t2)
    hi = np.where(a > 0, t2, t1)
    inside = (lo_val < b) & (b < hi_val)
    lo = np.where(a != 0, lo, np.where(inside, -np.inf, np.inf))
    hi = np.where(a != 0, hi, np.where(inside, np.inf, -np.inf))
    return lo, hi


def line_window(x0, y0, x1, y1, h, ox, oy, vx, vy, reach):
    """``(lo, hi)``: the open interval of start times ``T`` at which a point driven at
    constant speed from ``P0`` (time ``T``) to ``P1`` (time ``T + h``) comes closer than
    ``reach`` to a centre at ``O + t V``; ``lo >= hi`` when there is none. Broadcasting,
    float64. The same test as :func:`hga_jax.model.in_time.clearance.chord_reach` ``< reach^2``."""
    wx, wy = ox - x0, oy - y0  # the robot relative to P0 at T = 0: Q(T) = W + V T
    ex, ey = (x1 - x0) - vx * h, (y1 - y0) - vy * h  # the relative displacement
    vv = vx * vx + vy * vy
    rr = reach * reach
    lo, hi = np.full(np.broadcast(wx, ex, reach).shape, np.inf), None
    hi = -lo
    for cx, cy in ((0.0, 0.0), (ex, ey)):  # the capsule's end discs
        px, py = wx - cx, wy - cy
        b = px * vx + py * vy
        disc = b * b - vv * (px * px + py * py - rr)
        ok = (disc > 0) & (vv > 0)
        s = np.sqrt(np.maximum(disc, 0.0))
        vs = np.where(vv > 0, vv, 1.0)
        lo = np.minimum(lo, np.where(ok, (-b - s) / vs, np.inf))
        hi = np.maximum(hi, np.where(ok, (-b + s) / vs, -np.inf))
        still = (vv == 0) & (px * px + py * py < rr)  # a standing centre inside: always
        lo, hi = np.where(still, -np.inf, lo), np.where(still, np.inf, hi)
    length = np.hypot(ex, ey)
    has = length > 0
    el = np.where(has, length, 1.0)
    ux, uy = ex / el, ey / el
    a_lo, a_hi = _linear(vx * ux + vy * uy, wx * ux + wy * uy, 0.0, length)
    b_lo, b_hi = _linear(vx * -uy + vy * ux, wx * -uy + wy * ux, -reach, reach)
    s_lo, s_hi = np.maximum(a_lo, b_lo), np.minimum(a_hi, b_hi)
    ok = has & (s_lo < s_hi)
    lo = np.minimum(lo, np.where(ok, s_lo, np.inf))
    hi = np.maximum(hi, np.where(ok, s_hi, -np.inf))
    return lo, hi


def merge(lo, hi, keep: int = ARC_WINDOWS):
    """The union of the open intervals ``(lo, hi)`` along the last axis (empty ones have
    ``lo >= hi``) as ``keep`` disjoint intervals ``(..., keep)`` each, sorted: the union's
    ``keep - 1`` largest gaps stay, smaller ones are filled (a superset of the union).
    Unused intervals are ``(inf, -inf)``."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    empty = ~(lo < hi)
    lo, hi = np.where(empty, np.inf, lo), np.where(empty, -np.inf, hi)
    order = np.argsort(lo, axis=-1, kind="stable")
    lo, hi = np.take_along_axis(lo, order, -1), np.take_along_axis(hi, order, -1)
    reach = np.maximum.accumulate(hi, axis=-1)  # the end of what came before, running
    k = lo.shape[-1]
    gap = np.full(lo.shape, -np.inf)
    if k > 1:
        g_ = lo[..., 1:] - reach[..., :-1]
        gap[..., 1:] = np.where(np.isfinite(lo[..., 1:]) & (g_ > 0), g_, -np.inf)
    cut = np.argsort(-gap, axis=-1, kind="stable")[..., :keep - 1]  # the largest gaps
    real = np.take_along_axis(gap, cut, -1) > 0
    cut = np.sort(np.where(real, cut, k), axis=-1)  # k: no cut
    starts = np.concatenate([np.zeros(lo.shape[:-1] + (1,), int), cut], axis=-1)
    ends = np.concatenate([cut, np.full(lo.shape[:-1] + (1,), k)], axis=-1) - 1
    used = starts < k
    out_lo = np.take_along_axis(lo, np.minimum(starts, k - 1), -1)
    out_hi = np.take_along_axis(reach, np.clip(ends, 0, k - 1), -1)
    ok = used & (out_lo < out_hi)
    return np.where(ok, out_lo, np.inf), np.where(ok, out_hi, -np.inf)


def own_windows(mx, my, vx, vy, r, h, i, placed, swp, k, tol):
    """``(lo, hi)`` of shape ``(2,) + shape``: the start times of an arc on a moving robot's
    own circle at which sub-arc ``i`` of ``k`` (time ``h`` each, unit middle direction
    ``(mx, my)``) comes too close by :func:`hga_jax.model.in_time.clearance.own_reach`'s bound, one
    interval for the times after the circle's moment ``placed`` and one before."""
    speed2 = vx * vx + vy * vy
    s2 = np.where(speed2 > 0, speed2, 1.0)
    slack = np.sqrt(speed2) * (swp / k) / 2.0
    eps = 2.0 * r * tol - tol * tol
    mv = mx * vx + my * vy
    los, his = [], []
    for m, sign in ((mv + slack, 1.0), (mv - slack, -1.0)):
        disc = r * r * m * m - speed2 * eps
        ok = (disc > 0) & (speed2 > 0) & (sign * m > 0)
        s = np.sqrt(np.maximum(disc, 0.0))
        tau1, tau2 = (r * m - s) / s2, (r * m + s) / s2
        los.append(np.where(ok, tau1 - (i + 1) * h + placed, np.inf))
        his.append(np.where(ok, tau2 - i * h + placed, -np.inf))
    return np.stack(los), np.stack(his)


class _Robots(NamedTuple):
    """The moving robots as float64 arrays of shape (m, 1, 1) (and their speed)."""

    ox: Any
    oy: Any
    vx: Any
    vy: Any
    radius: Any
    placed: Any
    speed: float


def _arc_windows(rb: _Robots, cx, cy, r, sign, ax, ay, swp, subarcs: int, tol: float,
                 own: int = -1):
    """``(lo, hi)`` (m, A, D, ARC_WINDOWS): the start times (s) at which arcs ``(A, D)``
    from ``A`` on circle ``(cx, cy, r, sign)`` (travel angle ``-sign * swp``) collide with
    each robot, by the decoder's sub-chords; robot ``own`` (its own circle) by its bound."""
    k = subarcs
    ks = np.arange(k + 1, dtype=np.float64).reshape(-1, 1, 1)
    a0 = np.arctan2(ay - cy, ax - cx)
    ang = a0[None] - sign * swp[None] * ks / k  # (K+1, A, D)
    px, py = cx + r * np.cos(ang), cy + r * np.sin(ang)
    h = r * swp / k / rb.speed  # (A, D)
    err = r * (swp / k) ** 2 / 8.0
    reach = np.maximum(rb.radius[None] - tol + err[None, None], 0.0)  # (1, m, A, D)
    lo, hi = line_window(px[:-1, None], py[:-1, None], px[1:, None], py[1:, None],
                         h[None, None], rb.ox[None], rb.oy[None], rb.vx[None], rb.vy[None],
                         reach)  # (K, m, A, D)
    step = ks[:-1, :, :, None] * h  # shifted to the arc's start
    lo, hi = lo - step, hi - step
    if own >= 0:  # the robot's own circle: its own bound instead of the chords
        mx, my = 0.5 * (px[:-1] + px[1:]) - cx, 0.5 * (py[:-1] + py[1:]) - cy
        norm = np.hypot(mx, my)
        norm = np.where(norm > 0, norm, 1.0)
        olo, ohi = own_windows(mx / norm, my / norm, rb.vx[own, 0, 0], rb.vy[own, 0, 0], r,
                               h[None], ks[:-1], rb.placed[own, 0, 0], swp[None], k, tol)
        pad = np.full((k,) + lo.shape[1:], np.inf)
        lo, hi = np.concatenate([lo, pad]), np.concatenate([hi, -pad])
        lo[:, own] = olo.reshape(2 * k, *olo.shape[2:])
        hi[:, own] = ohi.reshape(2 * k, *ohi.shape[2:])
    lo = np.where(swp[None, None] > 0, lo, np.inf)  # a piece of length 0 never collides
    return merge(np.moveaxis(lo, 0, -1), np.moveaxis(hi, 0, -1), ARC_WINDOWS)


def _line_windows(rb: _Robots, x0, y0, x1, y1, tol: float):
    """``(lo, hi)`` (m, ..., 1): the start times (s) at which lines collide with each robot."""
    length = np.hypot(x1 - x0, y1 - y0)
    lo, hi = line_window(x0, y0, x1, y1, length / rb.speed, rb.ox[:, 0], rb.oy[:, 0],
                         rb.vx[:, 0], rb.vy[:, 0], np.maximum(rb.radius[:, 0] - tol, 0.0))
    lo = np.where(length > 0, lo, np.inf)
    return lo[..., None], hi[..., None], length


def _leg_windows(rb: _Robots, legs: dict, subarcs: int, tol: float):
    """``(lo, hi)`` (m, 1, D, w): the start times (s) at which each leg ``D`` leaving a
    circle collides with each robot, its pieces in travel order as the decoder drives them
    (the tangent; or the free arc; or, for a reversing car, the line to the free circle,
    the free arc and the line on)."""
    p1x, p1y, p2x, p2y = legs["p1x"], legs["p1y"], legs["p2x"], legs["p2y"]
    if "fsign" not in legs:  # tangents
        lo, hi, _ = _line_windows(rb, p1x, p1y, p2x, p2y, tol)
        return lo[:, None], hi[:, None]
    on = np.abs(legs["fsign"]) > 0.5
    fx, fy, fswp, fs = legs["fx"], legs["fy"], np.where(on, legs["sweep"], 0.0), legs["fsign"]
    if "q1x" in legs:  # P1 -> Q1 straight, the free circle, Q2 -> P2 straight
        q1x, q1y = np.where(on, legs["q1x"], p2x), np.where(on, legs["q1y"], p2y)
        q2x, q2y = np.where(on, legs["q2x"], p2x), np.where(on, legs["q2y"], p2y)
    else:  # over the free circle from P1 to P2
        q1x, q1y = np.where(on, p1x, p2x), np.where(on, p1y, p2y)
        q2x, q2y = p2x, p2y
    rho = np.where(on, np.hypot(q1x - fx, q1y - fy), 0.0)
    los, his = [], []
    l1lo, l1hi, l1 = _line_windows(rb, p1x, p1y, q1x, q1y, tol)
    alo, ahi = _arc_windows(rb, fx[None], fy[None], rho[None], fs[None], q1x[None],
                            q1y[None], fswp[None], subarcs, tol)  # (m, 1, D, w)
    l2lo, l2hi, _ = _line_windows(rb, q2x, q2y, p2x, p2y, tol)
    l2lo = np.where(on, l2lo[..., 0], np.inf)[..., None]
    t_arc = l1 / rb.speed
    t_l2 = (l1 + rho * fswp) / rb.speed
    los = [l1lo[:, None], alo - t_arc[None, None, :, None], l2lo[:, None] - t_l2[..., None]]
    his = [l1hi[:, None], ahi - t_arc[None, None, :, None], l2hi[:, None] - t_l2[..., None]]
    return np.concatenate(los, axis=-1), np.concatenate(his, axis=-1)


def soonest(lengths, circles: int, variants: int = 1):
    """``(V C + 1, C)``: a lower bound on the metres a path has driven when it arrives on
    circle ``b`` by leg ``i`` (rows as the turn table's), the shortest walk over the turn
    table's ``lengths`` ((T,) float64) from the start point, whatever its violations and
    whether it repeats a circle (every chromosome's path is such a walk); inf where no walk
    arrives. Relaxed to a fixed point (every length >= 0)."""
    c, side = circles, variants * circles + 1
    length = np.asarray(lengths, np.float64).reshape(side, c, side)
    d = np.full((side, c), np.inf)
    d[side - 1] = 0.0  # the start point's row (only the start circles occur in it)
    legs = np.arange(side - 1)
    rows = (legs // c)[None, :] * c + np.arange(c)[:, None]  # (C, VC): gene v_b, from b
    cols = np.broadcast_to(legs % c, rows.shape)  # to circle c
    for _ in range(side * c):
        best = np.min(d[:, :, None] + length, axis=0)[:, :-1]  # (C, VC): over i
        new = np.minimum(d[rows, cols], best)
        if np.array_equal(new, d[rows, cols]):
            break
        d[rows, cols] = new
    return d


def build(tb: Any, start, goal, motion: Any, obstacle_movers, subarcs: int, tol: float,
          legs: Any = None, arrival=None):
    """The windows of every turn of a turn table (:mod:`hga_jax.model.turns`, index ``(i *
    C + b) * (V C + 1) + d``): ``(T, 2 W)`` float64, per moving robot its arc's
    :data:`ARC_WINDOWS` windows then its leg's (the tangent's one; a free leg's pieces'),
    each ``(lo, hi)`` in metres driven when the car arrives on ``b``.

    ``tb``: the float64 tangent table; ``motion``: the float64
    :class:`~hga_jax.model.scenario.Motion`; ``obstacle_movers``: (n,) the moving robot of
    each obstacle (-1 for one that stands); ``subarcs`` and ``tol``: the decoder's
    (:func:`hga_jax.model.in_time.clearance.subarcs_of`, the length tolerance of its dtype); ``legs``:
    a float64 :class:`~hga_jax.model.cars.free_turns.legs.LegTable` (chromosomes with leg genes) or
    None (the tight rope); ``arrival``: :func:`soonest` (windows that end before a path can
    arrive are dropped) or None (the straight distance from the start bounds it)."""
    f8 = np.float64
    circles = np.asarray(tb.circles, f8)
    c = circles.shape[0]
    cx, cy, r, sign = (circles[:, i] for i in range(4))
    obstacle = np.asarray(tb.obstacle)
    names = ("p1x", "p1y", "p2x", "p2y", "coincident")
    extra = () if legs is None else ("fx", "fy", "sweep", "fsign") + (
        () if legs.q1x is None else ("q1x", "q1y", "q2x", "q2y"))
    source = tb if legs is None else legs
    parts = {k: np.asarray(getattr(source, k), f8).reshape(-1, c, c) for k in names + extra}
    v = parts["p1x"].shape[0]

    def arriving(x):  # (V, C, C) by (gene, a, b) -> (V C, C): rows i = v C + a
        return x.reshape(v * c, c)

    def leaving(x):  # (V, C, C) by (gene, b, c) -> (C, V C): columns d = v C + c
        return x.transpose(1, 0, 2).reshape(c, v * c)

    movers = np.asarray(obstacle_movers)
    real = np.flatnonzero(np.asarray(motion.index) < movers.size)  # the first m robots
    m = real.size  # the padding's robots (index n) never come near: no windows for them
    rb = _Robots(*(np.asarray(x, f8)[real].reshape(m, 1, 1) for x in (
        motion.centres[:, 0], motion.centres[:, 1], motion.velocities[:, 0],
        motion.velocities[:, 1], motion.radii, motion.placed)), float(motion.speed))
    # Arrival points on b (rows i, the start point last), departures (columns d, the goal
    # point last; it has no leg).
    arr_x = np.vstack([arriving(parts["p2x"]), np.full((1, c), start[0])])  # (VC+1, C)
    arr_y = np.vstack([arriving(parts["p2y"]), np.full((1, c), start[1])])
    dep_x = np.hstack([leaving(parts["p1x"]), np.full((c, 1), goal[0])])  # (C, VC+1)
    dep_y = np.hstack([leaving(parts["p1y"]), np.full((c, 1), goal[1])])
    coincident = np.hstack([leaving(parts["coincident"]) > 0, np.zeros((c, 1), bool)])
    leg_parts = {k: leaving(x) for k, x in parts.items() if k != "coincident"}
    tol_angle = g.tolerances(f8).angle
    w = ARC_WINDOWS
    out = None
    for b in range(c):
        ax = np.broadcast_to(arr_x[:, b][:, None], (v * c + 1, v * c + 1))
        ay = np.broadcast_to(arr_y[:, b][:, None], (v * c + 1, v * c + 1))
        bx = np.where(coincident[b], ax, dep_x[b][None, :])
        by = np.where(coincident[b], ay, dep_y[b][None, :])
        swp = g.sweep(ax - cx[b], ay - cy[b], bx - cx[b], by - cy[b], sign[b], tol_angle)
        own = int(movers[obstacle[b]]) if obstacle[b] >= 0 else -1
        alo, ahi = _arc_windows(rb, cx[b], cy[b], r[b], sign[b], ax, ay, swp, subarcs, tol,
                                own)  # (m, A, D, w)
        llo, lhi = _leg_windows(rb, {k: x[b] for k, x in leg_parts.items()}, subarcs, tol)
        none = np.full(llo.shape[:2] + (1,) + llo.shape[3:], np.inf)  # the goal point's
        llo, lhi = np.concatenate([llo, none], axis=2), np.concatenate([lhi, -none], axis=2)
        shift = (r[b] * swp / rb.speed)[None, :, :, None]  # the leg starts after the arc
        lo = np.concatenate([alo, llo - shift], axis=-1)  # (m, A, D, windows per robot)
        hi = np.concatenate([ahi, lhi - shift], axis=-1)
        lo, hi = lo * rb.speed, hi * rb.speed  # metres driven on arrival
        # A car arriving at A has driven at least |A - start|, and at least the shortest
        # walk there: earlier windows never hold.
        first = np.hypot(arr_x[:, b] - start[0], arr_y[:, b] - start[1])
        if arrival is not None:
            first = np.maximum(first, arrival[:, b])
        first = first - SOONEST_MARGIN
        ok = (lo < hi) & (hi > first[None, :, None, None])
        lo, hi = np.where(ok, lo, EMPTY), np.where(ok, hi, EMPTY)
        if out is None:
            out = np.full((v * c + 1, c, v * c + 1, m, lo.shape[-1], 2), EMPTY)
        out[:, b, :, :, :, 0] = np.moveaxis(lo, 0, 2)
        out[:, b, :, :, :, 1] = np.moveaxis(hi, 0, 2)
    return out.reshape(out.shape[0] * c * out.shape[2], -1)


def hits(windows, driven):
    """How many windows of each row hold ``driven`` (the metres driven on arrival): the
    violations in time of each looked-up turn. ``windows`` (B, 2 W), ``driven`` (B,)."""
    import jax.numpy as jnp

    lo, hi = windows[:, 0::2], windows[:, 1::2]
    d = driven[:, None]
    return jnp.sum((lo < d) & (d < hi), axis=1, dtype=jnp.int32)


__all__ = ["ARC_WINDOWS", "EMPTY", "MAX_WINDOWS", "build", "fits", "hits", "line_window",
           "merge", "own_windows", "per_turn"]


def table(entries, sa64: Any, n: int, subarcs: int, tol: float, legs: Any = None,
          tangents: Any = None):
    """A turn table among robots that move: the static ``entries`` ((T, 2), the rules for
    what stands, built with the moving robots' blocking radii 0) with one more violation
    per wrap of a moving robot's circle where :class:`~hga_jax.model.scenario.Motion` says
    so (``wrap_penalty``), and the windows of :func:`build` as more columns (:func:`compact`):
    ``(T, 2 + 2 K)`` float64, or None when they would not fit (:func:`fits`). ``sa64``: the
    float64 scenario arrays (their ``motion`` set); ``n``: the obstacle count; ``legs``:
    the float64 leg table of chromosomes with leg genes; ``tangents``: the tangent table
    the turn table was built on (default ``sa64.tangents``)."""
    motion = sa64.motion
    m = motion.centres.shape[0]
    entries = np.array(entries, np.float64)
    if not fits(entries.shape[0], int(np.sum(np.asarray(motion.index) < n)), legs is not None):
        return None
    tb = sa64.tangents if tangents is None else tangents
    c = np.asarray(tb.circles).shape[0]
    rows = entries.shape[0] // c
    side = int(round(math.sqrt(rows)))  # V C + 1
    obstacle = np.asarray(tb.obstacle)
    index = np.asarray(motion.index)
    movers = np.full(n + 1, -1)
    movers[index] = np.arange(m)
    movers[n] = -1  # the padding's index
    if int(motion.wrap_penalty):
        wraps = np.where(obstacle >= 0, movers[np.maximum(obstacle, 0)] >= 0, False)
        entries.reshape(side, c, side, 2)[:, wraps, :, 1] += float(motion.wrap_penalty)
    arrival = soonest(entries[:, 0], c, (side - 1) // c)
    windows = build(tb, np.asarray(sa64.start), np.asarray(sa64.goal), motion, movers[:n],
                    subarcs, tol, legs, arrival)
    return np.concatenate([entries, compact(windows)], axis=1)


def compact(windows):
    """The windows of each row that hold some time, first, the rest dropped: ``(T, 2 K)``
    with ``K`` the most any row holds, rounded up to a multiple of :data:`BLOCK` (at least
    one block). The count of windows holding a time is unchanged (the look-up reads
    fewer columns: most moving robots never come near most turns)."""
    w = np.asarray(windows).reshape(windows.shape[0], -1, 2)
    real = w[..., 0] < w[..., 1]
    order = np.argsort(~real, axis=1, kind="stable")
    w = np.take_along_axis(w, order[..., None], axis=1)
    most = int(real.sum(axis=1).max()) if real.size else 0
    k = max(BLOCK, -(-most // BLOCK) * BLOCK)
    if k > w.shape[1]:
        w = np.concatenate([w, np.full((w.shape[0], k - w.shape[1], 2), EMPTY)], axis=1)
    return w[:, :k].reshape(w.shape[0], 2 * k)


def for_scenario(sc: Any, entries, dtype: Any, legs: Any = None, tangents: Any = None):
    """:func:`table` of a scenario's static turn table ``entries`` for the search in
    ``dtype`` (the decoder's sub-arcs and tolerance of that dtype)."""
    from hga_jax.model.in_time.clearance import subarcs_of

    return table(entries, sc.arrays(np.float64), sc.n, subarcs_of(dtype),
                 g.tolerances(dtype).length, legs, tangents)
