"""Robots that move: the car's time along its path and clearance in space and time.

The model (docs/model.md, "Moving robots"): robot ``j`` moves at constant velocity,
its centre at time ``t >= 0`` being ``O_j + t V_j``; the car drives its path at constant
``speed`` from the start pose at time 0, so the point at arc length ``s`` is reached at
``t = s / speed`` (a cusp takes no time). A piece of the path violates robot ``j`` when,
at some moment the car is on it, the car's point is closer than ``R_j - tol`` to the
robot's centre at that moment: one violation per (piece, moving robot) pair. A path that
may wrap a moving robot: its circle stands where the robot is when the car passes it
(:meth:`hga_jax.model.scenario.Scenario.placement_times`), and an arc on it is judged
against that robot by :func:`own_reach` (with ``wrap_moving = "never"`` each wrap counts
one violation instead).

The test of one piece against one robot is sound: it never calls a piece clear that
comes closer than ``R_j - tol``.

- A line, driven at constant speed, against a centre moving at constant velocity: the
  distance between them is that of a point moving on a line relative to the robot, so
  its minimum over the piece is a clamped quadratic (closed form).
- An arc is cut into ``K`` sub-arcs, each replaced by its chord driven at constant
  speed over the same time. The car's true point is never farther than
  ``r (theta / K)^2 / 8`` from the chord's point at the same moment (the error of
  linear interpolation, ``|e''| <= r (theta/K)^2`` over the unit interval), so a sub-arc
  is called clear only when its chord keeps ``R_j - tol + r (theta / K)^2 / 8``; a piece
  closer than that by less than the bound is called a violation (conservative).
  The sub-arcs' ends come from the arc's ends by rotations whose cosines and sines are
  halved from the arc's own (no trigonometric call per arc).

:func:`violations` is device code (jit/vmap-able, any float dtype) over a
:class:`~hga_jax.model.decode.Decoded` batch, the same for the three car models: the
pieces of every slot in travel order are the arc on its circle, then its leg's line to
the free circle, the free arc and the line on (a tangent leg is the first line alone; the
forward car's free leg the free arc alone). :func:`segment_hits` is the float64 host
check over the segments of the result files, with sub-arcs of at most ``HOST_SUB_ANGLE``, which
re-verifies every reported path; :func:`closest_approach` samples a path densely (plots
and the independent check of the tests).
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple, Sequence

import numpy as np

from hga_jax.model.geometry import tolerances, xp_of

SUBARCS = 8
"""Sub-arcs per arc in the search's float32 fitness: a chord error of at most
``r (theta/8)^2 / 8`` (1.4 mm for a quarter turn of radius 0.3 m, called a violation when
that close)."""
SUBARCS_64 = 64
"""Sub-arcs per arc in the float64 decoder that re-evaluates every run's best (23 micrometres
for a quarter turn of 0.3 m)."""
HOST_SUB_ANGLE = 2.0 * math.pi / 1024
"""The largest sub-arc (rad) of the float64 path check of the result files: a chord error of
at most ``r * 4.7e-6`` (1.4 micrometres at 0.3 m)."""


def subarcs_of(dtype: Any) -> int:
    """Sub-arcs per arc of the decoder in ``dtype``: :data:`SUBARCS` or :data:`SUBARCS_64`."""
    return SUBARCS_64 if np.dtype(dtype) == np.float64 else SUBARCS


# ---------------------------------------------------------------------------
# One piece against one robot (array-generic: numpy on the host, jax on the device).

def chord_reach(p0x, p0y, p1x, p1y, t0, h, ox, oy, vx, vy):
    """The squared least distance between a point driven at constant speed from ``P0``
    (time ``t0``) to ``P1`` (time ``t0 + h``) and a centre at ``O + t V`` over those
    times: the clamped quadratic of their relative motion. Broadcasting."""
    xp = xp_of(p0x, p0y, p1x, p1y, t0, h, ox, oy, vx, vy)
    dx, dy = p0x - (ox + vx * t0), p0y - (oy + vy * t0)  # apart at t0
    ex, ey = (p1x - p0x) - vx * h, (p1y - p0y) - vy * h  # relative displacement
    ee = ex * ex + ey * ey
    s = xp.clip(-(dx * ex + dy * ey) / xp.where(ee > 0, ee, 1.0), 0.0, 1.0)
    fx, fy = dx + s * ex, dy + s * ey
    return fx * fx + fy * fy


def _half(c, s, big):
    """cos and sin of half the angle ``a`` in [0, 2 pi) whose cos and sin are ``c``, ``s``
    (``big``: ``a > pi``), without cancellation: from the larger of ``1 + c``, ``1 - c``."""
    xp = xp_of(c, s, big)
    up = c >= 0
    ch = xp.sqrt(xp.maximum(0.5 * (1.0 + c), 0.0))
    sh = xp.sqrt(xp.maximum(0.5 * (1.0 - c), 0.0)) * xp.where(big, -1.0, 1.0)
    ch, sh = (xp.where(up, ch, s / xp.where(sh != 0, 2.0 * sh, 1.0)),
              xp.where(up, s / xp.where(ch != 0, 2.0 * ch, 1.0), sh))
    return xp.where(big, -ch, ch), xp.where(big, -sh, sh)


def arc_points(cx, cy, r, ax, ay, swp, direction, cos_sin, k: int):
    """The ``k + 1`` points (lists of arrays) that cut the arc from ``A`` (centre ``C``,
    radius ``r``, sweep ``swp`` >= 0, ``direction`` +1 counter-clockwise, -1 clockwise)
    into ``k`` equal sub-arcs (``k`` a power of 2), and the chord error bound of each.
    ``cos_sin``: cos and sin of the sweep."""
    xp = xp_of(cx, cy, r, ax, ay, swp, direction)
    c, s = cos_sin
    big = swp > math.pi
    steps = 0
    while (1 << steps) < k:
        c, s = _half(c, s, big)
        big = big & False
        steps += 1
    s = s * direction  # the signed rotation of one sub-arc
    ux, uy = ax - cx, ay - cy
    xs, ys = [ax], [ay]
    for _ in range(k):
        ux, uy = c * ux - s * uy, s * ux + c * uy
        xs.append(cx + ux)
        ys.append(cy + uy)
    sub = swp / k
    return xs, ys, r * sub * sub / 8.0 + xp.zeros_like(swp)


def _reached(px, py, t, h, err, motion_arrays, tol, skip=None):
    """(m,) + P bool: which robots come closer than ``R - tol`` to the chord pieces from
    points ``px[i], py[i]`` (lists of ``k + 1`` arrays of shape P) at times ``t + i h``.
    ``motion_arrays``: ``(ox, oy, vx, vy, R)``, each (m,) + (1,) * len(P)."""
    xp = xp_of(h, err)
    k = len(px) - 1
    ox, oy, vx, vy, radius = motion_arrays  # (m,) + (1,) * len(P)
    reach = xp.maximum(radius - tol + err, 0.0)
    reach2 = reach * reach
    hit = None
    for i in range(k):  # a running "or": elementwise, no reduction over the sub-arcs
        d2 = chord_reach(px[i], py[i], px[i + 1], py[i + 1], t + i * h, h, ox, oy, vx, vy)
        here = d2 < reach2
        hit = here if hit is None else hit | here
    return hit if skip is None else hit & ~skip


def own_reach(px, py, cx, cy, r, t, h, vx, vy, placed, swp, tol):
    """P bool: whether a robot comes closer than ``r - tol`` to the car on an arc of its
    own circle (centre ``C`` where the robot is at time ``placed``, radius ``r`` its model
    radius), the arc cut at points ``px[i], py[i]`` (lists of ``k + 1`` arrays, the car
    there at ``t + i h``), sweep ``swp``; the robot moves at ``V``.

    Relative to the robot the car is at ``r u(t) - V tau`` (``tau = t - placed``), at squared
    distance ``r^2 - 2 r tau (u . V) + tau^2 |V|^2``: it comes too close iff
    ``2 r tau (u . V) - tau^2 |V|^2 > 2 r tol - tol^2``. On a sub-arc of angle ``phi``, ``u``
    is within ``phi / 2`` of its middle's direction ``m``, so ``tau (u . V) <= tau (m . V) +
    |tau| |V| phi / 2``; the concave bound is maximised in closed form on each sign of
    ``tau``. Sound (never clear when too close); conservative by at most that term."""
    xp = xp_of(t, h, swp)
    k = len(px) - 1
    phi = swp / k
    speed2 = vx * vx + vy * vy
    s2 = xp.where(speed2 > 0, speed2, 1.0)
    slack = xp.sqrt(speed2) * phi / 2.0
    eps = 2.0 * r * tol - tol * tol
    hit = None
    for i in range(k):
        mx, my = 0.5 * (px[i] + px[i + 1]) - cx, 0.5 * (py[i] + py[i + 1]) - cy
        norm = xp.sqrt(mx * mx + my * my)
        norm = xp.where(norm > 0, norm, 1.0)
        mv = (mx * vx + my * vy) / norm
        a, b = t + i * h - placed, t + (i + 1) * h - placed
        best = None
        for lo, hi, m in ((xp.maximum(a, 0.0), xp.maximum(b, 0.0), mv + slack),
                          (xp.minimum(a, 0.0), xp.minimum(b, 0.0), mv - slack)):
            tau = xp.clip(r * m / s2, lo, hi)
            q = 2.0 * r * tau * m - tau * tau * speed2
            best = q if best is None else xp.maximum(best, q)
        here = (best > eps) & (speed2 > 0)
        hit = here if hit is None else hit | here
    return hit


# ---------------------------------------------------------------------------
# The device fitness: every piece of a decoded batch against every moving robot.

def violations(d: Any, motion: Any, n: int, subarcs: int = SUBARCS):
    """(B,) int32: the violations in time of a decoded batch ``d``
    (:class:`~hga_jax.model.decode.Decoded`, batch first) among the moving robots of
    ``motion`` (:class:`~hga_jax.model.scenario.Motion`): one per (piece, moving robot)
    pair that comes too close while the car is on the piece, and one per moving robot's
    circle the path wraps. ``n``: the scenario's obstacle count. Pure, jit/vmap-able."""
    import jax.numpy as jnp

    dt = d.arcs.dtype
    tol = tolerances(dt).length
    count = d.count  # (B,)
    slots = d.arcs.shape[1]
    arcs = jnp.moveaxis(d.arcs, 0, -1)  # (S, 5, B)
    circ = jnp.moveaxis(d.circles, 0, -1)  # (S, 4, B)
    lines = jnp.moveaxis(d.lines, 0, -1)  # (S - 1, 5, B)
    idx = jnp.arange(slots)[:, None]
    real_arc = idx < count[None]  # (S, B)
    real_leg = idx[:-1] < (count - 1)[None]  # (S - 1, B)

    # The circle arc of each slot.
    cx, cy, r, sign = (circ[:, i] for i in range(4))
    ax, ay, bx, by, swp = (arcs[:, i] for i in range(5))
    swp = jnp.where(real_arc, swp, 0.0)
    pieces = [_arc(cx, cy, r, ax, ay, bx, by, swp, -sign, subarcs)]
    # Each leg: the line to the free circle, the free arc, the line on.
    p1x, p1y, p2x, p2y = (lines[:, i] for i in range(4))
    zero = jnp.zeros_like(p1x)
    if d.free is None:
        pieces.append(_line(p1x, p1y, p2x, p2y, real_leg))
    else:
        free = jnp.moveaxis(d.free, 0, -1)  # (S - 1, 4 or 9, B)
        fx, fy, fswp, fs = (free[:, i] for i in range(4))
        on = jnp.abs(fs) > 0.5
        if free.shape[1] > 4:  # P1 -> Q1 straight, the free circle, Q2 -> P2 straight
            q1x, q1y, q2x, q2y = (jnp.where(on, free[:, i], p) for i, p in
                                  zip(range(4, 8), (p2x, p2y, p2x, p2y)))
        else:  # over the free circle from P1 to P2
            q1x, q1y = jnp.where(on, p1x, p2x), jnp.where(on, p1y, p2y)
            q2x, q2y = p2x, p2y
        rho = jnp.where(on, jnp.sqrt((q1x - fx) ** 2 + (q1y - fy) ** 2), 0.0)
        pieces.append(_line(p1x, p1y, q1x, q1y, real_leg))
        pieces.append(_arc(fx, fy, rho, q1x, q1y, q2x, q2y,
                           jnp.where(on & real_leg, fswp, 0.0), -fs, subarcs))
        pieces.append(_line(q2x, q2y, p2x, p2y, real_leg & on))
    # Travel order: slot s's arc, then leg s's pieces; slot S - 1 has no leg.
    lengths = [p.length for p in pieces]
    lengths = [lengths[0]] + [jnp.concatenate([x, jnp.zeros_like(x[:1])]) for x in lengths[1:]]
    order = jnp.stack(lengths, axis=1)  # (S, pieces per slot, B)
    flat = order.reshape(-1, order.shape[-1])
    before = (jnp.cumsum(flat, axis=0) - flat).reshape(order.shape) / motion.speed
    m = motion.centres.shape[0]
    robots = tuple(a.reshape((m, 1, 1)) for a in (
        motion.centres[:, 0], motion.centres[:, 1], motion.velocities[:, 0],
        motion.velocities[:, 1], motion.radii))
    # An arc on a moving robot's own circle is judged against that robot apart (own_reach).
    mover_of = jnp.full((n,), -1, jnp.int32).at[motion.index].set(
        jnp.arange(m, dtype=jnp.int32), mode="drop")  # the padding's index n: dropped
    own = d.obstacle.T  # (S, B)
    own_j = jnp.where(own >= 0, mover_of[jnp.maximum(own, 0)], -1)
    total = jnp.zeros(count.shape, jnp.int32)
    for j, p in enumerate(pieces):
        t0 = before[:, j] if j == 0 else before[:-1, j]
        h = p.length / p.cuts / motion.speed
        skip = (jnp.arange(m)[:, None, None] == own_j[None]) if j == 0 else None
        hit = _reached(p.xs, p.ys, t0, h, p.err, robots, tol, skip) & (p.length > 0)
        total = total + jnp.sum(hit, axis=(0, 1), dtype=jnp.int32)
        if j == 0:
            oj = jnp.maximum(own_j, 0)
            mine = own_reach(p.xs, p.ys, cx, cy, r, t0, h, motion.velocities[oj, 0],
                             motion.velocities[oj, 1], motion.placed[oj], swp, tol)
            total = total + jnp.sum(mine & (own_j >= 0) & (p.length > 0), axis=0,
                                    dtype=jnp.int32)
    wraps = real_arc & (own_j >= 0)
    return total + motion.wrap_penalty * jnp.sum(wraps, axis=0, dtype=jnp.int32)


