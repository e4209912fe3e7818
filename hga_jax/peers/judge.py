"""A path that a planner outside the GA returned, judged by the project's own float64 model.

A peer (OMPL, say) measures its paths by its own rules: a sampling planner checks
its motions only at a finite resolution, and its lengths are its own. So every
peer path is judged again here, the way hga-jax judges its own paths
(docs/model.md, "Feasibility"), in float64 and under the full collision rule:

- **length**: :func:`hga_jax.model.path.segments_length` of the segment list (m);
- **violations**: each line by
  :func:`hga_jax.model.collision.segment_violations` and each arc by
  :func:`hga_jax.model.collision.arc_violations` (obstacles whose model circle the
  piece comes closer to than its radius less the float64 length tolerance, and
  leaving the kept field). A peer's arcs have no own obstacle (``own = -1``); an
  arc that runs on a model circle is not a hit of that circle anyway. Plus one
  violation for each *break*: the path must start at the scenario's start pose,
  end at its goal pose, and each piece must start where the previous one ended,
  with the same heading (``POSITION_TOL`` m, ``HEADING_TOL`` rad); ``gaps`` counts
  the breaks. And one for each arc tighter than the car's minimum turning radius.

Segments are those of the result files (:attr:`hga_jax.model.path.Path.segments`):
an arc ``{"center", "radius", "start_angle", "sweep"}`` starts at radial angle
``start_angle`` and sweeps ``sweep`` rad (positive counter-clockwise). The collision
rules take an arc as its arrival point A, departure point B, sweep ``swp >= 0`` and
orientation ``sign`` (+1 CW, -1 CCW): ``A`` at ``start_angle``, ``B`` at
``start_angle + sweep``, ``swp = |sweep|`` (at most a full circle), ``sign =
-sign(sweep)``. A peer that returns waypoint poses (a sampling planner in a Dubins
state space) has its consecutive poses joined by the shortest Dubins path
(:func:`hga_jax.model.dubins.shortest`), a Reeds–Shepp planner's by the shortest
Reeds–Shepp path (:func:`hga_jax.model.cars.reeds_shepp.closed_form.shortest`), as the planner itself
joins them.

Host code (numpy, float64); metres and radians.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple, Sequence

import numpy as np

from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from hga_jax.model import car_model
from hga_jax.model.path import segments_length
from hga_jax.model.scenario import Scenario

POSITION_TOL = 1e-6  # m: ends of consecutive pieces (and the path's ends) this close join
HEADING_TOL = 1e-6  # rad: headings this close join


class Judged(NamedTuple):
    """A peer path under the model: ``length`` (m, sum of the segments), ``violations``
    (count, breaks included), ``segments`` (the segment list judged) and ``gaps`` (the
    number of breaks: a wrong start or end, or a piece that does not start where and
    how the previous one ended)."""

    length: float
    violations: int
    segments: list[dict[str, Any]]
    gaps: int

    @property
    def feasible(self) -> bool:
        return self.violations == 0


def _ends(seg: dict[str, Any]) -> tuple[tuple[float, float, float | None], ...]:
    """Start and end poses ``(x, y, heading)`` of a piece (a piece driven backward,
    ``"reverse": true``, faces against its travel, so a cusp joins where the heading is
    continuous); heading None where the piece has no direction: a line shorter than
    ``POSITION_TOL`` (a point at this resolution) or an arc of sweep 0 (which way it
    would turn is unknown)."""
    if seg["type"] == "arc":
        (cx, cy), r = seg["center"], float(seg["radius"])
        a0, sw = float(seg["start_angle"]), float(seg["sweep"])
        a1 = a0 + sw
        turn = math.copysign(math.pi / 2.0, sw) if sw != 0.0 else None
        turn = turn if turn is None or not seg.get("reverse") else turn + math.pi
        h0, h1 = (None, None) if turn is None else (a0 + turn, a1 + turn)
        return ((cx + r * math.cos(a0), cy + r * math.sin(a0), h0),
                (cx + r * math.cos(a1), cy + r * math.sin(a1), h1))
    (x0, y0), (x1, y1) = seg["start"], seg["end"]
    long_enough = math.hypot(x1 - x0, y1 - y0) >= POSITION_TOL
    heading = math.atan2(y1 - y0, x1 - x0) if long_enough else None
    if heading is not None and seg.get("reverse"):  # driven backward: facing the other way
        heading += math.pi
    return (x0, y0, heading), (x1, y1, heading)


def _joins(a: Sequence[float | None], b: Sequence[float | None]) -> bool:
    """Whether pose ``a`` (where one piece ends) is pose ``b`` (where the next starts);
    a missing heading matches any."""
    if math.hypot(b[0] - a[0], b[1] - a[1]) > POSITION_TOL:
        return False
    if a[2] is None or b[2] is None:
        return True
    turn = math.remainder(b[2] - a[2], 2.0 * math.pi)
    return abs(turn) <= HEADING_TOL


def _breaks(scenario: Scenario, segments: Sequence[dict[str, Any]]) -> int:
    """Breaks along the path, from the start pose through every piece to the goal pose.
    A piece without a direction passes on the heading it received."""
    breaks, at = 0, tuple(float(v) for v in scenario.start)
    for seg in segments:
        first, last = _ends(seg)
        breaks += not _joins(at, first)
        at = last if last[2] is not None else (last[0], last[1], at[2])
    return breaks + (not _joins(at, tuple(float(v) for v in scenario.goal)))


def _collisions(scenario: Scenario, segments: Sequence[dict[str, Any]]) -> int:
    """Violations of the pieces under the full rule of :mod:`hga_jax.model.collision`."""
    sa = scenario.arrays(np.float64)
    obs = col.obstacles(np.asarray(sa.centres, np.float64),
                        np.asarray(sa.model_radii, np.float64), ndim=1)
    bounds, tol = np.asarray(sa.bounds, np.float64), g.tolerances(np.float64).length
    lines = np.array([[*s["start"], *s["end"]] for s in segments if s["type"] != "arc"],
                     np.float64).reshape(-1, 4)
    arcs = np.array([[*s["center"], s["radius"], s["start_angle"], s["sweep"]]
                     for s in segments if s["type"] == "arc"], np.float64).reshape(-1, 5)
    total = 0
    if len(lines):
        ends = tuple(lines.T)
        total += int(col.segment_violations(ends, np.ones(len(lines), bool), obs, bounds, tol,
                                            "full").sum())
    if len(arcs):
        cx, cy, r, a0, sw = arcs.T
        a1 = a0 + sw
        circle = (cx, cy, r, -np.sign(sw))  # +1 CW, -1 CCW
        arc = (cx + r * np.cos(a0), cy + r * np.sin(a0), cx + r * np.cos(a1),
               cy + r * np.sin(a1), np.minimum(np.abs(sw), 2.0 * np.pi))
        own = np.full(len(arcs), -1, np.int32)
        total += int(col.arc_violations(circle, own, arc, obs, bounds, tol, "full").sum())
    return total


def judge_segments(scenario: Scenario, segments: Sequence[dict[str, Any]]) -> Judged:
    """A segment list (result-file format, travel order) judged by the model: length,
    violations (collisions, field exits and breaks) and breaks (see module doc)."""
    segments = list(segments)
    gaps = _breaks(scenario, segments)
    tight = _too_tight(scenario, segments)
    return Judged(float(segments_length(segments)),
                  _collisions(scenario, segments) + gaps + tight, segments, gaps)


def _too_tight(scenario: Scenario, segments: Sequence[dict[str, Any]]) -> int:
    """Arcs that turn tighter than the car can (radius below ``min_turn_radius`` by more
    than the float64 length tolerance): one violation each."""
    least = float(scenario.min_turn_radius) - g.tolerances(np.float64).length
    return sum(1 for seg in segments if seg["type"] == "arc" and seg["sweep"] != 0.0
               and seg["radius"] < least)


def judge_poses(scenario: Scenario, poses: Sequence[Sequence[float]],
                car: str | None = None) -> Judged:
    """Waypoint poses ``(x, y, heading)`` (m, m, rad; shape (k, 3)) joined by the car's
    shortest paths of radius ``scenario.min_turn_radius`` (``car``: ``"dubins"``, forward
    only, or ``"reeds-shepp"``; None: the scenario's), judged by :func:`judge_segments`
    (the first and last poses must be the scenario's start and goal)."""
    poses = [tuple(float(v) for v in p) for p in poses]
    rho = float(scenario.min_turn_radius)
    model = car_model.of_car(scenario.car if car is None else car)
    segments: list[dict[str, Any]] = []
    for p, q in zip(poses, poses[1:]):
        segments += model.connect(p, q, rho)
    judged = judge_segments(scenario, segments)
    if poses and not segments:  # no motion: the path is the point at the first pose
        start, goal = (tuple(float(v) for v in p) for p in (scenario.start, scenario.goal))
        gaps = int(not _joins(start, poses[0])) + int(not _joins(poses[0], goal))
        judged = judged._replace(violations=judged.violations - judged.gaps + gaps, gaps=gaps)
    return judged
