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
    violation, how far a point may leave the field, and how far inside a model
    circle a segment's end may lie and still count as outside it (m).
    angle: a sweep within this of ``2*pi`` is a rounding artefact and counts as 0 (rad).
    eps: centre distance below which two circles count as coincident, and gap
    (``d - |k|``, either sign) below which two circles count as touching (m).
    """

    length: float
    angle: float
    eps: float


def tolerances(dtype: Any) -> Tolerances:
    """Tolerances for ``dtype``: float32 1e-5 m / 1e-5 rad / 1e-6 m, float64 1e-7 m / 1e-9 rad / 1e-9 m."""
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
    ``-asin(k/d)``, i.e. ``u = (D*c + left(D)*(-s)) / d`` with ``s = k/d`` and
    ``c = sqrt(d^2 - k^2)/d``.

    Touching circles (``|d - |k|| <= eps``): the tangent is the single contact
    point, so ``c = 0`` exactly. Computing ``c`` from a gap of a few rounding
    units would put the touch points ``sqrt(rounding)`` off (about 1e-8 rad in
    float64, 1e-3 rad in float32), on either side of the contact point, and a
    goal or departure point there would then be reached by a spurious full loop.
    Coincident centres (``d < eps``) take ``fallback_u`` as the direction (the
    heading on circle 1, so that two equal circles give a zero tangent at the
    arrival point and the path continues along the circle).
    """
    xp = xp_of(c1x, c1y, r1, s1, c2x, c2y, r2, s2, fallback_ux, fallback_uy)
    dx, dy = c2x - c1x, c2y - c1y
    d = xp.sqrt(dx * dx + dy * dy)
    sig1, sig2 = -s1, -s2
    k = sig2 * r2 - sig1 * r1
    gap = d - xp.abs(k)
    exists = gap >= -eps
    touching = xp.abs(gap) <= eps
    coincident = d < eps
    d_safe = xp.where(coincident, 1.0, d)
    s = xp.clip(k / d_safe, -1.0, 1.0)
    c = xp.where(touching, 0.0, xp.sqrt(xp.maximum(gap * (d + xp.abs(k)), 0.0)) / d_safe)
    ux = xp.where(coincident, fallback_ux, (dx * c + dy * s) / d_safe)
    uy = xp.where(coincident, fallback_uy, (-dx * s + dy * c) / d_safe)
    # A missing tangent's stand-in joins its touch points, which lie |k| - d apart.
    length = xp.where(exists, xp.where(coincident, 0.0, d * c), -gap)
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


def arc_frame(ax, ay, bx, by, swp, sign):
    """The middle direction of an arc and the cosine of its half sweep, for :func:`in_span`.

    A and B are the radial vectors of the arc's ends (equal length), ``swp`` its
    sweep in ``[0, 2*pi)`` and ``sign`` its orientation. The middle direction is
    ``M = e*(A + B) + sigma*right(B - A)`` with ``e = +1`` for sweeps up to pi and
    ``-1`` beyond: both terms point at the arc's middle, and their lengths are
    ``2r|cos(swp/2)|`` and ``2r*sin(swp/2)``, so ``M`` never vanishes, not even for a
    half circle (where ``A + B`` is rounding noise of arbitrary sign) or a zero
    sweep (where ``B - A`` is). ``cos(swp/2) = e*|A + B| / (|A| + |B|)`` needs no
    trigonometry and is continuous through pi. Returns ``(mx, my, m_cos)`` with
    ``m_cos = |M| * cos(swp/2)``.
    """
    xp = xp_of(ax, ay, bx, by, swp, sign)
    sigma = -sign
    e = xp.where(swp <= np.pi, 1.0, -1.0)
    sx, sy = ax + bx, ay + by
    mx = e * sx + sigma * (by - ay)
    my = e * sy - sigma * (bx - ax)
    norm = xp.sqrt(ax * ax + ay * ay) + xp.sqrt(bx * bx + by * by)
    cos_half = e * xp.sqrt(sx * sx + sy * sy) / xp.where(norm > 0, norm, 1.0)
    return mx, my, xp.sqrt(mx * mx + my * my) * cos_half