class _Piece(NamedTuple):
    xs: list  # k + 1 arrays of points along the piece, in travel order
    ys: list
    err: Any  # the chord error bound (0 for a line)
    length: Any  # metres (0 where the piece is not on the path)
    cuts: int


def _line(p1x, p1y, p2x, p2y, real):
    import jax.numpy as jnp

    length = jnp.where(real, jnp.sqrt((p2x - p1x) ** 2 + (p2y - p1y) ** 2), 0.0)
    return _Piece([p1x, p2x], [p1y, p2y], jnp.zeros_like(p1x), length, 1)


def _arc(cx, cy, r, ax, ay, bx, by, swp, direction, k):
    import jax.numpy as jnp

    ux, uy, wx, wy = ax - cx, ay - cy, bx - cx, by - cy
    rr = r * r
    rr = jnp.where(rr > 0, rr, 1.0)
    cos_sin = ((ux * wx + uy * wy) / rr, direction * (ux * wy - uy * wx) / rr)
    xs, ys, err = arc_points(cx, cy, r, ax, ay, swp, direction, cos_sin, k)
    return _Piece(xs, ys, err, r * swp, k)


# ---------------------------------------------------------------------------
# The float64 path check over the segments of the result files (host).

class TimedSegment(NamedTuple):
    """A result-file segment with the car's times on it (s) and its length (m)."""

    index: int
    segment: dict
    t0: float
    t1: float
    length: float


