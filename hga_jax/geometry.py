"""Tangent geometry of oriented circles (docs/model.md), elementwise and array-generic.

Every function takes x and y components as separate arrays (the batch layout
that vectorises well) and broadcasts them; it runs on numpy arrays (host code,
float64: the exact solver) and on jax arrays or tracers (device code: decoding,
fitness) with the same formulas, so the GA and the exact solver share one model.

Conventions (docs/model.md): lengths in metres, angles in radians. A circle's
orientation ``sign`` is ``+1`` clockwise (CW) and ``-1`` counter-clockwise (CCW);
``sigma = -sign`` is ``+1`` for CCW. ``left(u) = (-u_y, u_x)``.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import jax.numpy as jnp
import numpy as np


def xp_of(*arrays: Any):
    """numpy if every argument is a numpy array or a Python/numpy scalar, else jax.numpy."""
    for a in arrays:
        if not isinstance(a, (np.ndarray, np.generic, float, int, bool)):
            return jnp
    return np


class Tolerances(NamedTuple):
    """Rounding tolerances of one float precision.

    length: how much closer than a radius a piece may come before it counts as a
    violation, and how far a touch point may leave the field (m).
    angle: a sweep within this of ``2*pi`` is a rounding artefact and counts as 0 (rad).
    eps: centre distance below which two circles count as coincident (m).
    """

    length: float
    angle: float
    eps: float


def tolerances(dtype: Any) -> Tolerances:
    """Tolerances for ``dtype``: float32 1e-5 m / 1e-5 rad, float64 1e-7 m / 1e-9 rad."""
    if np.dtype(dtype) == np.float64:
        return Tolerances(length=1e-7, angle=1e-9, eps=1e-9)
    return Tolerances(length=1e-5, angle=1e-5, eps=1e-6)


def turning_circle(x, y, heading, rho, sign):
    """Centre of the turning circle of pose ``(x, y, heading)`` on side ``sign``.

    ``sign = -1`` (CCW, left): ``p + rho*(-sin t, cos t)``; ``+1`` (CW, right):
    ``p + rho*(sin t, -cos t)``.
    """
    xp = xp_of(x, y, heading, rho, sign)
    return x + sign * rho * xp.sin(heading), y - sign * rho * xp.cos(heading)


def heading_on_circle(px, py, cx, cy, sign):
    """Unit direction of travel at point P of the circle centred at C with orientation ``sign``.

    From ``P = C - sigma*r*left(u)``: ``u = sigma * (P - C)`` rotated by +90 degrees
    (CCW travel turns left). Returns ``(ux, uy)``.
    """
    xp = xp_of(px, py, cx, cy, sign)
    wx, wy = px - cx, py - cy
    norm = xp.sqrt(wx * wx + wy * wy)
    norm = xp.where(norm > 0, norm, 1.0)
    sigma = -sign
    return -sigma * wy / norm, sigma * wx / norm


class Tangent(NamedTuple):
    """The directed tangent from circle 1 to circle 2 (docs/model.md).

    ux, uy: its unit direction. length: ``sqrt(d^2 - k^2)`` (m). p1x..p2y: touch
    points on circles 1 and 2. exists: False when the tangent does not exist (one
    violation); the stand-in then clamps ``k/d`` to ``+-1`` so every value stays
    finite and deterministic, and its length is the distance ``|k| - d`` between
    its touch points.
    """

    ux: Any
    uy: Any
    length: Any
    p1x: Any
    p1y: Any
    p2x: Any
    p2y: Any
    exists: Any


def tangent(c1x, c1y, r1, s1, c2x, c2y, r2, s2, fallback_ux, fallback_uy, eps):
    """Directed tangent from oriented circle 1 to oriented circle 2, without trigonometry.

    With ``D = c2 - c1``, ``d = |D|``, ``k = sigma2*r2 - sigma1*r1`` the tangent
    exists iff ``|k| <= d`` (up to ``eps``); its direction is ``D/d`` rotated by
    ``-asin(k/d)``. Coincident centres (``d < eps``) take ``fallback_u`` as the
    direction (the heading on circle 1, so that two equal circles give a zero
    tangent at the arrival point and the path continues along the circle).
    """
    xp = xp_of(c1x, c1y, r1, s1, c2x, c2y, r2, s2, fallback_ux, fallback_uy)
    dx, dy = c2x - c1x, c2y - c1y
    d = xp.sqrt(dx * dx + dy * dy)
    sig1, sig2 = -s1, -s2
    k = sig2 * r2 - sig1 * r1
    exists = xp.abs(k) <= d + eps
    coincident = d < eps
    d_safe = xp.where(coincident, 1.0, d)
    s = xp.clip(k / d_safe, -1.0, 1.0)
    c = xp.sqrt(xp.maximum(1.0 - s * s, 0.0))
    ux = xp.where(coincident, fallback_ux, (dx * c + dy * s) / d_safe)
    uy = xp.where(coincident, fallback_uy, (-dx * s + dy * c) / d_safe)
    # A missing tangent's stand-in joins its touch points, which lie |k| - d apart.
    length = xp.where(exists, xp.where(coincident, 0.0, d * c), xp.abs(k) - d)
    p1x, p1y = c1x + sig1 * r1 * uy, c1y - sig1 * r1 * ux
    p2x, p2y = c2x + sig2 * r2 * uy, c2y - sig2 * r2 * ux
    return Tangent(ux, uy, length, p1x, p1y, p2x, p2y, exists)


def sweep(ax, ay, bx, by, sign, angle_tol):
    """Arc sweep (rad, in ``[0, 2*pi)``) from radial vector A to radial vector B.

    CCW (``sign = -1``) sweeps increase the angle, CW sweeps decrease it. A sweep
    within ``angle_tol`` of ``2*pi`` counts as 0 (a rounding artefact).
    """
    xp = xp_of(ax, ay, bx, by, sign)
    delta = xp.arctan2(ax * by - ay * bx, ax * bx + ay * by)
    two_pi = 2.0 * np.pi
    sw = xp.mod(-sign * delta, two_pi)
    return xp.where(sw > two_pi - angle_tol, 0.0, sw)


def in_span(ax, ay, bx, by, vx, vy, swp, sign):
    """Whether direction V (from the arc's centre) lies within the arc A -> B.

    A and B are the radial vectors of the arc's ends, ``swp`` its sweep in
    ``[0, 2*pi)`` and ``sign`` its orientation. Cross/dot products only.
    """
    sigma = -sign
    ca = sigma * (ax * vy - ay * vx)
    cb = sigma * (vx * by - vy * bx)
    bis = vx * (ax + bx) + vy * (ay + by)
    small = (ca >= 0) & (cb >= 0) & (bis >= 0)
    outside_big = (ca < 0) & (cb < 0) & (bis > 0)
    return (swp <= np.pi) & small | (swp > np.pi) & ~outside_big


def segment_hits(p1x, p1y, p2x, p2y, qx, qy, radius, tol):
    """Full criterion: the segment comes closer than ``radius - tol`` to Q."""
    xp = xp_of(p1x, p1y, p2x, p2y, qx, qy, radius)
    vx, vy = p2x - p1x, p2y - p1y
    wx, wy = qx - p1x, qy - p1y
    vv = vx * vx + vy * vy
    t = xp.clip((wx * vx + wy * vy) / xp.where(vv > 0, vv, 1.0), 0.0, 1.0)
    ex, ey = wx - t * vx, wy - t * vy
    reach = xp.maximum(radius - tol, 0.0)
    return ex * ex + ey * ey < reach * reach


def segment_hits_paper(p1x, p1y, p2x, p2y, qx, qy, radius, tol):
    """The paper's Appendix B criterion: the segment S->T meets the circle in two
    distinct points. With ``f(t) = t^2 + 2bt + c``: ``-1 < b < 0``, ``f(-b) < 0``,
    ``f(0) >= 0`` and ``f(1) >= 0``. ``f(-b) < 0`` is judged with the tolerance
    (closest distance of the line below ``radius - tol``) so that tangent touching
    is not a crossing. A segment that starts or ends inside the circle is missed,
    as in the paper.
    """
    xp = xp_of(p1x, p1y, p2x, p2y, qx, qy, radius)
    x1, y1 = p2x - p1x, p2y - p1y
    x2, y2 = p1x - qx, p1y - qy
    a = x1 * x1 + y1 * y1
    a_safe = xp.where(a > 0, a, 1.0)
    b = (x1 * x2 + y1 * y2) / a_safe
    c = (x2 * x2 + y2 * y2 - radius * radius) / a_safe
    reach = xp.maximum(radius - tol, 0.0)
    closest_sq = x2 * x2 + y2 * y2 - b * b * a  # squared distance of the line to Q
    return (a > 0) & (b > -1) & (b < 0) & (closest_sq < reach * reach) & (c >= 0) & (
        1 + 2 * b + c >= 0
    )


def arc_hits(cx, cy, r, ax, ay, bx, by, swp, sign, qx, qy, radius, tol):
    """The arc (centre C, radius r, from point A to point B, sweep ``swp``, ``sign``)
    comes closer than ``radius - tol`` to Q.

    Its closest point to Q is the circle's point towards Q when that direction lies
    within the arc (distance ``| |Q - C| - r |``), else the nearer end. Compared in
    squares, without square roots.
    """
    xp = xp_of(cx, cy, r, ax, ay, bx, by, swp, sign, qx, qy, radius)
    vx, vy = qx - cx, qy - cy
    inside = in_span(ax - cx, ay - cy, bx - cx, by - cy, vx, vy, swp, sign)
    reach = xp.maximum(radius - tol, 0.0)
    reach2 = reach * reach
    vv = vx * vx + vy * vy
    lo, hi = r - reach, r + reach
    hit_mid = (vv < hi * hi) & ((lo < 0) | (vv > lo * lo))
    hit_a = (qx - ax) ** 2 + (qy - ay) ** 2 < reach2
    hit_b = (qx - bx) ** 2 + (qy - by) ** 2 < reach2
    return xp.where(inside, hit_mid, hit_a | hit_b)


def arc_leaves_box(cx, cy, r, ax, ay, bx, by, swp, sign, bounds, tol):
    """The arc leaves the box ``bounds = (xmin, xmax, ymin, ymax)`` by more than ``tol``."""
    xp = xp_of(cx, cy, r, ax, ay, bx, by, swp, sign)
    rax, ray, rbx, rby = ax - cx, ay - cy, bx - cx, by - cy

    def reaches(vx, vy):
        return in_span(rax, ray, rbx, rby, vx, vy, swp, sign)

    xmax = xp.where(reaches(1.0, 0.0), cx + r, xp.maximum(ax, bx))
    xmin = xp.where(reaches(-1.0, 0.0), cx - r, xp.minimum(ax, bx))
    ymax = xp.where(reaches(0.0, 1.0), cy + r, xp.maximum(ay, by))
    ymin = xp.where(reaches(0.0, -1.0), cy - r, xp.minimum(ay, by))
    return (xmin < bounds[0] - tol) | (xmax > bounds[1] + tol) | (
        ymin < bounds[2] - tol) | (ymax > bounds[3] + tol)


def segment_leaves_box(p1x, p1y, p2x, p2y, bounds, tol):
    """The segment leaves the (convex) box: one of its ends lies outside by more than ``tol``."""
    def out(x, y):
        return (x < bounds[0] - tol) | (x > bounds[1] + tol) | (y < bounds[2] - tol) | (
            y > bounds[3] + tol)

    return out(p1x, p1y) | out(p2x, p2y)
