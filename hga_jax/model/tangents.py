"""The tangent table of a scenario: every directed tangent between its oriented circles, judged once.

Oriented circles are numbered by the one rule of :mod:`hga_jax.model.circle_ids`
(decoder, exact solvers, turn tables): ``0`` start CCW (``-1``), ``1`` start CW
(``+1``), ``2`` goal CCW, ``3`` goal CW, then ``4 + 2i`` obstacle ``i`` CW and
``5 + 2i`` obstacle ``i`` CCW; ``C = 2n + 4`` circles.

A tangent depends only on its two circles, so its touch points, its length and its
violations (the segment against every obstacle, by the full or the paper criterion;
the field; a missing tangent) are computed here once per scenario, on the host, with
the functions of :mod:`hga_jax.model.geometry` and the rules of
:mod:`hga_jax.model.collision` in the scenario's float dtype. Decoding a
leg is then a lookup; only the arcs depend on the chromosome. Circles with coincident
centres (a start and a goal circle on the same turning circle) have no fixed
tangent: the decoder puts it on the ray through the point where the path arrived
(so equal circles of one orientation go on along the circle from there), and their
entry counts only a missing tangent (other radii or orientations), no segment.

Units: metres. Host code (numpy), called by :meth:`hga_jax.model.scenario.Scenario.arrays`;
the same functions build a frame's table on the device from jax arrays (:mod:`hga_jax.loop`).
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import collision as col
from hga_jax.model import geometry as g


class TangentTable(NamedTuple):
    """Per ordered pair ``(a, b)`` of oriented circles, arrays shaped ``(C, C)``.

    circles: ``(C, 4)`` ``x, y, r, sign``. obstacle: ``(C,)`` obstacle index, -1 for
    start and goal circles. p1x, p1y, p2x, p2y: touch points on ``a`` and ``b``
    (the stand-in's for a missing tangent). length: ``|P2 - P1|`` (m). exists: the
    tangent exists. coincident: the two centres coincide. violations_full,
    violations_paper: the tangent's violations under each criterion (segment
    against every obstacle, field exit, missing tangent).
    """

    circles: Any
    obstacle: Any
    p1x: Any
    p1y: Any
    p2x: Any
    p2y: Any
    length: Any
    exists: Any
    coincident: Any
    violations_full: Any
    violations_paper: Any


def oriented_circles(start, goal, centres, model_radii, rho) -> tuple[np.ndarray, ...]:
    """``(x, y, r, sign, obstacle)`` of the ``C = 2n + 4`` oriented circles (numpy, or
    jax.numpy for jax arrays: the per-frame arrays of :mod:`hga_jax.loop`)."""
    xp = g.xp_of(start, goal, centres, model_radii, rho)
    dt = centres.dtype
    lr = xp.asarray(np.array([-1.0, 1.0], dt))
    n = centres.shape[0]
    sx, sy = g.turning_circle(start[0], start[1], start[2], rho, lr)
    gx, gy = g.turning_circle(goal[0], goal[1], goal[2], rho, lr)
    x = xp.concatenate([sx, gx, xp.repeat(centres[:, 0], 2)]).astype(dt)
    y = xp.concatenate([sy, gy, xp.repeat(centres[:, 1], 2)]).astype(dt)
    r = xp.concatenate([xp.full(4, rho, dt), xp.repeat(model_radii, 2)]).astype(dt)
    sign = xp.concatenate([lr, lr, xp.asarray(np.tile(np.array([1.0, -1.0], dt), n))])
    obstacle = np.concatenate([np.full(4, -1), np.repeat(np.arange(n), 2)]).astype(np.int32)
    return x, y, r, sign, obstacle


def build(start, goal, centres, model_radii, rho, bounds) -> TangentTable:
    """The table of a scenario given as numpy arrays of one float dtype (see module doc)."""
    return table(oriented_circles(start, goal, centres, model_radii, rho), centres,
                 model_radii, bounds)


def table(circles, centres, model_radii, bounds) -> TangentTable:
    """The table over any oriented circles ``(x, y, r, sign, obstacle)`` (numpy, the
    dtype of ``centres``): the scenario's :func:`oriented_circles`, or those and the
    circles a car model adds after them, numbered on."""
    x, y, r, sign, obstacle = circles
    xp = g.xp_of(x, y, r, sign, centres, model_radii, bounds)
    dt = centres.dtype
    tol = g.tolerances(dt)
    c = x.size
    a, b = (m.ravel() for m in np.meshgrid(np.arange(c), np.arange(c), indexing="ij"))
    one, zero = xp.ones(a.size, dt), xp.zeros(a.size, dt)
    t = g.tangent(x[a], y[a], r[a], sign[a], x[b], y[b], r[b], sign[b], one, zero, tol.eps)
    dx, dy = x[b] - x[a], y[b] - y[a]
    coincident = xp.sqrt(dx * dx + dy * dy) < tol.eps
    ends, obstacles = (t.p1x, t.p1y, t.p2x, t.p2y), col.obstacles(centres, model_radii, ndim=1)
    missing = col.missing_tangent(t.exists).astype(np.int32)

    def judged(collision):  # coincident: no segment, only a missing tangent (module doc)
        v = col.segment_violations(ends, t.exists, obstacles, bounds, tol.length, collision)
        return xp.where(coincident, missing, v).astype(np.int32)

    def square(v):
        return xp.asarray(v).reshape(c, c)

    return TangentTable(
        circles=xp.stack([x, y, r, sign], axis=1), obstacle=obstacle,
        p1x=square(t.p1x), p1y=square(t.p1y), p2x=square(t.p2x), p2y=square(t.p2y),
        length=square(t.length), exists=square(t.exists), coincident=square(coincident),
        violations_full=square(judged("full")), violations_paper=square(judged("paper")))