def timed(segments: Sequence[dict], speed: float) -> list[TimedSegment]:
    """The segments in travel order with the times the car enters and leaves each."""
    out, s = [], 0.0
    for i, seg in enumerate(segments):
        if seg["type"] == "arc":
            length = float(seg["radius"]) * abs(float(seg["sweep"]))
        else:
            length = math.dist(seg["start"], seg["end"])
        out.append(TimedSegment(i, seg, s / speed, (s + length) / speed, length))
        s += length
    return out


def _robot_arrays(scenario: Any):
    """(ox, oy, vx, vy, R, index) float64 numpy arrays of the scenario's moving robots."""
    idx = np.flatnonzero(scenario.moving)
    vel = np.asarray(scenario.velocities, float).reshape(scenario.n, 2)
    return (np.asarray(scenario.centres, float)[idx, 0], np.asarray(scenario.centres, float)[idx, 1],
            vel[idx, 0], vel[idx, 1], np.asarray(scenario.model_radii, float)[idx], idx)


def _segment_points(seg: dict, cuts: int):
    """Points cutting a segment into ``cuts`` pieces (float64) and the chord error bound."""
    if seg["type"] == "line":
        (x0, y0), (x1, y1) = seg["start"], seg["end"]
        return np.array([x0, x1], float), np.array([y0, y1], float), 0.0
    cx, cy = seg["center"]
    r, a0, sw = float(seg["radius"]), float(seg["start_angle"]), float(seg["sweep"])
    ang = a0 + sw * np.arange(cuts + 1) / cuts
    sub = abs(sw) / cuts
    return cx + r * np.cos(ang), cy + r * np.sin(ang), r * sub * sub / 8.0


