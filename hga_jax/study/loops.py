"""Scene families where free turns win: start and goal poses a few turning radii apart.

Between far-apart poses the tight rope was never beaten in the studies' families;
between poses less than about 5 rho apart the car's shortest path often turns on a
free circle (a turn-turn-turn Dubins word, a loop beside an obstacle). These
families hold such scenes, for measuring a search under ``turns = "free"`` against
the free-turn optimum. Units: metres and degrees (as in a scenario file).

- ``loops``: the RoboCup robots (radius 0.09 m, rho 0.15 m) on the RoboCup field
  (kept), obstacles uniform as in ``clutter`` (:func:`hga_jax.study.scene_files.place_uniform`);
  the start anywhere at least 0.3 m inside the field, the goal in a uniform direction
  at a distance uniform in [0, 5 rho], both headings uniform.
- ``cluster_loops``: the ``clusters`` rule (:mod:`hga_jax.study.clusters`: per-scene
  robot, turning radius and field, clumps of overlapping obstacles around a bent line
  between the poses), with poses drawn as in ``loops``: the clumps gather round them.

A scene is kept only when its tight-rope optimum is feasible, the free-turn optimum
is shorter by at least :data:`MIN_SAVING`, and a chromosome with leg genes expresses it
(:func:`hga_jax.model.cars.free_turns.leg_space.shortest` reaches it): the scenes a free-turn GA can
hit. Scene ``i`` with ``n`` obstacles of seed ``s`` depends on ``(s, n, i)`` alone.
"""
from __future__ import annotations

import math

import numpy as np

from hga_jax.model.cars.free_turns import leg_space
from hga_jax.model.cars.free_turns.model import FREE_TURNS
from hga_jax.model.exact import solve
from . import clusters, scene_files

KINDS = ("loops", "cluster_loops")
STREAM = 0x100F  # last word of the seed: streams apart from the other generators'
REACH = 5.0  # goal within this many turning radii of the start
MIN_SAVING = 0.01  # the free-turn optimum at least 1 % shorter than the tight rope's
MAX_TRIES = 400


def _poses(rng: np.random.Generator, w: float, h: float, rho: float, room: float):
    """Start at least ``room`` inside the field, goal within ``REACH * rho`` of it (also
    ``room`` inside), headings uniform; None when the goal falls outside."""
    sx, sy = rng.uniform(room, w - room), rng.uniform(room, h - room)
    d, b = rng.uniform(0.0, REACH) * rho, rng.uniform(-math.pi, math.pi)
    gx, gy = sx + d * math.cos(b), sy + d * math.sin(b)
    if not (room <= gx <= w - room and room <= gy <= h - room):
        return None
    heads = rng.uniform(-180.0, 180.0, 2)
    return [sx, sy, float(heads[0])], [gx, gy, float(heads[1])]


def draw(kind: str, rng: np.random.Generator, n: int, name: str) -> dict | None:
    """One candidate scene of ``kind`` (a scenario mapping, not yet checked or kept), or
    None when its poses or obstacles could not be placed."""
    if kind == "loops":
        r, rho = scene_files.ROBOT_RADIUS, scene_files.TURN_RADIUS
        w, h = scene_files.FIELD_W, scene_files.FIELD_H
    else:
        r, rho = rng.uniform(*clusters.ROBOT_RADIUS), rng.uniform(*clusters.TURN_RADIUS)
        w, h = clusters.field_size(rng, n)
    poses = _poses(rng, w, h, rho, max(0.3, r + rho))
    if poses is None:
        return None
    start, goal = poses
    if kind == "loops":
        try:
            centres, radii = scene_files.place_uniform(rng, n, w, h, start, goal, False), None
        except RuntimeError:
            return None
    else:
        placed = clusters._place(rng, n, w, h, r, rho, start, goal)
        if placed is None:
            return None
        centres, radii = placed
    return scene_files.scene_dict(name, w, h, start, goal, centres, radii=radii,
                                  robot_radius=r, turn_radius=rho)


def kept(sc) -> bool:
    """The keep rule of the module doc."""
    free = solve(sc, turns=FREE_TURNS.name)
    tight = free.tight_rope_length
    if not (free.feasible and math.isfinite(tight)) or free.length > (1 - MIN_SAVING) * tight:
        return False
    return leg_space.shortest(sc)[0] <= free.length * (1 + 1e-9)


def generate(kind: str, n: int, seed: int, index: int, name: str,
             density: float | None = None) -> dict:
    """Scene ``index`` with ``n`` obstacles of a ``kind`` family (:data:`KINDS`) with
    ``seed``: a scenario mapping; ``density`` must be None (the fields are fixed or
    drawn as the module doc says)."""
    if density is not None:
        raise ValueError(f"{kind} scenes take no density")
    rng = np.random.default_rng([seed, n, index, STREAM])
    return scene_files.first_kept(lambda: draw(kind, rng, n, name), kept, name, MAX_TRIES,
                                  f"{kind} scene with {n} obstacles")
