"""A path as poses: sampled ``(s, x, y, heading, curvature, gear)`` at a chosen spacing.

Host-side numpy in float64 (no JAX). ``segments`` are the segment dicts of the
result files (docs/model.md), in travel order: lines
``{"type": "line", "start": [x, y], "end": [x, y]}`` and arcs
``{"type": "arc", "center": [x, y], "radius": R, "start_angle": a, "sweep": w}``
with ``w`` signed, positive counter-clockwise (CCW, turning left); a piece driven
backward (a Reeds–Shepp car) carries ``"reverse": true``.

Columns of a pose table (one row per pose, in travel order):

- ``s``: arc length from the start of the path (m);
- ``x``, ``y``: position (m);
- ``heading``: the car's heading (rad, counter-clockwise from +x), wrapped into
  ``(-pi, pi]`` (``numpy.unwrap`` of the column gives a continuous one): the
  direction of travel, or its opposite where the car drives backward;
- ``curvature``: signed (1/m): ``+1/R`` where the path turns left (CCW) as ``s``
  grows, ``-1/R`` where it turns right (CW), 0 on a line. It is the curvature of the
  piece that starts at the pose (at the last pose, of the piece that ends there), so
  each row's curvature holds exactly up to the next row;
- ``gear``: the sign of the speed on that piece: ``+1`` forward, ``-1`` backward (a
  cusp is where it changes; the row at a cusp holds the new gear). Along the signed
  distance the car drives (``gear * ds``) the steering curvature is ``gear * curvature``.

Rows are at ``s = 0, spacing, 2 spacing, ...``, at every segment boundary and at
the end ``s = length``; a multiple of ``spacing`` within ``TOL`` of a boundary
gives way to the boundary, so consecutive rows are at most ``spacing + TOL``
apart along ``s``.

In Python the poses are a numpy structured array of :data:`POSE_DTYPE`: the
columns above (``gear`` an integer, ``int8``) and ``t``, the time (s) at which the
car, at its constant speed, passes the pose (``t = s / speed``). :func:`poses` gives
them for a path, a result, a plan or a scenario's optimum; ``res.best.poses(spacing)``
(:class:`hga_jax.running.results.BestPath`) and the replanner's ``Plan.poses(spacing)``
give the same array. The files of ``hga-jax export`` hold the columns without ``t``.
"""
from __future__ import annotations

import csv
import json
import math
from typing import Any, Mapping, Sequence

import numpy as np

from .output import write_file

COLUMNS = ("s", "x", "y", "heading", "curvature", "gear")
UNITS = {"s": "m, arc length from the start", "x": "m", "y": "m",
         "heading": "rad, counter-clockwise from +x, in (-pi, pi]",
         "curvature": "1/m, signed: positive turning left (counter-clockwise), 0 on lines",
         "gear": "+1 driving forward, -1 backward"}
TOL = 1e-9  # m: a multiple of the spacing this close to a segment boundary is left out
POSE_DTYPE = np.dtype([(c, np.int8 if c == "gear" else np.float64) for c in COLUMNS + ("t",)])
"""The poses of :func:`poses`: ``s, x, y, heading, curvature`` (float64), ``gear``
(int8: +1 forward, -1 backward) and ``t`` (float64, s)."""


def wrap(angle: Any) -> Any:
    """Angles (rad) wrapped into ``(-pi, pi]``."""
    return math.pi - np.mod(math.pi - np.asarray(angle, np.float64), 2.0 * math.pi)


def _length(seg: Mapping[str, Any]) -> float:
    """A segment's length (m)."""
    if seg["type"] == "arc":
        return float(seg["radius"]) * abs(float(seg["sweep"]))
    (x0, y0), (x1, y1) = seg["start"], seg["end"]
    return math.hypot(float(x1) - float(x0), float(y1) - float(y0))


