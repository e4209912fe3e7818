"""The ``scattered`` scene family: obstacles strewn over the field, every scene its own
robot, obstacle sizes and field, and the field's edges walls in half of the scenes.

Held-out scenes for the search, unlike :mod:`hga_jax.study.scenes` (``obstructed``: one
robot, one obstacle size, a fixed field, half the obstacles near the straight line)
and :mod:`~hga_jax.study.clusters` (clumps along a bent line, walls always). Units:
metres and degrees (as in a scenario file); field corner at the origin.

- Robot: per scene a radius in [0.05, 0.12] m and a minimum turning radius in
  [0.09, 0.25] m. Obstacles: each a physical radius in [0.03, 0.20] m, so model
  radii ``max(rho, r_i + r)`` differ between obstacles of a scene.
- Field: per scene a density of 0.6 to 2.5 obstacles per square metre (tight and
  wide fields; area ``n / density``, at least :data:`MIN_AREA`) and an aspect ratio
  of 1 to 2.2; its edges are walls (``keep_inside = true``) with probability 1/2.
- Poses: as :mod:`~hga_jax.study.clusters` draws them (opposite ends of the long side
  or opposite corners, headings uniform), but as close as ``r + 0.02`` m to the near
  edges (a room drawn per scene up to ``r + rho``): a turning circle at a pose may
  cross the field's edge.
- Placement: uniform over the field, 0.1 m from its edges, clear of the start and
  goal points by the obstacle's model radius; any two model circles at least
  :data:`MIN_GAP` times the sum of their radii apart (so they may overlap).

A scene is kept only when the straight start-goal line and all four direct Dubins
paths collide and the exact optimum is feasible, expressible and touches at least
two obstacles. A family's ``density`` key is refused (each scene draws its own).
Scene ``i`` with ``n`` obstacles of seed ``s`` depends on ``(s, n, i)`` alone.
"""
from __future__ import annotations

import numpy as np

from . import scene_files
from .clusters import field_size, poses

STREAM = 0x5CA7  # last word of the seed: streams apart from the other generators'
ROBOT_RADIUS = (0.05, 0.12)  # m
TURN_RADIUS = (0.09, 0.25)  # m
OBSTACLE_RADIUS = (0.03, 0.20)  # m, physical
DENSITY = (0.6, 2.5)  # obstacles per square metre
ASPECT = (1.0, 2.2)  # long side over short side
MIN_AREA = 2.0  # m^2
MIN_GAP = 0.5  # any two centres at least this times the sum of their model radii apart
WALLS = 0.5  # probability that the field is kept
MAX_TRIES = 2000


def _place(rng: np.random.Generator, n: int, w: float, h: float, r: float, rho: float,
           start, goal) -> tuple[np.ndarray, np.ndarray] | None:
    """``n`` centres and physical radii, or None when the field is too full."""
    ends = np.array([start[:2], goal[:2]])
    xy: list[np.ndarray] = []
    radius: list[float] = []
    model: list[float] = []
    for _ in range(100 * n):
        if len(xy) >= n:
            break
        ri = rng.uniform(*OBSTACLE_RADIUS)
        big = max(rho, ri + r)
        c = rng.uniform([0.1, 0.1], [w - 0.1, h - 0.1])
        if np.min(np.hypot(*(ends - c).T)) < big + 0.05:
            continue
        if xy and np.any(np.hypot(*(np.array(xy) - c).T) < MIN_GAP * (np.array(model) + big)):
            continue
        xy.append(c)
        radius.append(ri)
        model.append(big)
    if len(xy) < n:
        return None
    return np.array(xy).reshape(n, 2), np.array(radius)


def generate(n: int, seed: int, index: int, name: str, density: float | None = None) -> dict:
    """Scene ``index`` with ``n`` obstacles of a ``scattered`` family with ``seed``: a
    scenario mapping (:func:`hga_jax.study.scene_files.scene_dict`); ``density`` must be None."""
    if density is not None:
        raise ValueError("scattered scenes draw their own density; give none")
    rng = np.random.default_rng([seed, n, index, STREAM])

    def draw() -> dict | None:
        r, rho = rng.uniform(*ROBOT_RADIUS), rng.uniform(*TURN_RADIUS)
        w, h = field_size(rng, n, DENSITY, ASPECT, MIN_AREA)
        walls = bool(rng.random() < WALLS)
        start, goal = poses(rng, w, h, r + rng.uniform(0.02, rho))
        placed = _place(rng, n, w, h, r, rho, start, goal)
        if placed is None:
            return None
        return scene_files.scene_dict(name, w, h, start, goal, placed[0], radii=placed[1],
                                      robot_radius=r, turn_radius=rho, keep_inside=walls)

    return scene_files.first_kept(draw, scene_files.blocked_and_wrapping(2), name, MAX_TRIES,
                                  f"scattered scene with {n} obstacles")