def segment_hits(scenario: Any, segments: Sequence[dict],
                 sub_angle: float = HOST_SUB_ANGLE) -> list[tuple[int, int]]:
    """``(segment index, obstacle index from 0)`` of each (segment, moving robot) pair
    that comes closer than ``R - tol`` (float64) while the car is on the segment, by the
    sound tests of the module doc (arcs cut into sub-arcs of at most ``sub_angle`` rad; an
    arc round a moving robot's centre at some moment, where its circle stands in the
    tables or a frozen copy of it, by :func:`own_reach`); empty when nothing moves. All
    pieces at once (numpy)."""
    if not scenario.has_motion:
        return []
    ox, oy, vx, vy, big_r, idx = _robot_arrays(scenario)
    tol = tolerances(np.float64).length
    parts, owned = [], []  # per segment: (x0, y0, x1, y1, t0, h, err), own arcs apart
    for ts in timed(segments, float(scenario.speed)):
        if ts.length <= 0.0:
            continue
        seg = ts.segment
        cuts = 1 if seg["type"] == "line" else max(1, math.ceil(abs(seg["sweep"]) / sub_angle))
        xs, ys, err = _segment_points(seg, cuts)
        h = (ts.t1 - ts.t0) / cuts
        own = np.zeros(idx.size, bool)
        if seg["type"] == "arc":
            # An arc round a moving robot's centre at some moment t* (its circle in the
            # tables, or a frozen copy): judged against that robot by own_reach.
            cx, cy = (float(v) for v in seg["center"])
            own, when = _round_robot(seg, ox, oy, vx, vy, big_r)
            for j in np.flatnonzero(own):
                owned.append((ts.index, j, own_reach(
                    list(xs), list(ys), cx, cy, float(big_r[j]), ts.t0, h, vx[j], vy[j],
                    when[j], abs(float(seg["sweep"])), tol)))
        steps = np.arange(cuts)
        parts.append((ts.index, xs[:-1], ys[:-1], xs[1:], ys[1:], ts.t0 + steps * h, h, err, own))
    if not parts:
        return []
    seg_of = np.concatenate([np.full(len(p[1]), p[0]) for p in parts])
    x0, y0, x1, y1, t0 = (np.concatenate([p[i] for p in parts]) for i in range(1, 6))
    h = np.concatenate([np.full(len(p[1]), p[6]) for p in parts])
    err = np.concatenate([np.full(len(p[1]), p[7]) for p in parts])
    skip = np.concatenate([np.repeat(p[8][:, None], len(p[1]), axis=1) for p in parts], axis=1)
    d2 = chord_reach(x0, y0, x1, y1, t0, h, ox[:, None], oy[:, None], vx[:, None], vy[:, None])
    reach = np.maximum(big_r[:, None] - tol + err, 0.0)
    close = (d2 < reach * reach) & ~skip  # (m, pieces)
    hits = {(int(seg_of[i]), int(idx[j])) for j, i in zip(*np.nonzero(close))}
    hits |= {(int(i), int(idx[j])) for i, j, hit in owned if bool(hit)}
    return sorted(hits)


