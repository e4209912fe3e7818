"""The ``corridors`` scene family: barriers of obstacles across the field, each with a gap
or two, so that a path must thread the gaps in turn.

A held-out rule unlike the others (:mod:`hga_jax.study.scattered` strews obstacles,
:mod:`~hga_jax.study.clusters` clumps them): most obstacles stand in rows across the
field whose model circles overlap, and the way from start to goal is a corridor from
one gap to the next. Units: metres and degrees (as in a scenario file); field corner
at the origin, x along the width, the barriers across it.

- Robot: per scene a radius in [0.05, 0.12] m and a minimum turning radius in
  [0.09, 0.25] m. Obstacles: each a physical radius in [0.03, 0.15] m, so model radii
  ``R_i = max(rho, r_i + r)`` differ between obstacles of a scene.
- Barriers: ``1 + n // 12`` of them (1 at 9 obstacles, 4 at 40), holding 60 to 85 %
  of the obstacles between them. Along a barrier, neighbours stand ``f (R_a + R_b)``
  apart with ``f`` in [0.75, 0.95] (overlapping, closed), but at one or two gaps
  ``R_a + R_b + g`` with ``g`` in [0.03, 0.30] m; each centre is moved across the
  barrier by up to 0.15 of its model radius (closed steps stay closed). The barriers'
  first gaps alternate between the lower and upper halves of the field (a zigzag),
  each with probability 0.7 (otherwise anywhere). Barriers shorter than the field's
  height lengthen their closed steps (up to 0.95 of the two model radii, still
  closed), then their gaps; their end circles reach past the field's edges.
- Field: compartments 0.6 to 1.1 m plus the largest model radius wide between the
  barriers and the ends; its height the longest barrier's (an end circle's centre a
  quarter of its model radius inside the edge); the edges are walls (``keep_inside =
  true``) with probability 0.7 (where they are not, a path may go round a barrier's end).
- Poses: the start in the first compartment, the goal in the last, headings uniform.
- The other obstacles: uniform over the field, clear of the poses by their model
  radius, any two centres at least 0.5 times the sum of their model radii apart.

A scene is kept only when the straight start-goal line and all four direct Dubins
paths collide and the exact optimum is feasible, expressible and touches at least two
obstacles. A family's ``density`` key is refused (the barriers set the field). Scene
``i`` with ``n`` obstacles of seed ``s`` depends on ``(s, n, i)`` alone.
"""
from __future__ import annotations

import numpy as np

from . import scene_files

STREAM = 0xC0DD  # last word of the seed: streams apart from the other generators'
ROBOT_RADIUS = (0.05, 0.12)  # m
TURN_RADIUS = (0.09, 0.25)  # m
OBSTACLE_RADIUS = (0.03, 0.15)  # m, physical
IN_BARRIERS = (0.60, 0.85)  # share of the obstacles standing in barriers
CLOSED = (0.75, 0.95)  # neighbours' distance over the sum of their model radii
GAP = (0.03, 0.30)  # m of clear room in a gap
SWAY = 0.15  # a barrier centre's move across the barrier, in its model radius
COMPARTMENT = (0.6, 1.1)  # m between barriers
WALLS = 0.7  # probability that the field is kept
TIGHTEST = 0.95  # a closed step's longest: this times the sum of the two model radii
ZIGZAG = 0.7  # probability that a barrier's first gap keeps the zigzag (lower, upper, ...)
MIN_GAP = 0.5  # free obstacles: centres at least this times the sum of model radii apart
MAX_TRIES = 2000


def _barrier(rng: np.random.Generator, model: np.ndarray, low: bool | None
             ) -> tuple[np.ndarray, np.ndarray]:
    """The steps between neighbours along a barrier of circles with model radii
    ``model`` (from the bottom edge up) and the indices of the steps that are gaps: one
    or two, the first in the lower half of the barrier when ``low``, in the upper half
    when not ``low``, anywhere when None."""
    k = model.size - 1
    i = np.arange(k)
    where = i if low is None else np.flatnonzero(i + 1 <= k / 2 if low else i >= k / 2)
    first = int(rng.choice(where if where.size else np.arange(k)))
    rest = np.setdiff1d(np.arange(k), [first])
    gaps = np.concatenate([[first], rng.choice(rest, min(rest.size, int(rng.integers(0, 2))),
                                               replace=False)]).astype(int)
    steps = rng.uniform(*CLOSED, k) * (model[:-1] + model[1:])
    steps[gaps] = model[:-1][gaps] + model[1:][gaps] + rng.uniform(*GAP, gaps.size)
    return steps, gaps


