"""The path model in plain Python: one chromosome at a time, floats and ``math`` only.

This is the decoder a DEAP user writes from the model's definition (docs/model.md)
for the fitness of the paper's GA (:mod:`hga_jax.peers.deap_ga`). It shares no
code with hga-jax's decoder: it takes the scenario's numbers (robot, poses, obstacles,
field) and nothing else, and works with angles (``atan2``, ``asin``) where hga-jax
works with cross products and a precomputed tangent table.

- Oriented circles: the start and goal turning circles (radius ``rho``, centre
  ``p + rho * (sin t, -cos t)`` for CW ``+1``, ``p + rho * (-sin t, cos t)`` for CCW
  ``-1``) and the obstacles' model circles ``R_i = max(rho, r_i + r)``.
- A leg from ``(c1, r1, s1)`` to ``(c2, r2, s2)``: with ``sigma = -s``,
  ``k = sigma2 r2 - sigma1 r1`` and ``d = |c2 - c1|``, the tangent leaves in
  direction ``atan2(D) - asin(k / d)``, is ``sqrt(d^2 - k^2)`` long and touches
  circle ``j`` at ``c_j - sigma_j r_j left(u)``. It is missing when ``|k| > d`` (one
  violation; ``k / d`` is clamped to +-1 for a stand-in whose length is the distance
  of its touch points); circles whose gap ``d - |k|`` is within ``EPS`` touch (the
  tangent is their contact point). Coincident centres: the tangent's direction is
  the direction of travel at the point where the path arrived; its segment is
  not tested.
- Arcs run in the circle's direction from the arrival point to the departure
  point (the goal arc to the goal point); a sweep within ``ANGLE`` of a full turn
  counts as 0.
- Violations (``collision="full"``): a segment closer than ``R_j - LENGTH`` to any
  obstacle's centre, an arc (not its own circle's obstacle) likewise, each
  missing tangent, each piece leaving the kept field (shrunk by the robot
  radius) by more than ``LENGTH``. ``collision="paper"``: segments by the paper's
  Appendix B test (two distinct crossings inside the segment, ends on the circle
  outside it), arcs not tested against obstacles; missing tangents and the field
  count as in "full".
- Fitness ``10000 / (length + delta * violations + 1)``, ``delta = 2 pi R`` with the
  largest model radius (``rho`` without obstacles).

Tolerances are hga-jax's float64 ones (1e-7 m, 1e-9 rad, 1e-9 m), so the two
decoders give the same length and violations (tests/test_baselines.py).

A chromosome here is hga-jax's internal form: ``perm`` the obstacle indices from 0
in upper-module order, ``labels`` the ``n + 2`` labels (start, one per position,
goal). Metres and radians.
"""
from __future__ import annotations

import math
from typing import Any, Sequence

LENGTH = 1e-7  # m: how much closer than a radius a piece may come
ANGLE = 1e-9  # rad: a sweep this close to a full turn is rounding
EPS = 1e-9  # m: coincident centres, touching circles
TWO_PI = 2.0 * math.pi
FITNESS_CONST = 10000.0


