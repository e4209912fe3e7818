"""Tangent geometry of oriented circles (docs/model.md), elementwise and array-generic.

Every function takes x and y components as separate arrays (the batch layout
that vectorises well) and broadcasts them; it runs on numpy arrays (host code,
float64: the exact solver) and on jax arrays or tracers (device code: decoding,
fitness) with the same formulas, so the GA and the exact solver share one model.
The clearance and field tests built on :func:`arc_frame` and :func:`in_span` are
the feasibility rules of :mod:`hga_jax.model.collision`.

Conventions (docs/model.md): lengths in metres, angles in radians. A circle's
orientation ``sign`` is ``+1`` clockwise (CW) and ``-1`` counter-clockwise (CCW);
``sigma = -sign`` is ``+1`` for CCW. ``left(u) = (-u_y, u_x)``.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np


def xp_of(*arrays: Any):
    """numpy if every argument is a numpy array or a Python/numpy scalar, else jax.numpy."""
    for a in arrays:
        if not isinstance(a, (np.ndarray, np.generic, float, int, bool)):
            import jax.numpy as jnp  # imported only where jax arrays already are

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
    (:mod:`hga_jax.model.collision`) also test the end points, so nothing depends on that.
    """
    xp = xp_of(vx, vy, *frame)
    mx, my, m_cos = frame
    return vx * mx + vy * my >= m_cos * xp.sqrt(vx * vx + vy * vy)