def _poses(seg: Mapping[str, Any], u: np.ndarray) -> np.ndarray:
    """Rows ``(x, y, heading, curvature, gear)`` at distances ``u`` (m) along one segment."""
    back = bool(seg.get("reverse"))
    gear = np.full_like(u, -1.0 if back else 1.0)
    face = math.pi if back else 0.0  # driven backward: the car faces against its travel
    if seg["type"] == "arc":
        (cx, cy), r = (float(v) for v in seg["center"]), float(seg["radius"])
        turn = 1.0 if float(seg["sweep"]) >= 0.0 else -1.0  # +1 CCW (left), -1 CW (right)
        angle = float(seg["start_angle"]) + turn * u / r
        return np.stack([cx + r * np.cos(angle), cy + r * np.sin(angle),
                         wrap(angle + turn * math.pi / 2 + face), np.full_like(u, turn / r),
                         gear], axis=1)
    (x0, y0), (x1, y1) = (np.asarray(p, np.float64) for p in (seg["start"], seg["end"]))
    n = max(_length(seg), 1e-300)
    dx, dy = (x1 - x0) / n, (y1 - y0) / n
    return np.stack([x0 + u * dx, y0 + u * dy, np.full_like(u, wrap(math.atan2(dy, dx) + face)),
                     np.zeros_like(u), gear], axis=1)


def sample(segments: Sequence[Mapping[str, Any]], spacing: float,
           start: Sequence[float] | None = None) -> np.ndarray:
    """The pose table ``(k, 6)`` of a path (float64; columns :data:`COLUMNS`).

    ``spacing``: metres between samples along the path (> 0). ``start``: the pose
    ``(x, y, heading in rad)`` to return, alone at ``s = 0`` with curvature 0 (gear +1), for a
    path without segments (start equal to goal); such a path without ``start`` is a
    ValueError.
    """
    spacing = float(spacing)
    if not (math.isfinite(spacing) and spacing > 0.0):
        raise ValueError(f"spacing must be a number > 0 (m), got {spacing!r}")
    if not segments:
        if start is None:
            raise ValueError("a path without segments has no pose: give its start")
        x, y, h = (float(v) for v in start)
        return np.array([[0.0, x, y, float(wrap(h)), 0.0, 1.0]])
    lengths = np.array([_length(seg) for seg in segments])
    bounds = np.concatenate([[0.0], np.cumsum(lengths)])  # boundaries, start and end
    total = float(bounds[-1])
    grid = np.arange(int(math.floor(total / spacing)) + 1) * spacing
    j = np.searchsorted(bounds, grid)  # the boundaries either side of each multiple
    below, above = bounds[np.maximum(j - 1, 0)], bounds[np.minimum(j, len(bounds) - 1)]
    near = np.minimum(np.abs(grid - below), np.abs(above - grid)) <= TOL
    s = np.unique(np.concatenate([grid[(grid < total) & ~near], bounds]))
    piece = np.searchsorted(bounds[1:-1], s, side="right")  # the piece starting at s
    table = np.empty((len(s), len(COLUMNS)))
    table[:, 0] = s
    for i in np.unique(piece):
        rows = piece == i
        u = np.clip(s[rows] - bounds[i], 0.0, lengths[i])
        table[rows, 1:] = _poses(segments[i], u)
    return table


def sample_poses(segments: Sequence[Mapping[str, Any]], spacing: float,
                 start: Sequence[float] | None = None, speed: float = 1.0) -> np.ndarray:
    """:func:`sample` as a structured array of :data:`POSE_DTYPE`, ``t = s / speed``
    (``speed`` in m/s, > 0)."""
    speed = float(speed)
    if not (math.isfinite(speed) and speed > 0.0):
        raise ValueError(f"speed must be a number > 0 (m/s), got {speed!r}")
    table = sample(segments, spacing, start=start)
    out = np.empty(len(table), POSE_DTYPE)
    for i, name in enumerate(COLUMNS[:5]):
        out[name] = table[:, i]
    out["gear"] = np.rint(table[:, 5]).astype(np.int8)
    out["t"] = table[:, 0] / speed
    return out