class PythonDecoder:
    """The model of one scenario, decoded one chromosome at a time.

    Built from plain numbers (:meth:`from_scenario` reads them off an hga-jax
    ``Scenario``). Tangent legs depend on their two circles only, so each one is
    computed on first use and kept (a dict per decoder), as a careful Python
    user would; arcs are computed for every chromosome.
    """

    def __init__(self, robot_radius: float, rho: float, start: Sequence[float],
                 goal: Sequence[float], centres: Sequence[Sequence[float]],
                 radii: Sequence[float], field: Sequence[float] | None = None,
                 collision: str = "full"):
        if collision not in ("full", "paper"):
            raise ValueError(f"collision: must be full or paper, got {collision!r}")
        self.rho = float(rho)
        self.start = tuple(float(v) for v in start)
        self.goal = tuple(float(v) for v in goal)
        self.obstacles = [(float(x), float(y), max(self.rho, float(q) + float(robot_radius)))
                          for (x, y), q in zip(centres, radii)]
        r = float(robot_radius)
        self.box = None if field is None else (field[0] + r, field[1] - r, field[2] + r,
                                                field[3] - r)
        self.full = collision == "full"
        biggest = max([self.rho] + [big for _, _, big in self.obstacles])
        self.delta = TWO_PI * biggest
        self._legs: dict[tuple, tuple] = {}

    @classmethod
    def from_scenario(cls, sc: Any, collision: str = "full") -> "PythonDecoder":
        """The decoder of an hga-jax ``Scenario`` (only its numbers are used)."""
        f = sc.field
        field = (f.xmin, f.xmax, f.ymin, f.ymax) if f is not None and f.keep_inside else None
        return cls(sc.robot_radius, sc.min_turn_radius, sc.start, sc.goal,
                   [tuple(c) for c in sc.centres.tolist()], sc.radii.tolist(), field, collision)

    # -- circles ---------------------------------------------------------------------

    def _turning_circle(self, pose: tuple[float, float, float], sign: int) -> tuple:
        x, y, t = pose
        return (x + sign * self.rho * math.sin(t), y - sign * self.rho * math.cos(t), self.rho,
                sign, -1)

    def circles(self, perm: Sequence[int], labels: Sequence[int]) -> list[tuple]:
        """The path's oriented circles ``(x, y, radius, sign, obstacle index or -1)``."""
        out = [self._turning_circle(self.start, int(labels[0]))]
        for pos, i in enumerate(perm):
            s = int(labels[pos + 1])
            if s != 0:
                x, y, big = self.obstacles[int(i)]
                out.append((x, y, big, s, int(i)))
        out.append(self._turning_circle(self.goal, int(labels[-1])))
        return out

    # -- pieces ----------------------------------------------------------------------

    def _segment_violations(self, p1: tuple, p2: tuple) -> int:
        """Obstacles the segment P1-P2 violates, plus 1 if it leaves the kept field."""
        (x1, y1), (x2, y2) = p1, p2
        vx, vy = x2 - x1, y2 - y1
        vv = vx * vx + vy * vy
        hits = 0
        for qx, qy, big in self.obstacles:
            reach = max(big - LENGTH, 0.0)
            reach2 = reach * reach
            wx, wy = qx - x1, qy - y1
            if self.full:
                t = (wx * vx + wy * vy) / vv if vv > 0 else 0.0
                t = min(max(t, 0.0), 1.0)
                ex, ey = wx - t * vx, wy - t * vy
                hits += ex * ex + ey * ey < reach2
            elif vv > 0:
                # Appendix B: the closest point of the line lies strictly inside the
                # segment and inside the circle, and neither end is inside.
                t = (wx * vx + wy * vy) / vv
                start2 = wx * wx + wy * wy
                end2 = (qx - x2) ** 2 + (qy - y2) ** 2
                closest2 = start2 - t * t * vv
                hits += 0 < t < 1 and closest2 < reach2 and start2 >= reach2 and end2 >= reach2
        return hits + (self._outside(x1, y1) or self._outside(x2, y2))

    def _outside(self, x: float, y: float) -> bool:
        b = self.box
        return b is not None and (x < b[0] - LENGTH or x > b[1] + LENGTH or y < b[2] - LENGTH
                                  or y > b[3] + LENGTH)

    def _leg(self, c1: tuple, c2: tuple) -> tuple:
        """Tangent from circle 1 to circle 2 with distinct centres:
        ``(p1, p2, length, violations of its segment, missing)``, kept per pair."""
        key = (c1, c2)
        leg = self._legs.get(key)
        if leg is None:
            x1, y1, r1, s1, _ = c1
            x2, y2, r2, s2, _ = c2
            dx, dy = x2 - x1, y2 - y1
            d = math.hypot(dx, dy)
            sig1, sig2 = -s1, -s2
            k = sig2 * r2 - sig1 * r1
            gap = d - abs(k)
            missing = gap < -EPS
            if abs(gap) <= EPS or missing:  # touching, or the stand-in of a missing one
                theta = math.atan2(dy, dx) - math.copysign(math.pi / 2, k)
            else:
                theta = math.atan2(dy, dx) - math.asin(k / d)
            ux, uy = math.cos(theta), math.sin(theta)
            # P_j = c_j - sigma_j r_j left(u), left(u) = (-uy, ux)
            p1 = (x1 + sig1 * r1 * uy, y1 - sig1 * r1 * ux)
            p2 = (x2 + sig2 * r2 * uy, y2 - sig2 * r2 * ux)
            if missing:
                length = math.hypot(p2[0] - p1[0], p2[1] - p1[1])
            elif abs(gap) <= EPS:
                length = 0.0
            else:
                length = math.sqrt(max(d * d - k * k, 0.0))
            leg = (p1, p2, length, self._segment_violations(p1, p2), int(missing))
            self._legs[key] = leg
        return leg

    def _arc(self, c: tuple, a: tuple, b: tuple) -> tuple[float, int]:
        """Sweep of the arc on circle ``c`` from point A to point B, and its violations."""
        cx, cy, r, s, own = c
        alpha = math.atan2(a[1] - cy, a[0] - cx)
        beta = math.atan2(b[1] - cy, b[0] - cx)
        swp = ((beta - alpha) if s < 0 else (alpha - beta)) % TWO_PI
        if swp > TWO_PI - ANGLE:
            swp = 0.0

        def within(phi: float) -> bool:
            off = ((phi - alpha) if s < 0 else (alpha - phi)) % TWO_PI
            return off <= swp

        hits = 0
        if self.full:
            for j, (qx, qy, big) in enumerate(self.obstacles):
                if j == own:
                    continue
                reach = max(big - LENGTH, 0.0)
                dq = math.hypot(qx - cx, qy - cy)
                near = (abs(dq - r) < reach and within(math.atan2(qy - cy, qx - cx))
                        ) if dq > 0 else r < reach
                hits += (near or math.hypot(qx - a[0], qy - a[1]) < reach
                         or math.hypot(qx - b[0], qy - b[1]) < reach)
        box = self.box
        if box is not None:
            xs, ys = [a[0], b[0]], [a[1], b[1]]
            for phi, px, py in ((0.0, cx + r, cy), (math.pi / 2, cx, cy + r),
                                (math.pi, cx - r, cy), (-math.pi / 2, cx, cy - r)):
                if within(phi):
                    xs.append(px)
                    ys.append(py)
            hits += (min(xs) < box[0] - LENGTH or max(xs) > box[1] + LENGTH
                     or min(ys) < box[2] - LENGTH or max(ys) > box[3] + LENGTH)
        return swp, hits

    # -- a chromosome ----------------------------------------------------------------

    def decode(self, perm: Sequence[int], labels: Sequence[int]) -> tuple[float, int]:
        """``(length in metres, violations)`` of one chromosome."""
        path = self.circles(perm, labels)
        here = self.start[:2]
        length, violations = 0.0, 0
        for c1, c2 in zip(path, path[1:]):
            if math.hypot(c2[0] - c1[0], c2[1] - c1[1]) < EPS:
                # Coincident centres: the tangent runs in the direction of travel at
                # the arrival point; equal circles of one orientation go on from there.
                x1, y1, r1, s1, _ = c1
                x2, y2, r2, s2, _ = c2
                wx, wy = here[0] - x1, here[1] - y1
                norm = math.hypot(wx, wy) or 1.0
                ux, uy = s1 * wy / norm, -s1 * wx / norm  # travel direction on circle 1
                p1 = (x1 + -s1 * r1 * uy, y1 - -s1 * r1 * ux)
                p2 = (x2 + -s2 * r2 * uy, y2 - -s2 * r2 * ux)
                d = math.hypot(x2 - x1, y2 - y1)
                missing = d - abs(s2 * r2 - s1 * r1) < -EPS  # k = sigma2 r2 - sigma1 r1
                tangent = math.hypot(p2[0] - p1[0], p2[1] - p1[1]) if missing else 0.0
                seg_violations = int(missing)
            else:
                p1, p2, tangent, seg_hits, missing = self._leg(c1, c2)
                seg_violations = seg_hits + missing
            swp, arc_hits = self._arc(c1, here, p1)
            length += c1[2] * swp + tangent
            violations += arc_hits + seg_violations
            here = p2
        swp, arc_hits = self._arc(path[-1], here, self.goal[:2])
        return length + path[-1][2] * swp, violations + arc_hits

    def fitness(self, perm: Sequence[int], labels: Sequence[int]) -> tuple[float, float, int]:
        """``(fitness, length, violations)``: fitness ``10000 / (Dist_m + 1)``."""
        length, violations = self.decode(perm, labels)
        return FITNESS_CONST / (length + self.delta * violations + 1.0), length, violations
