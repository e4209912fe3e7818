"""The feasibility rules of the path model (docs/model.md, "Feasibility"), each written once.

A path is a chain of *pieces*: arcs on oriented circles and tangent segments
between them. Its violations are the sum, over its pieces, of

- **segment against obstacles**: each obstacle whose model circle (centre Q,
  radius ``R_k``) the segment comes closer to than ``R_k - tol``
  (``collision = "full"``), or that it crosses in two distinct points inside the
  segment by the paper's Appendix B criterion (``collision = "paper"``);
- **arc against obstacles** (``"full"`` only): each obstacle whose model circle the
  arc comes closer to than ``R_k - tol``, *except its own circle*: an arc on
  obstacle ``i``'s model circle is never tested against obstacle ``i`` (start and
  goal circles have no own obstacle, ``own = -1``);
- **the field**: one violation for a piece that leaves the kept field box (already
  shrunk by the robot radius; infinite when the field is not kept) by more than
  ``tol``, whatever the number of sides it crosses;
- **a missing tangent**: one violation (its stand-in segment is judged as well).

So tangent touching (distance exactly ``R_k``) is never a violation. ``tol`` is the
length tolerance of the precision (:func:`hga_jax.model.geometry.tolerances`).

Array conventions. Every function is elementwise and array-generic: on numpy
arrays (host code, float64) and on jax arrays or tracers (the device decoder),
with the same formulas. A piece is given by tuples of arrays of one shape ``P``
(any, broadcastable): ``ends = (p1x, p1y, p2x, p2y)``, ``circle = (cx, cy, r,
sign)`` and ``arc = (ax, ay, bx, by, sweep)`` (arrival and departure points, sweep
in rad, ``sign`` +1 CW / -1 CCW). Obstacles are an :class:`Obstacles` whose arrays
have shape ``(n,) + (1,) * len(P)``; per-pair results have shape ``(n,) + P`` (the
obstacle axis first, the layout the decoder vectorises well), and counts sum that
axis away (shape ``P``). Units: metres.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from .geometry import arc_frame, in_span, xp_of

COLLISIONS = ("full", "paper")


class Obstacles(NamedTuple):
    """Model circles of the obstacles, shaped ``(n,) + (1,) * ndim`` (see module doc).

    x, y: centres (m). r: model radii ``R_k`` (m). index: obstacle index ``k``
    (int32), compared with a piece's ``own`` obstacle.
    """

    x: Any
    y: Any
    r: Any
    index: Any


def obstacles(centres, model_radii, ndim: int = 0, index=None) -> Obstacles:
    """:class:`Obstacles` from ``centres`` (n, 2) and ``model_radii`` (n,), with ``ndim``
    trailing axes of length 1 for pieces of ``ndim`` dimensions. ``index`` (n,):
    the obstacles' indices when these are a subset (default ``0..n-1``)."""
    n = centres.shape[0]
    shape = (n,) + (1,) * ndim
    index = np.arange(n, dtype=np.int32) if index is None else np.asarray(index, np.int32)
    return Obstacles(centres[:, 0].reshape(shape), centres[:, 1].reshape(shape),
                     model_radii.reshape(shape), index.reshape(shape))


def arcs_meet_obstacles(collision: str) -> bool:
    """Whether arcs are tested against obstacles: in ``"full"`` mode, not in ``"paper"``."""
    return collision == "full"


def count(pairs) -> Any:
    """Number of true pairs per piece: ``pairs`` (n,) + P summed over its obstacle axis (int32)."""
    return xp_of(pairs).sum(pairs, axis=0, dtype=np.int32)


# The clearance tests of one piece against one circle (broadcasting).

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
    always tested, so a direction at an end that :func:`~hga_jax.model.geometry.in_span`
    rounds either way gives the same answer. Compared in squares.
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


# The rules, piece by piece (see module doc).

def segment_obstacles(ends, obs: Obstacles, tol, collision: str):
    """(n,) + P: which obstacles the segments violate, by the criterion of ``collision``."""
    hits = segment_hits if collision == "full" else segment_hits_paper
    return hits(*ends, obs.x, obs.y, obs.r, tol)


def arc_obstacles(circle, own, arc, obs: Obstacles, tol, collision: str):
    """(n,) + P: which obstacles the arcs violate; never an arc's ``own`` obstacle
    (P-shaped obstacle index of its circle, -1 for start and goal circles), and none
    in ``"paper"`` mode."""
    (cx, cy, r, sign), (ax, ay, bx, by, swp) = circle, arc
    hits = arc_hits(cx, cy, r, ax, ay, bx, by, swp, sign, obs.x, obs.y, obs.r, tol)
    hits = hits & (obs.index != own)
    return hits if arcs_meet_obstacles(collision) else hits & False