def moments_wrapped(scenario: Any, segments: Sequence[dict]) -> dict[int, float]:
    """``{obstacle index from 0: t*}`` for each moving robot that an arc of the path turns
    round where the robot is at the moment ``t*`` (s): the arc's radius is the robot's
    model radius and its centre the robot's centre then (to 1e-9 m)."""
    if not scenario.has_motion:
        return {}
    ox, oy, vx, vy, big_r, idx = _robot_arrays(scenario)
    out: dict[int, float] = {}
    for seg in segments:
        if seg["type"] == "arc":
            on, when = _round_robot(seg, ox, oy, vx, vy, big_r)
            for j in np.flatnonzero(on):
                out.setdefault(int(idx[j]), float(when[j]))
    return out


def _round_robot(seg: dict, ox, oy, vx, vy, big_r):
    """``(on, when)``, (m,) each: which moving robots an arc segment turns round where the
    robot is at some moment (its radius the robot's model radius, its centre the robot's
    centre then, to 1e-9 m), and that moment ``t*`` (s)."""
    cx, cy = (float(v) for v in seg["center"])
    speed2 = vx * vx + vy * vy
    when = ((cx - ox) * vx + (cy - oy) * vy) / np.where(speed2 > 0, speed2, 1.0)
    on = (np.abs(big_r - seg["radius"]) < 1e-9) & (speed2 > 0) & (
        np.hypot(ox + vx * when - cx, oy + vy * when - cy) < 1e-9)
    return on, when


