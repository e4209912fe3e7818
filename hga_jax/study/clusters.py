"""The ``clusters`` scene family: held-out scenes made by a rule unlike ``obstructed``.

Search settings tuned on :mod:`hga_jax.study.scenes` (``obstructed``) are checked here on
scenes that differ from those in every respect the generator chooses. Units: metres
and degrees (as in a scenario file); field corner at the origin, x along the width.

- Robot: per scene a radius in [0.05, 0.12] m and a minimum turning radius in
  [0.10, 0.30] m. Obstacles: each a physical radius in [0.04, 0.22] m, so model radii
  ``max(rho, r_i + r)`` differ between obstacles of a scene.
- Field: per scene a density of 0.8 to 2.0 obstacles per square metre (area
  ``n / density``, at least :data:`MIN_AREA`) and an aspect ratio of 1 to 2.5, long
  side along x or y at random; the field is kept (``keep_inside = true``).
- Poses: start and goal near opposite ends of the long side or near opposite
  corners (at random, either way round), headings uniform in [-180, 180) degrees.
- Placement: obstacles come in clumps of 1 to 4; each new member lies
  ``f * (R_a + R_b)`` from a random earlier member, ``f`` in [0.6, 1.1], so a clump's
  model circles often overlap. Clump centres are drawn around a random polyline from
  start to goal with 2 or 3 bends (:data:`ON_PATH` of them), the rest uniform.

A scene is kept, as ``obstructed`` keeps one, only when the straight start-goal line
and all four direct Dubins paths collide, the exact optimum is feasible and
expressible, and it wraps at least three obstacles. A family's ``density`` key is
not used (each scene draws its own) and is refused by the study loader. Scene ``i``
with ``n`` obstacles of seed ``s`` depends on ``(s, n, i)`` alone.
"""
from __future__ import annotations

import math

import numpy as np

from . import scene_files

STREAM = 0xC1A5  # last word of the seed: streams apart from those of scenes.py
ROBOT_RADIUS = (0.05, 0.12)  # m
TURN_RADIUS = (0.10, 0.30)  # m
OBSTACLE_RADIUS = (0.04, 0.22)  # m, physical
DENSITY = (0.8, 2.0)  # obstacles per square metre
ASPECT = (1.0, 2.5)  # long side over short side
MIN_AREA = 3.0  # m^2: room for the largest turning circles on small counts
CLUMP = (1, 4)  # members per clump
GAP = (0.6, 1.1)  # member distance over the sum of the two model radii
ON_PATH = 0.6  # fraction of clump centres drawn around the bent polyline
MIN_GAP = 0.3  # any two centres at least this times the sum of their model radii apart
MAX_TRIES = 2000


def field_size(rng: np.random.Generator, n: int, density=DENSITY, aspect=ASPECT,
               min_area: float = MIN_AREA) -> tuple[float, float]:
    """A field's width and height (m) for ``n`` obstacles: a density and an aspect ratio
    drawn uniformly from their ranges, the long side along x or y at random."""
    area = max(n / rng.uniform(*density), min_area)
    aspect = rng.uniform(*aspect)
    long, short = math.sqrt(area * aspect), math.sqrt(area / aspect)
    return (long, short) if rng.random() < 0.5 else (short, long)


def poses(rng: np.random.Generator, w: float, h: float, room: float
          ) -> tuple[list[float], list[float]]:
    """Start and goal near opposite ends (or corners), ``room`` to ``room + 0.3`` from
    the near edges; the ends along the long side, or a diagonal, at random."""
    def near(lo_end: bool, size: float) -> float:
        d = rng.uniform(room, max(room, min(room + 0.3, size / 3)))
        return d if lo_end else size - d

    def across(size: float) -> float:
        return rng.uniform(room, size - room)

    flip = bool(rng.random() < 0.5)
    if rng.random() < 0.5:  # opposite corners
        sx, sy = bool(rng.random() < 0.5), bool(rng.random() < 0.5)
        a, b = (near(sx, w), near(sy, h)), (near(not sx, w), near(not sy, h))
    elif w >= h:  # opposite ends of the long side
        a, b = (near(flip, w), across(h)), (near(not flip, w), across(h))
    else:
        a, b = (across(w), near(flip, h)), (across(w), near(not flip, h))
    heads = rng.uniform(-180.0, 180.0, 2)
    return [a[0], a[1], float(heads[0])], [b[0], b[1], float(heads[1])]


