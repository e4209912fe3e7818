"""The shortest path of a forward-only Dubins car between two poses, in closed form.

Dubins (1957) showed that the shortest path of a car that only drives forward, with
turning radius at least ``rho``, between two poses is one of six *words*: three
pieces, each a left turn ``L`` (counter-clockwise, on a circle of radius ``rho``), a
right turn ``R`` (clockwise) or a straight line ``S``: LSL, RSR, LSR, RSL, RLR, LRL
(Shkel and Lumelsky list them by the same names). Each word is built here from its
geometry and the shortest one is returned:

- A pose ``p`` with heading ``t`` and unit direction ``u = (cos t, sin t)`` has two
  turning circles, centred at ``p + s*rho*left(u)`` with ``s = +1`` (left, CCW) and
  ``s = -1`` (right, CW), ``left(u) = (-u_y, u_x)``. Driving round a circle in
  direction ``s`` at radial angle ``phi`` (seen from its centre), the heading is
  ``phi + s*pi/2``; a turn from heading ``t0`` to heading ``t1`` sweeps
  ``(s*(t1 - t0)) mod 2 pi``.
- **CSC**: the line leaves the start circle ``(c1, s1)`` and joins the goal circle
  ``(c2, s2)`` along the directed tangent with direction ``u``, touching circle ``j``
  at ``c_j - s_j*rho*left(u)``. With ``D = c2 - c1``, ``d = |D|`` and
  ``k = (s2 - s1)*rho`` it exists when ``d >= |k|``; its length is
  ``L = sqrt(d^2 - k^2)`` and ``u = (L*D - k*left(D)) / d^2``. Two circles of one
  direction with the same centre (start and goal on one turning circle) join where
  the start is: the path is that circle's arc.
- **CCC**: a middle circle of the opposite direction touches both end circles
  (``c1``, ``c2`` of one direction ``s``); its centre lies ``2 rho`` from each, so
  it exists when ``d <= 4 rho``. Both such circles (either side of ``c1 -> c2``) are
  tried; the path switches circles at the contact points, the midpoints of the
  centres.

A sweep within ``ANGLE_TOL`` of ``2 pi`` is rounding of a zero sweep (a full loop is
never shortest). Pure functions of plain floats (float64); metres and radians,
headings counter-clockwise from +x. The result is a segment list in the format of
the result files (:attr:`hga_jax.model.path.Path.segments`).
"""
from __future__ import annotations

import math
from typing import Any

Pose = tuple[float, float, float]
"""``(x, y, heading)``: metres, metres, radians counter-clockwise from +x."""

TWO_PI = 2.0 * math.pi
ANGLE_TOL = 1e-10  # rad: a sweep this close to 2 pi is a zero sweep
TINY = 1e-12  # a sweep (rad) or a line (m) below this is left out of the segments
WORDS = ("LSL", "RSR", "LSR", "RSL", "RLR", "LRL")
_SIDE = {"L": 1.0, "R": -1.0}  # s: +1 left (CCW), -1 right (CW)


def _mod2pi(a: float) -> float:
    """``a`` in ``[0, 2 pi)``, with values within ``ANGLE_TOL`` of ``2 pi`` taken as 0."""
    a = math.fmod(a, TWO_PI)
    if a < 0.0:
        a += TWO_PI
    return 0.0 if a >= TWO_PI - ANGLE_TOL else a


def _centre(p: Pose, s: float, rho: float) -> tuple[float, float]:
    """Centre of the turning circle of pose ``p`` on side ``s`` (+1 left, -1 right)."""
    return p[0] - s * rho * math.sin(p[2]), p[1] + s * rho * math.cos(p[2])


def _arc(c: tuple[float, float], s: float, rho: float, point: tuple[float, float],
         sweep: float) -> dict[str, Any]:
    """The arc on circle ``c`` from ``point``, sweeping ``sweep >= 0`` rad in direction ``s``."""
    return {"type": "arc", "center": [c[0], c[1]], "radius": rho,
            "start_angle": math.atan2(point[1] - c[1], point[0] - c[0]), "sweep": s * sweep}


