"""Scene families where reversing pays: parking-like poses for the Reeds–Shepp car.

A car that also drives backward gains most where the goal lies behind it, in a slot,
or where it starts facing a wall. These families hold such scenes, for measuring a
search or a planner of the Reeds–Shepp car (``[robot] car = "reeds-shepp"``) against
its optimum. The RoboCup robots (radius 0.09 m, rho 0.15 m) on the RoboCup field
(kept), ``n`` obstacles placed uniformly around the poses
(:func:`hga_jax.study.scene_files.place_uniform`), and poses by kind:

- ``behind``: the goal 2-6 rho straight behind the start, its heading within 15
  degrees of the start's (backing into a lane);
- ``slot``: the goal between two obstacles on either side of it (a parking slot, the
  obstacles 0.42 m apart centre to centre, in line across the goal's heading), the
  start 3-8 rho away in a uniform direction with a uniform heading;
- ``wall``: the start 0.1-0.25 m from a wall of the field, facing it within 30
  degrees, the goal 2-8 rho away with a uniform heading.

A scene is kept only when the Reeds–Shepp optimum exists and is shorter than the
free-turn (forward only) optimum by at least :data:`MIN_SAVING`. A family whose
``car = "dubins"`` holds the same kinds of poses for the forward car: its scenes
are kept where the forward car's tight-rope optimum is feasible and expressible
(a start facing a wall it cannot turn away from is dropped, not counted as a miss).
Scene ``i`` with ``n`` obstacles of seed ``s`` depends on ``(s, n, i)`` alone. Units: metres and degrees (as
in a scenario file).
"""
from __future__ import annotations

import math

import numpy as np

from hga_jax.model.cars.reeds_shepp.model import REEDS_SHEPP
from hga_jax.model.exact import solve
from . import scene_files

KINDS = ("behind", "slot", "wall")
STREAM = 0x9A4C  # last word of the seed: streams apart from the other generators'
MIN_SAVING = 0.01  # the Reeds-Shepp optimum at least 1 % shorter than the forward one
MAX_TRIES = 400
SLOT = 0.21  # m: half the distance between the two obstacles of a slot


def _within(p, w: float, h: float, room: float) -> bool:
    return room <= p[0] <= w - room and room <= p[1] <= h - room


def _poses(kind: str, rng: np.random.Generator, w: float, h: float, rho: float,
           room: float):
    """``(start, goal, fixed obstacle centres)`` of ``kind``, or None when a pose falls
    outside the field."""
    fixed: list[list[float]] = []
    if kind == "wall":
        side = int(rng.integers(4))
        d = rng.uniform(0.1, 0.25) + scene_files.ROBOT_RADIUS
        along = rng.uniform(room, (w if side < 2 else h) - room)
        x, y = {0: (d, along), 1: (w - d, along), 2: (along, d), 3: (along, h - d)}[side]
        facing = {0: 180.0, 1: 0.0, 2: -90.0, 3: 90.0}[side] + rng.uniform(-30, 30)
        start = [x, y, facing]
        dist, b = rng.uniform(2, 8) * rho, rng.uniform(-math.pi, math.pi)
        goal = [x + dist * math.cos(b), y + dist * math.sin(b), rng.uniform(-180, 180)]
    else:
        goal_first = kind == "slot"
        a = [rng.uniform(room, w - room), rng.uniform(room, h - room), rng.uniform(-180, 180)]
        if goal_first:
            goal = a
            dist, b = rng.uniform(3, 8) * rho, rng.uniform(-math.pi, math.pi)
            start = [a[0] + dist * math.cos(b), a[1] + dist * math.sin(b),
                     rng.uniform(-180, 180)]
            t = math.radians(goal[2])
            fixed = [[goal[0] - s * SLOT * math.sin(t), goal[1] + s * SLOT * math.cos(t)]
                     for s in (1.0, -1.0)]
        else:
            start = a
            dist, t = rng.uniform(2, 6) * rho, math.radians(a[2])
            goal = [a[0] - dist * math.cos(t), a[1] - dist * math.sin(t),
                    a[2] + rng.uniform(-15, 15)]
    if not (_within(start, w, h, room) or kind == "wall") or not _within(goal, w, h, room):
        return None
    return start, goal, fixed


def draw(kind: str, rng: np.random.Generator, n: int, name: str) -> dict | None:
    """One candidate scene of ``kind`` (not yet checked or kept), or None."""
    r, rho = scene_files.ROBOT_RADIUS, scene_files.TURN_RADIUS
    w, h = scene_files.FIELD_W, scene_files.FIELD_H
    poses = _poses(kind, rng, w, h, rho, max(0.3, r + rho))
    if poses is None:
        return None
    start, goal, fixed = poses
    try:
        centres = scene_files.place_uniform(rng, max(0, n - len(fixed)), w, h, start, goal,
                                            False)
    except RuntimeError:
        return None
    centres = np.concatenate([np.asarray(fixed, float).reshape(-1, 2), centres])[:n]
    d = scene_files.scene_dict(name, w, h, start, goal, centres, robot_radius=r,
                               turn_radius=rho)
    d["robot"]["car"] = REEDS_SHEPP.car
    return d


def kept(sc) -> bool:
    """The keep rule of the module doc."""
    rs = REEDS_SHEPP.solve(sc, "full")
    free = rs.details.get("free_turn_length", math.inf)
    return rs.feasible and rs.length <= (1 - MIN_SAVING) * free


def kept_forward(sc) -> bool:
    """The keep rule for the forward car: its tight-rope optimum is feasible and a
    chromosome expresses it (no obstacle touched twice)."""
    opt = solve(sc)
    return bool(opt.feasible and opt.expressible)


def generate(kind: str, n: int, seed: int, index: int, name: str,
             density: float | None = None, car: str | None = None) -> dict:
    """Scene ``index`` with ``n`` obstacles of a ``kind`` family (:data:`KINDS`) with
    ``seed``: a scenario mapping; ``density`` must be None. ``car``: the scene's car
    (default the Reeds–Shepp car); for the forward car (``"dubins"``) the same draws
    are kept by :func:`kept_forward` instead: parking-like poses that the forward car
    can drive, whatever reversing would save."""
    if density is not None:
        raise ValueError(f"{kind} scenes take no density")
    rng = np.random.default_rng([seed, n, index, STREAM])
    forward = car is not None and car != REEDS_SHEPP.car

    def candidate():
        d = draw(kind, rng, n, name)
        if d is not None and forward:
            d["robot"]["car"] = car
        return d

    return scene_files.first_kept(candidate, kept_forward if forward else kept, name,
                                  MAX_TRIES, f"{kind} scene with {n} obstacles")