def _polyline(rng: np.random.Generator, a: np.ndarray, b: np.ndarray, w: float, h: float
              ) -> np.ndarray:
    """Start, 2 or 3 bends pushed off the straight line (up to 0.35 of its length), goal."""
    d = b - a
    normal = np.array([-d[1], d[0]]) / np.hypot(*d)
    t = np.sort(rng.uniform(0.15, 0.85, rng.integers(2, 4)))
    off = rng.uniform(-0.35, 0.35, t.size) * np.hypot(*d)
    bends = a + t[:, None] * d + off[:, None] * normal
    bends = np.clip(bends, [0.1 * w, 0.1 * h], [0.9 * w, 0.9 * h])
    return np.vstack([a, bends, b])


def _on_polyline(rng: np.random.Generator, pts: np.ndarray) -> np.ndarray:
    """A point at a uniform arc length along ``pts``, moved by N(0, 0.15 m) each way."""
    seg = np.hypot(*np.diff(pts, axis=0).T)
    s = rng.uniform(0.0, seg.sum())
    k = min(int(np.searchsorted(np.cumsum(seg), s)), seg.size - 1)
    u = (s - seg[:k].sum()) / seg[k]
    return pts[k] + u * (pts[k + 1] - pts[k]) + rng.normal(0.0, 0.15, 2)


def _place(rng: np.random.Generator, n: int, w: float, h: float, r: float, rho: float,
           start: list[float], goal: list[float]) -> tuple[np.ndarray, np.ndarray] | None:
    """``n`` centres and physical radii in clumps, or None when the field is too full."""
    ends = np.array([start[:2], goal[:2]])
    path = _polyline(rng, ends[0], ends[1], w, h)
    xy: list[np.ndarray] = []
    radius: list[float] = []
    model: list[float] = []
    for _ in range(50 * n):
        if len(xy) >= n:
            break
        centre = (_on_polyline(rng, path) if rng.random() < ON_PATH
                  else rng.uniform([0.0, 0.0], [w, h]))
        size = min(int(rng.integers(CLUMP[0], CLUMP[1] + 1)), n - len(xy))
        first = len(xy)
        for m in range(size):
            ri = rng.uniform(*OBSTACLE_RADIUS)
            big = max(rho, ri + r)
            c = centre
            if m:
                j = int(rng.integers(first, len(xy))) if len(xy) > first else None
                if j is None:
                    break
                ang = rng.uniform(0.0, 2.0 * math.pi)
                c = xy[j] + rng.uniform(*GAP) * (model[j] + big) * np.array(
                    [math.cos(ang), math.sin(ang)])
            if not (0.1 <= c[0] <= w - 0.1 and 0.1 <= c[1] <= h - 0.1):
                continue
            if np.min(np.hypot(*(ends - c).T)) < big + 0.05:
                continue
            if xy and np.any(np.hypot(*(np.array(xy) - c).T) < MIN_GAP * (np.array(model) + big)):
                continue
            xy.append(np.asarray(c, float))
            radius.append(ri)
            model.append(big)
    if len(xy) < n:
        return None
    return np.array(xy[:n]).reshape(n, 2), np.array(radius[:n])


def generate(n: int, seed: int, index: int, name: str, density: float | None = None) -> dict:
    """Scene ``index`` with ``n`` obstacles of a ``clusters`` family with ``seed``: a
    scenario mapping (:func:`hga_jax.study.scene_files.scene_dict`); ``density`` must be None."""
    if density is not None:
        raise ValueError("clusters scenes draw their own density; give none")
    rng = np.random.default_rng([seed, n, index, STREAM])

    def draw() -> dict | None:
        r, rho = rng.uniform(*ROBOT_RADIUS), rng.uniform(*TURN_RADIUS)
        w, h = field_size(rng, n)
        start, goal = poses(rng, w, h, r + rho)
        placed = _place(rng, n, w, h, r, rho, start, goal)
        if placed is None:
            return None
        return scene_files.scene_dict(name, w, h, start, goal, placed[0], radii=placed[1],
                                      robot_radius=r, turn_radius=rho)

    return scene_files.first_kept(draw, scene_files.blocked_and_wrapping(3), name, MAX_TRIES,
                                  f"clusters scene with {n} obstacles")