def in_span(frame, vx, vy):
    """Whether direction V (from the arc's centre) lies within the arc.

    ``frame`` is :func:`arc_frame` of the arc: V is within it iff its angle to the
    middle direction M is at most half the sweep, ``V.M >= |V| |M| cos(swp/2)``.
    Directions within rounding of the arc's ends may go either way; the callers
    also test the end points, so nothing depends on that.
    """
    xp = xp_of(vx, vy, *frame)
    mx, my, m_cos = frame
    return vx * mx + vy * my >= m_cos * xp.sqrt(vx * vx + vy * vy)


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
    distinct points. With ``f(t) = t^2 + 2bt + c`` (``f(t) < 0`` inside the circle):
    ``-1 < b < 0``, ``f(-b) < 0``, ``f(0) >= 0`` and ``f(1) >= 0``.

    The same tolerance convention as the full test (:func:`segment_hits`): a point
    is inside only when closer than ``radius - tol``. So ``f(-b) < 0`` asks the
    line's closest distance to be below ``radius - tol`` (tangent touching is not a
    crossing), and ``f(0) >= 0``, ``f(1) >= 0`` ask the ends not to be inside by
    more than ``tol`` (an end on the circle, such as a touch point on a
    neighbouring circle, counts as outside, whatever the rounding). A segment that
    starts or ends deeper inside is missed, as in the paper.
    """
    xp = xp_of(p1x, p1y, p2x, p2y, qx, qy, radius)
    x1, y1 = p2x - p1x, p2y - p1y
    x2, y2 = p1x - qx, p1y - qy
    a = x1 * x1 + y1 * y1
    a_safe = xp.where(a > 0, a, 1.0)
    b = (x1 * x2 + y1 * y2) / a_safe
    reach = xp.maximum(radius - tol, 0.0)
    reach2 = reach * reach
    start_sq = x2 * x2 + y2 * y2  # squared distances of S, T and the line to Q
    end_sq = (p2x - qx) ** 2 + (p2y - qy) ** 2
    closest_sq = start_sq - b * b * a
    return (a > 0) & (b > -1) & (b < 0) & (closest_sq < reach2) & (start_sq >= reach2) & (
        end_sq >= reach2)


def arc_hits(cx, cy, r, ax, ay, bx, by, swp, sign, qx, qy, radius, tol):
    """The arc (centre C, radius r, from point A to point B, sweep ``swp``, ``sign``)
    comes closer than ``radius - tol`` to Q.

    Its closest point to Q is the circle's point towards Q when that direction lies
    within the arc (distance ``| |Q - C| - r |``), else the nearer end; both ends are
    always tested, so a direction at an end that :func:`in_span` rounds either way
    gives the same answer. Compared in squares.
    """
    xp = xp_of(cx, cy, r, ax, ay, bx, by, swp, sign, qx, qy, radius)
    frame = arc_frame(ax - cx, ay - cy, bx - cx, by - cy, swp, sign)
    vx, vy = qx - cx, qy - cy
    reach = xp.maximum(radius - tol, 0.0)
    reach2 = reach * reach
    vv = vx * vx + vy * vy
    lo, hi = r - reach, r + reach
    hit_mid = (vv < hi * hi) & ((lo < 0) | (vv > lo * lo)) & in_span(frame, vx, vy)
    hit_a = (qx - ax) ** 2 + (qy - ay) ** 2 < reach2
    hit_b = (qx - bx) ** 2 + (qy - by) ** 2 < reach2
    return hit_mid | hit_a | hit_b


def arc_leaves_box(cx, cy, r, ax, ay, bx, by, swp, sign, bounds, tol):
    """The arc leaves the box ``bounds = (xmin, xmax, ymin, ymax)`` by more than ``tol``."""
    xp = xp_of(cx, cy, r, ax, ay, bx, by, swp, sign)
    frame = arc_frame(ax - cx, ay - cy, bx - cx, by - cy, swp, sign)

    def reaches(vx, vy):
        return in_span(frame, vx, vy)

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