def _csc(p: Pose, q: Pose, s1: float, s2: float, rho: float):
    """``(length, segments)`` of the word turn-line-turn, or None when it does not exist."""
    c1, c2 = _centre(p, s1, rho), _centre(q, s2, rho)
    dx, dy = c2[0] - c1[0], c2[1] - c1[1]
    d2 = dx * dx + dy * dy
    k = (s2 - s1) * rho
    if d2 < k * k:
        return None
    if k == 0.0 and d2 < (TINY * rho) ** 2:  # one circle: leave it where the start is
        ux, uy, length = math.cos(p[2]), math.sin(p[2]), 0.0
    else:
        length = math.sqrt(d2 - k * k)
        ux, uy = (length * dx + k * dy) / d2, (length * dy - k * dx) / d2
    heading = math.atan2(uy, ux)
    p1 = (c1[0] + s1 * rho * uy, c1[1] - s1 * rho * ux)  # c_j - s_j*rho*left(u)
    p2 = (c2[0] + s2 * rho * uy, c2[1] - s2 * rho * ux)
    sw1, sw2 = _mod2pi(s1 * (heading - p[2])), _mod2pi(s2 * (q[2] - heading))
    segments = [_arc(c1, s1, rho, p[:2], sw1),
                {"type": "line", "start": [p1[0], p1[1]], "end": [p2[0], p2[1]]},
                _arc(c2, s2, rho, p2, sw2)]
    return rho * (sw1 + sw2) + length, segments


def _ccc(p: Pose, q: Pose, s: float, side: float, rho: float):
    """``(length, segments)`` of the word turn-turn-turn (end circles in direction ``s``,
    the middle circle on ``side`` +-1 of ``c1 -> c2``), or None when it does not exist."""
    c1, c2 = _centre(p, s, rho), _centre(q, s, rho)
    dx, dy = c2[0] - c1[0], c2[1] - c1[1]
    d = math.hypot(dx, dy)
    if d > 4.0 * rho or d == 0.0:
        return None
    h = math.sqrt(max(4.0 * rho * rho - d * d / 4.0, 0.0))  # middle centre off the midpoint
    cm = (c1[0] + dx / 2.0 - side * h * dy / d, c1[1] + dy / 2.0 + side * h * dx / d)
    t1 = ((c1[0] + cm[0]) / 2.0, (c1[1] + cm[1]) / 2.0)  # contact points
    t2 = ((cm[0] + c2[0]) / 2.0, (cm[1] + c2[1]) / 2.0)
    h1 = math.atan2(cm[1] - c1[1], cm[0] - c1[0]) + s * math.pi / 2.0  # heading at t1
    h2 = math.atan2(c2[1] - cm[1], c2[0] - cm[0]) - s * math.pi / 2.0  # heading at t2
    sw1, swm, sw2 = (_mod2pi(s * (h1 - p[2])), _mod2pi(-s * (h2 - h1)),
                     _mod2pi(s * (q[2] - h2)))
    segments = [_arc(c1, s, rho, p[:2], sw1), _arc(cm, -s, rho, t1, swm),
                _arc(c2, s, rho, t2, sw2)]
    return rho * (sw1 + swm + sw2), segments


def _candidates(p: Pose, q: Pose, rho: float):
    """``(length, word, segments)`` of every word that exists between ``p`` and ``q``."""
    for word in WORDS:
        a, b, c = (_SIDE.get(w) for w in word)
        if b is None:
            found = [_csc(p, q, a, c, rho)]
        else:
            found = [_ccc(p, q, a, side, rho) for side in (1.0, -1.0)]
        for f in found:
            if f is not None:
                yield f[0], word, f[1]


def _best(p: Pose, q: Pose, rho: float) -> tuple[float, list[dict[str, Any]]]:
    if not rho > 0.0:
        raise ValueError(f"rho: must be positive, got {rho!r}")
    p = (float(p[0]), float(p[1]), float(p[2]))
    q = (float(q[0]), float(q[1]), float(q[2]))
    length, _, segments = min(_candidates(p, q, float(rho)), key=lambda c: c[0])
    return length, segments


def shortest(p: Pose, q: Pose, rho: float) -> list[dict[str, Any]]:
    """The shortest forward path from pose ``p`` to pose ``q`` with turning radius ``rho``
    (m), as segments of the result files: arcs ``{"type": "arc", "center", "radius",
    "start_angle", "sweep"}`` (start angle of the first point seen from the centre,
    signed sweep, positive counter-clockwise; rad) and lines ``{"type": "line",
    "start", "end"}`` (m), in travel order. Pieces with a sweep or length below 1e-12
    are left out (``p == q`` gives ``[]``). Ties between words: any shortest one."""
    _, segments = _best(p, q, rho)
    return [seg for seg in segments if _extent(seg) >= TINY]


def length(p: Pose, q: Pose, rho: float) -> float:
    """Length (m) of :func:`shortest` ``(p, q, rho)``: the Dubins distance."""
    return _best(p, q, rho)[0]


def _extent(seg: dict[str, Any]) -> float:
    """A piece's sweep (rad) for an arc, its length (m) for a line."""
    if seg["type"] == "arc":
        return abs(seg["sweep"])
    return math.hypot(seg["end"][0] - seg["start"][0], seg["end"][1] - seg["start"][1])