REACH_MARGIN = 1e-3
"""m: an obstacle whose model circle stays farther than this from a circle is never met
by an arc on it (:func:`reaching`); the margin covers rounding."""


def reaching(cx, cy, r, centres, model_radii, margin: float = REACH_MARGIN) -> np.ndarray:
    """(k, n) bool (numpy): which obstacles' model circles come within ``margin`` (m) of
    each of ``k`` circles, ``| |Q - C| - r | <= R_j + margin``. No arc on a circle comes
    closer than ``R_j`` to the others: the one prefilter of host code that judges many
    arcs."""
    d = np.hypot(np.asarray(cx)[:, None] - centres[:, 0], np.asarray(cy)[:, None] - centres[:, 1])
    return np.abs(d - np.asarray(r)[:, None]) <= model_radii + margin


def arc_candidates(circle, own: int, centres, model_radii,
                   margin: float = REACH_MARGIN) -> np.ndarray:
    """Indices of the obstacles that some arc on one ``circle`` could violate (numpy):
    every obstacle but ``own`` that :func:`reaching` it."""
    cx, cy, r, _ = circle
    near = reaching(np.atleast_1d(cx), np.atleast_1d(cy), np.atleast_1d(r), centres,
                    model_radii, margin)[0]
    return np.flatnonzero(near & (np.arange(centres.shape[0]) != own))


def arcs_clear(circles, c, arc, centres, model_radii, bounds, tol,
               collision: str = "full") -> np.ndarray:
    """Which arcs have no violation by :func:`arc_violations`' rule (numpy, host code):
    arcs ``arc = (ax, ay, bx, by, sweep)`` on circles ``c`` (indices into ``circles =
    (x, y, r, sign, own)``), in the field and, under ``"full"``, clear of every obstacle
    but their circle's own. Each arc is tested only against the obstacles that reach
    its circle (:func:`reaching`), which gives the same answer."""
    x, y, r, sg, own = (np.asarray(v)[c] for v in circles)
    ok = ~arc_leaves_field((x, y, r, sg), arc, bounds, tol)
    centres, model_radii = np.asarray(centres), np.asarray(model_radii)
    if not (arcs_meet_obstacles(collision) and centres.shape[0]) or not np.size(c):
        return ok
    used = np.unique(c)
    near = reaching(*(np.asarray(v)[used] for v in circles[:3]), centres, model_radii)
    i, j = np.nonzero(near[np.searchsorted(used, c)])
    ax, ay, bx, by, swp = (np.asarray(v)[i] for v in arc)
    hit = arc_hits(x[i], y[i], r[i], ax, ay, bx, by, swp, sg[i], centres[j, 0], centres[j, 1],
                   model_radii[j], tol) & (own[i] != j)
    ok[i[hit]] = False
    return ok


def segment_leaves_field(ends, bounds, tol):
    """P: the segment leaves the (convex) box ``bounds = (xmin, xmax, ymin, ymax)``:
    one of its ends lies outside by more than ``tol``."""
    p1x, p1y, p2x, p2y = ends

    def out(x, y):
        return (x < bounds[0] - tol) | (x > bounds[1] + tol) | (y < bounds[2] - tol) | (
            y > bounds[3] + tol)

    return out(p1x, p1y) | out(p2x, p2y)


def arc_leaves_field(circle, arc, bounds, tol):
    """P: the arc leaves the box ``bounds = (xmin, xmax, ymin, ymax)`` by more than ``tol``
    (its extreme points: the circle's at the axis directions within the arc, else its ends)."""
    (cx, cy, r, sign), (ax, ay, bx, by, swp) = circle, arc
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


def missing_tangent(exists):
    """P: one violation where the tangent does not exist."""
    return xp_of(exists).logical_not(exists)


def segment_violations(ends, exists, obs: Obstacles, bounds, tol, collision: str):
    """P (int32): violations of tangent segments: obstacles, the field, a missing tangent."""
    v = (missing_tangent(exists).astype(np.int32)
         + segment_leaves_field(ends, bounds, tol).astype(np.int32))
    if obs.x.shape[0]:
        v = v + count(segment_obstacles(ends, obs, tol, collision))
    return v


def arc_violations(circle, own, arc, obs: Obstacles, bounds, tol, collision: str):
    """P (int32): violations of arcs: obstacles other than their ``own`` (``"full"``
    mode only), the field."""
    v = arc_leaves_field(circle, arc, bounds, tol).astype(np.int32)
    if arcs_meet_obstacles(collision) and obs.x.shape[0]:
        v = v + count(arc_obstacles(circle, own, arc, obs, tol, collision))
    return v
