"""The free circles that a car's shortest path may turn on, pinned by two contacts.

Under free turns (:mod:`hga_jax.model.cars.free_turns.turns`) a path may turn on any circle of
radius rho in free space. A free arc with a tangent or a change of circle on each
side is a rope over a pulley: while its circle can move, moving it shortens the
path. So at an optimum every free circle is pinned by two contacts, and those are
the only free circles needed:

- tangent externally to two *anchors* among the start circles, the goal circles
  and the obstacles' model circles. Next to a pose circle the path changes circle
  at the contact point (a junction: the free circle turns the other way); next to
  an obstacle it may turn either way, the obstacle holding the circle;
- when the field is kept, tangent to a wall of the field shrunk by the robot
  radius and one anchor, or to two walls.

Host code (numpy, float64); metres.
"""
from __future__ import annotations

import math

import numpy as np

from hga_jax.model import circle_ids as ids
from hga_jax.model import geometry as g

from hga_jax.model.scenario import Scenario

TOL = g.tolerances(np.float64)


def pair_centres(ax, ay, ra, bx, by, rb):
    """Centres at distance ``ra`` from A and ``rb`` from B (circle intersections),
    both solutions (one point, twice, where the two circles touch to within
    ``TOL.eps``); rows without one are dropped. Returns ``(x, y, i)`` with ``i``
    the index of the pair each centre came from."""
    dx, dy = bx - ax, by - ay
    d = np.hypot(dx, dy)
    # Circles within TOL.eps of touching meet in one point, whichever way rounding
    # went: the square root would blow rounding up (1e-16 to 1e-8 m), and a free circle
    # that exists or not, or a contact point 1e-8 m behind a pose (a sweep of 0 in
    # float32, a whole circle in float64), would make the precisions disagree.
    ok = (d > TOL.eps) & (d <= ra + rb + TOL.eps) & (d >= np.abs(ra - rb) - TOL.eps)
    d = np.where(ok, d, 1.0)
    along = (ra * ra - rb * rb + d * d) / (2.0 * d)
    touching = (d >= ra + rb - TOL.eps) | (d <= np.abs(ra - rb) + TOL.eps)
    h = np.where(touching, 0.0, np.sqrt(np.maximum(ra * ra - along * along, 0.0)))
    mx, my = ax + along * dx / d, ay + along * dy / d
    out = [(mx + s * h * -dy / d, my + s * h * dx / d) for s in (1.0, -1.0)]
    idx = np.flatnonzero(ok)
    xs = np.concatenate([out[0][0][idx], out[1][0][idx]])
    ys = np.concatenate([out[0][1][idx], out[1][1][idx]])
    return xs, ys, np.concatenate([idx, idx])


def free_circles(sc: Scenario, both: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pinned free circles of ``sc`` (module doc): ``(x, y, sign)`` of each oriented
    free circle, radius ``rho``. An orientation is left out where a pose-circle anchor
    forbids it (the junction turns the other way), and so is a circle that lies wholly
    inside an obstacle's model circle. ``both``: every circle in both orientations (a
    car that reverses may meet a pose circle at a cusp, turning the same way)."""
    rho = float(sc.min_turn_radius)
    x, y, r, sign, _ = sc.circles(np.float64)
    # Anchors: the 4 pose circles (with the sign a free circle needs to join them) and
    # the n model circles (either sign: 0); a centre lies ``r + rho`` from its anchors.
    poses, each = slice(0, ids.POSES), ids.one_per_obstacle
    ax, ay = np.concatenate([x[poses], each(x)]), np.concatenate([y[poses], each(y)])
    ar = np.concatenate([r[poses], each(r)]) + rho
    need = np.concatenate([np.zeros(ids.POSES) if both else -sign[poses], np.zeros(sc.n)])
    i, j = np.triu_indices(ax.size, 1)
    fx, fy, k = pair_centres(ax[i], ay[i], ar[i], ax[j], ay[j], ar[j])
    ni, nj = need[i][k], need[j][k]
    ok = (ni == 0) | (nj == 0) | (ni == nj)
    cx, cy, cs = [fx[ok]], [fy[ok]], [np.where(ni != 0, ni, nj)[ok]]
    b = sc.bounds
    if np.isfinite(b[0]):
        walls = ((0, b[0] + rho), (0, b[1] - rho), (1, b[2] + rho), (1, b[3] - rho))
        for axis, at in walls:  # a wall and an anchor: on the line x = at (axis 0) or y = at
            off = (ax if axis == 0 else ay) - at
            h = np.sqrt(np.maximum(ar * ar - off * off, 0.0))
            hit = np.abs(off) <= ar
            for s in (1.0, -1.0):
                along = (ay if axis == 0 else ax) + s * h
                cx.append(np.full(int(hit.sum()), at) if axis == 0 else along[hit])
                cy.append(along[hit] if axis == 0 else np.full(int(hit.sum()), at))
                cs.append(need[hit])
        cx.append(np.array([walls[0][1], walls[0][1], walls[1][1], walls[1][1]]))  # corners
        cy.append(np.array([walls[2][1], walls[3][1], walls[2][1], walls[3][1]]))
        cs.append(np.zeros(4))
    cx, cy, cs = np.concatenate(cx), np.concatenate(cy), np.concatenate(cs)
    if sc.n:
        dist = np.hypot(cx[:, None] - sc.centres[:, 0], cy[:, None] - sc.centres[:, 1])
        inside = np.any(dist + rho < sc.model_radii - TOL.length, axis=1)
        cx, cy, cs = cx[~inside], cy[~inside], cs[~inside]
    either = cs == 0
    return (np.concatenate([cx, cx[either]]), np.concatenate([cy, cy[either]]),
            np.concatenate([np.where(either, 1.0, cs), -np.ones(int(either.sum()))]))


def reach(sc: Scenario, x, y, r):
    """Lower bounds (m) on the way from the start point to a circle and from it to the
    goal point: the distances to its disc."""
    return (np.maximum(np.hypot(x - sc.start[0], y - sc.start[1]) - r, 0.0),
            np.maximum(np.hypot(x - sc.goal[0], y - sc.goal[1]) - r, 0.0))


def circles(sc: Scenario, bound: float = math.inf, both: bool = False) -> tuple[np.ndarray, ...]:
    """``(x, y, r, sign, own)`` of every circle of the free-turn graph: the scenario's
    ``2n + 4`` (numbered as in :mod:`hga_jax.model.tangents`), then the free circles
    (``own`` -1: no exemption) that a path shorter than ``bound`` (m) can reach: the
    distance from the start point to the circle's disc and from it to the goal point
    add up to ``bound`` or less. ``both``: :func:`free_circles`' ``both``."""
    x, y, r, sign, own = sc.circles(np.float64)
    fx, fy, fs = free_circles(sc, both)
    rho = float(sc.min_turn_radius)
    if math.isfinite(bound):
        to, back = reach(sc, fx, fy, rho)
        near = to + back <= bound
        fx, fy, fs = fx[near], fy[near], fs[near]
    return (np.concatenate([x, fx]), np.concatenate([y, fy]),
            np.concatenate([r, np.full(fx.size, rho)]), np.concatenate([sign, fs]),
            np.concatenate([own, np.full(fx.size, -1)]).astype(np.int32))