def sample(segments: Sequence[dict], speed: float, spacing: float = 1e-3):
    """Points of the path every ``spacing`` metres or closer (each segment's ends
    included) with the car's time at each: ``(x, y, t)`` float64 arrays."""
    xs, ys, ts = [], [], []
    for seg in timed(segments, speed):
        cuts = max(1, int(math.ceil(seg.length / spacing)))
        u = np.arange(cuts + 1) / cuts
        if seg.segment["type"] == "line":
            (x0, y0), (x1, y1) = seg.segment["start"], seg.segment["end"]
            x, y = x0 + (x1 - x0) * u, y0 + (y1 - y0) * u
        else:
            cx, cy = seg.segment["center"]
            r = float(seg.segment["radius"])
            ang = float(seg.segment["start_angle"]) + float(seg.segment["sweep"]) * u
            x, y = cx + r * np.cos(ang), cy + r * np.sin(ang)
        xs.append(x)
        ys.append(y)
        ts.append(seg.t0 + (seg.t1 - seg.t0) * u)
    if not xs:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    return np.concatenate(xs), np.concatenate(ys), np.concatenate(ts)


class Approach(NamedTuple):
    """A moving robot's closest approach to the car along a path."""

    obstacle: int  # index from 0
    time: float  # s
    distance: float  # centre to the car's point, m
    clearance: float  # distance - R (negative: a collision)
    car: tuple[float, float]  # the car's point then
    centre: tuple[float, float]  # the robot's centre then


def closest_approach(scenario: Any, segments: Sequence[dict], spacing: float = 1e-3,
                     start: tuple[float, float] | None = None) -> list[Approach]:
    """Each moving robot's closest approach to the car along the path, sampled every
    ``spacing`` metres (the independent dense check; plots draw robots there).
    ``start``: the car's point for a path with no segment (it stays there at time 0)."""
    if not scenario.has_motion:
        return []
    x, y, t = sample(segments, float(scenario.speed), spacing)
    if x.size == 0:
        p = start if start is not None else scenario.start[:2]
        x, y, t = np.array([p[0]]), np.array([p[1]]), np.zeros(1)
    ox, oy, vx, vy, big_r, idx = _robot_arrays(scenario)
    out = []
    for j in range(idx.size):
        cx, cy = ox[j] + vx[j] * t, oy[j] + vy[j] * t
        dist = np.hypot(x - cx, y - cy)
        i = int(np.argmin(dist))
        out.append(Approach(int(idx[j]), float(t[i]), float(dist[i]), float(dist[i] - big_r[j]),
                            (float(x[i]), float(y[i])), (float(cx[i]), float(cy[i]))))
    return out


def at(scenario: Any, point: Sequence[float], t: float) -> list[tuple[int, float]]:
    """``(obstacle index from 0, distance - R)`` of each moving robot whose model circle
    holds ``point`` at time ``t`` (closer than ``R`` by more than the float64 tolerance)."""
    if not scenario.has_motion:
        return []
    ox, oy, vx, vy, big_r, idx = _robot_arrays(scenario)
    d = np.hypot(point[0] - (ox + vx * t), point[1] - (oy + vy * t)) - big_r
    tol = tolerances(np.float64).length
    return [(int(idx[j]), float(d[j])) for j in np.flatnonzero(d < -tol)]
