"""Loading and validating scenario files (TOML).

A scenario file holds (units: metres and degrees; headings are converted to
radians in the returned :class:`~hga_jax.model.scenario.Scenario`)::

    name = "..."
    [robot]      radius, min_turn_radius, car, speed (optional, m/s, default 1.0)
    [start]      x, y, heading_deg
    [goal]       x, y, heading_deg
    [[obstacles]] x, y, radius (optional, default: the robot's radius),
                 vx, vy (optional, m/s, default 0: a robot that moves, docs/model.md)
    [field]      xmin, xmax, ymin, ymax, keep_inside (optional, default false)
    [ga]         GA settings, checked by :class:`~hga_jax.search.settings.GASettings`
                 (operators it names must be registered first: plugins load before)

``obstacles``, ``field`` and ``ga`` may be absent. Every problem raises
:class:`~hga_jax.errors.ConfigError` with one line ``"<source>: <key>: <problem>"``
where the key is a dotted path such as ``obstacles[3].x``. Obstacles are numbered
from 1 in the order of the ``[[obstacles]]`` tables, here as everywhere a user
reads them (summaries, plots, the chromosome's upper module, result files), so
``obstacles[3]`` is the third table (docs/model.md).
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from hga_jax.model.scenario import Field, Scenario, scenario_to_dict  # noqa: F401 (the loader's inverse)
from hga_jax import validation
from hga_jax.model import car_model
from hga_jax.search.settings import GASettings

TOL = 1e-9  # metres: a point counts as inside a circle only by more than this

# Table-driven schema: key -> (kind, required).
Spec = dict[str, tuple[str, bool]]
TOP: Spec = {
    "name": ("string", True), "robot": ("table", True), "start": ("table", True),
    "goal": ("table", True), "obstacles": ("tables", False), "field": ("table", False),
    "ga": ("table", False),
}
ROBOT: Spec = {"radius": ("number", True), "min_turn_radius": ("number", True),
               "car": ("string", False), "speed": ("number", False)}
POSE: Spec = {"x": ("number", True), "y": ("number", True), "heading_deg": ("number", True)}
OBSTACLE: Spec = {"x": ("number", True), "y": ("number", True), "radius": ("number", False),
                  "vx": ("number", False), "vy": ("number", False)}
FIELD: Spec = {
    "xmin": ("number", True), "xmax": ("number", True), "ymin": ("number", True),
    "ymax": ("number", True), "keep_inside": ("bool", False),
}


_error = validation.error  # ConfigError("source: key: problem"), on one line


def _value(v: Any, kind: str, source: str, key: str) -> Any:
    """Check one value against its kind; numbers come back as finite floats."""
    if kind == "number":
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise _error(source, key, f"must be a number, got {v!r}")
        if not math.isfinite(v):
            raise _error(source, key, f"must be finite, got {v!r}")
        return float(v)
    if kind == "bool" and not isinstance(v, bool):
        raise _error(source, key, f"must be true or false, got {v!r}")
    if kind == "string" and not isinstance(v, str):
        raise _error(source, key, f"must be a string, got {v!r}")
    if kind == "table" and not isinstance(v, Mapping):
        raise _error(source, key, f"must be a table, got {v!r}")
    if kind == "tables":
        if not isinstance(v, (list, tuple)):
            raise _error(source, key, f"must be an array of tables, got {v!r}")
        for i, item in enumerate(v, start=1):
            _value(item, "table", source, f"{key}[{i}]")
    return v


def _table(table: Mapping[str, Any], spec: Spec, source: str, where: str) -> dict[str, Any]:
    """Check a table's keys (unknown, missing) and value kinds against ``spec``."""
    prefix = f"{where}." if where else ""
    for key in table:
        if key not in spec:
            raise _error(source, f"{prefix}{key}", f"unknown key (known: {', '.join(spec)})")
    out: dict[str, Any] = {}
    for key, (kind, required) in spec.items():
        if key in table:
            out[key] = _value(table[key], kind, source, f"{prefix}{key}")
        elif required:
            raise _error(source, f"{prefix}{key}", "missing key")
    return out


def _positive(v: float, source: str, key: str) -> float:
    """Return ``v`` if it is > 0 (a radius, metres), else raise."""
    if v <= 0.0:
        raise _error(source, key, f"must be > 0, got {v!r}")
    return v


def _pose(table: Mapping[str, Any], source: str, key: str) -> tuple[float, float, float]:
    """A pose ``(x, y, heading)`` in metres and radians from a ``[start]``/``[goal]`` table."""
    t = _table(table, POSE, source, key)
    return (t["x"], t["y"], math.radians(t["heading_deg"]))


def _field(table: Mapping[str, Any], r: float, source: str) -> Field:
    """The field rectangle (metres), checked for order and, when kept, size."""
    t = _table(table, FIELD, source, "field")
    f = Field(t["xmin"], t["xmax"], t["ymin"], t["ymax"], t.get("keep_inside", False))
    for lo, hi in (("xmin", "xmax"), ("ymin", "ymax")):
        a, b = getattr(f, lo), getattr(f, hi)
        if a >= b:
            raise _error(source, f"field.{hi}", f"must be > field.{lo} ({a:g}), got {b:g}")
        if f.keep_inside and b - a <= 2.0 * r:
            raise _error(source, "field", f"{hi} - {lo} = {b - a:g} leaves no room for "
                         f"a robot of radius {r:g} (keep_inside = true)")
    return f