def _stretch(steps: np.ndarray, gaps: np.ndarray, pairs: np.ndarray, short: float
             ) -> np.ndarray:
    """``steps`` lengthened by ``short`` in all: the closed ones up to :data:`TIGHTEST`
    times their neighbours' ``pairs`` of model radii (staying closed), the rest in the gaps."""
    room = np.maximum(TIGHTEST * pairs - steps, 0.0)
    room[gaps] = 0.0
    grow = min(short, room.sum())
    out = steps + (room * (grow / room.sum()) if room.sum() > 0 else 0.0)
    out[gaps] += (short - grow) / gaps.size
    return out


def _place(rng: np.random.Generator, n: int, r: float, rho: float):
    """Field width, height, centres, physical radii, model radii, how many obstacles
    stand in barriers (the first ones), each compartment's middle x and width."""
    radii = rng.uniform(*OBSTACLE_RADIUS, n)
    model = np.maximum(rho, radii + r)
    walls = 1 + n // 12
    held = max(walls * 2, min(n, int(round(rng.uniform(*IN_BARRIERS) * n))))
    counts = np.diff(np.linspace(0, held, walls + 1).round().astype(int))
    firsts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    flip = bool(rng.random() < 0.5)
    rows = [_barrier(rng, model[f:f + c], None if rng.random() < 1 - ZIGZAG else (j % 2 == 0) ^ flip)
            for j, (f, c) in enumerate(zip(firsts, counts))]
    # the field's height: the longest barrier, an end circle's centre a quarter of its
    # model radius inside the edge (so that the end circles cross the edges)
    ends = [0.25 * (model[f] + model[f + c - 1]) for f, c in zip(firsts, counts)]
    h = float(max(steps.sum() + e for (steps, _), e in zip(rows, ends)))
    rooms = rng.uniform(*COMPARTMENT, walls + 1) + model.max()
    xs = np.cumsum(rooms)[:-1]
    w = float(rooms.sum())
    centres = np.zeros((n, 2))
    for (steps, gaps), f, c, e, x in zip(rows, firsts, counts, ends, xs):
        m = model[f:f + c]
        steps = _stretch(steps, gaps, m[:-1] + m[1:], h - steps.sum() - e)
        centres[f:f + c, 1] = 0.25 * m[0] + np.concatenate([[0.0], np.cumsum(steps)])
        centres[f:f + c, 0] = x + rng.uniform(-SWAY, SWAY, c) * m
    middles = np.concatenate([[rooms[0] / 2], xs + rooms[1:] / 2])
    return w, h, centres, radii, model, held, middles, rooms


def generate(n: int, seed: int, index: int, name: str, density: float | None = None) -> dict:
    """Scene ``index`` with ``n`` obstacles of a ``corridors`` family with ``seed``: a
    scenario mapping (:func:`hga_jax.study.scene_files.scene_dict`); ``density`` must be None."""
    if density is not None:
        raise ValueError("corridors scenes take their field from their barriers; give no density")
    rng = np.random.default_rng([seed, n, index, STREAM])

    def draw() -> dict | None:
        r, rho = rng.uniform(*ROBOT_RADIUS), rng.uniform(*TURN_RADIUS)
        w, h, centres, radii, model, held, middles, rooms = _place(rng, n, r, rho)
        room = r + 0.02
        if h < 2 * room + 0.1:
            return None
        ends = []
        for mid, width in ((middles[0], rooms[0]), (middles[-1], rooms[-1])):
            x = mid + rng.uniform(-0.25, 0.25) * width
            ends.append([x, rng.uniform(room, h - room), float(rng.uniform(-180.0, 180.0))])
        start, goal = ends
        poses = np.array([start[:2], goal[:2]])
        placed = list(range(held))
        for i in range(held, n):  # the free obstacles
            for _ in range(200):
                c = rng.uniform([0.1, 0.1], [w - 0.1, h - 0.1])
                if np.min(np.hypot(*(poses - c).T)) < model[i] + 0.05:
                    continue
                if np.any(np.hypot(*(centres[placed] - c).T) < MIN_GAP * (model[placed] + model[i])):
                    continue
                centres[i] = c
                placed.append(i)
                break
            else:
                return None
        return scene_files.scene_dict(name, w, h, start, goal, centres, radii=radii,
                                      robot_radius=r, turn_radius=rho,
                                      keep_inside=bool(rng.random() < WALLS))

    return scene_files.first_kept(draw, scene_files.blocked_and_wrapping(2), name, MAX_TRIES,
                                  f"corridors scene with {n} obstacles")