def poses(path: Any, spacing: float = 0.01, *, scenario: Any = None,
          speed: float | None = None) -> np.ndarray:
    """A path as poses every ``spacing`` m (and at each piece's ends): a structured array
    of :data:`POSE_DTYPE` (``poses["x"]``, ``poses["gear"]``, ``poses["t"]``).

    ``path``: a scenario (its exact optimum, :func:`hga_jax.model.exact.solve`; a
    ValueError saying why where no feasible path exists), a
    :class:`~hga_jax.running.results.RunsResult` (its best path), a path
    (:class:`~hga_jax.model.path.Path`, the result's ``best``, a replanner's ``Plan``, an
    :class:`~hga_jax.model.exact.ExactResult`), or a list of the result files'
    segment dicts. ``scenario`` gives the start pose (the one pose of an empty path)
    and the speed of a path that does not carry them; ``speed`` (m/s) sets the time
    scale (default: the path's or the scenario's ``speed``, else 1 m/s)."""
    from hga_jax.model.scenario import Scenario

    if isinstance(path, Scenario):
        from hga_jax.model.exact import solve
        from hga_jax.model.no_path import verdict

        scenario, found = path, solve(path)
        if not found.feasible:
            why = verdict(found.collision, found.turns, found.message)
            raise ValueError(f"{path.name}: {why}")
        path = found
    elif hasattr(path, "best") and hasattr(path, "scenario"):  # a RunsResult
        scenario, path = scenario or path.scenario, path.best
    start = getattr(path, "start", None)
    if start is None or len(start) == 0:  # a plan without its pose, a bare path
        start = None if scenario is None else scenario.start
    if speed is None:
        speed = getattr(path, "speed", None) or (1.0 if scenario is None else scenario.speed)
    segments = path.segments if hasattr(path, "segments") else path
    return sample_poses(list(segments), spacing, start=start, speed=speed)


def at(segments: Sequence[Mapping[str, Any]], s: Any) -> np.ndarray:
    """Rows ``(x, y, heading, curvature, gear)`` (float64) at arc lengths ``s`` (m, an
    array) along a path with at least one segment, each clipped to ``[0, length]``."""
    s = np.atleast_1d(np.asarray(s, np.float64))
    lengths = np.array([_length(seg) for seg in segments])
    bounds = np.concatenate([[0.0], np.cumsum(lengths)])
    s = np.clip(s, 0.0, bounds[-1])
    piece = np.minimum(np.searchsorted(bounds[1:-1], s, side="right"), len(segments) - 1)
    out = np.empty((s.size, 5))
    for i in np.unique(piece):
        rows = piece == i
        out[rows] = _poses(segments[i], np.clip(s[rows] - bounds[i], 0.0, lengths[i]))
    return out


def _rows(table: np.ndarray) -> list[list[float]]:
    return np.asarray(table, np.float64).reshape(-1, len(COLUMNS)).tolist()


def write_csv(path: str, table: np.ndarray) -> None:
    """Write a pose table as CSV (header :data:`COLUMNS`; numbers as Python writes
    them, which read back to the same float64), atomically."""
    def write(fh) -> None:
        out = csv.writer(fh, lineterminator="\n")
        out.writerow(COLUMNS)
        out.writerows(_rows(table))

    write_file(path, write)


def write_json(path: str, table: np.ndarray, meta: Mapping[str, Any]) -> None:
    """Write a pose table as strict JSON, atomically: ``meta``'s keys, then
    ``columns``, ``units`` and ``poses`` (one ``[s, x, y, heading, curvature, gear]`` list
    per pose, one pose a line)."""
    head = {**meta, "columns": list(COLUMNS), "units": UNITS}
    lines = ",\n".join("  " + json.dumps(r, allow_nan=False) for r in _rows(table))

    def write(fh) -> None:
        fh.write(json.dumps(head, indent=1, allow_nan=False)[:-2])  # without the closing "\n}"
        fh.write(',\n "poses": [\n' + lines + "\n ]\n}\n")

    write_file(path, write)