def _obstacles(items: Any, r: float,
               source: str) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Obstacle centres ``(n, 2)``, physical radii ``(n,)`` in metres and velocities
    ``(n, 2)`` in m/s (None when no obstacle gives one)."""
    centres, radii, velocities = [], [], []
    for i, item in enumerate(items, start=1):
        t = _table(item, OBSTACLE, source, f"obstacles[{i}]")
        radii.append(_positive(t.get("radius", r), source, f"obstacles[{i}].radius"))
        velocities.append((t.get("vx", 0.0), t.get("vy", 0.0)))
        c = (t["x"], t["y"])
        for j, other in enumerate(centres, start=1):
            if math.dist(c, other) <= TOL:
                raise _error(source, f"obstacles[{i}]", f"same centre as obstacles[{j}]")
        centres.append(c)
    moving = any(v != (0.0, 0.0) for v in velocities)
    return (np.asarray(centres, float).reshape(-1, 2), np.asarray(radii, float),
            np.asarray(velocities, float).reshape(-1, 2) if moving else None)


def _check_pose(s: Scenario, pose: tuple[float, float, float], source: str, key: str,
                still_only: bool = False) -> None:
    """Raise if the pose point is inside a model circle or (kept) outside the field;
    ``still_only``: only the circles of robots that stand (the goal: a moving robot is
    elsewhere by the time the car arrives, which feasibility in time judges)."""
    x, y, _ = pose
    for i, (c, big_r, moves) in enumerate(zip(s.centres, s.model_radii, s.moving), start=1):
        if still_only and moves:
            continue
        d = math.dist((x, y), c)
        if d < big_r - TOL:
            when = " (a robot that moves, where it is at time 0)" if moves else ""
            raise _error(source, key, f"point ({x:g}, {y:g}) is inside the model circle "
                         f"of obstacles[{i}]{when} (distance {d:.6g} < R {big_r:.6g})")
    xmin, xmax, ymin, ymax = s.bounds
    if not (xmin - TOL <= x <= xmax + TOL and ymin - TOL <= y <= ymax + TOL):
        raise _error(source, key, f"point ({x:g}, {y:g}) is outside the field shrunk "
                     f"by the robot radius [{xmin:g}, {xmax:g}] x [{ymin:g}, {ymax:g}]")


PoseOverride = tuple[Mapping[str, Any], str, str]
"""A pose given apart from the file: ``(table, source, key)``, the table laid out like
``[start]`` (``x``, ``y``, ``heading_deg``), e.g. ``({...}, "command line", "--start")``."""


def scenario_from_dict(mapping: Mapping[str, Any], source: str = "<dict>",
                       poses: Mapping[str, PoseOverride] | None = None) -> Scenario:
    """A validated :class:`Scenario` from a mapping laid out like a scenario file.

    Units: metres and degrees in; metres and radians in the result. ``poses``:
    ``{"start" | "goal": (table, source, key)}`` replaces the mapping's ``[start]``
    or ``[goal]`` (which may then be absent) and is checked by the same rules, its
    problems named ``source: key`` (``command line: --start: point ... is inside the
    model circle of obstacles[3] ...``).
    """
    if not isinstance(mapping, Mapping):
        raise _error(source, "scenario", f"must be a table, got {type(mapping).__name__}")
    if not mapping:
        raise _error(source, "file", "is empty (a scenario needs name, robot, start and goal)")
    poses = dict(poses or {})
    if set(poses) - {"start", "goal"}:
        raise ValueError(f"poses: only start and goal can be given, got {sorted(poses)}")
    top = _table({**mapping, **{k: t for k, (t, _, _) in poses.items()}}, TOP, source, "")
    given = {k: poses.get(k, (top[k], source, k)) for k in ("start", "goal")}
    name = top["name"]
    if not name.strip():
        raise _error(source, "name", "must be a non-empty string")
    robot = _table(top["robot"], ROBOT, source, "robot")
    r = _positive(robot["radius"], source, "robot.radius")
    rho = _positive(robot["min_turn_radius"], source, "robot.min_turn_radius")
    car = robot.get("car", car_model.DUBINS)
    if car not in car_model.cars():
        raise _error(source, "robot.car", f"must be one of {', '.join(car_model.cars())}, "
                     f"got {car!r}")
    start, goal = _pose(*given["start"]), _pose(*given["goal"])
    fld = _field(top["field"], r, source) if "field" in top else None
    speed = _positive(robot.get("speed", 1.0), source, "robot.speed")
    centres, radii, velocities = _obstacles(top.get("obstacles", ()), r, source)
    ga = dict(top.get("ga", {}))
    # Keys and types now; values once every layer (preset, file, --ga, flags) is merged.
    GASettings.check_layer(validation.file_layer(ga, source, "ga"))
    s = Scenario(name=name, robot_radius=r, min_turn_radius=rho, start=start, goal=goal,
                 centres=centres, radii=radii, field=fld, ga=ga, source=source, car=car,
                 velocities=velocities, speed=speed)
    _check_pose(s, start, *given["start"][1:])
    _check_pose(s, goal, *given["goal"][1:], still_only=True)
    return s


def load_scenario(path: str | Path,
                  poses: Mapping[str, PoseOverride] | None = None) -> Scenario:
    """Load and validate a scenario TOML file (metres and degrees; see module doc);
    ``poses`` replace its start or goal (:func:`scenario_from_dict`)."""
    return scenario_from_dict(validation.read_toml(path), str(path), poses)
