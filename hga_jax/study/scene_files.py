"""A generated scene as a scenario mapping and as TOML text, and the obstructed rule.

Shared by the scene generators (:mod:`hga_jax.study.scenes`, :mod:`hga_jax.study.clusters`):
:func:`scene_dict` lays a scene out like a scenario file (metres, degrees, rounded),
:func:`to_toml` writes it in the layout of ``configs/scenarios``, :func:`blocked`
is the test an obstructed scene must pass, and :func:`place_uniform` the RoboCup
placement of ``clutter``, ``obstructed`` and ``loops`` obstacles. Host code.
"""
from __future__ import annotations

import numpy as np
import tomli_w

from hga_jax.model import collision
from hga_jax.model.path import decode64
from hga_jax.model.scenario import Scenario

ROBOT_RADIUS, TURN_RADIUS = 0.09, 0.15  # the bundled RoboCup robots (m)
MODEL_RADIUS = 0.18
FIELD_W, FIELD_H = 2.8, 2.3
SPACING = 0.30  # minimum distance between obstacle centres (m)


def scene_dict(name: str, w: float, h: float, start, goal, centres, radii=None,
               robot_radius: float = ROBOT_RADIUS, turn_radius: float = TURN_RADIUS,
               keep_inside: bool = True) -> dict:
    """A scenario mapping (metres, degrees) rounded to 0.1 mm and 0.01 degree; ``radii``:
    per-obstacle physical radii (None: none written, the robot's radius); ``keep_inside``:
    whether the field's edges are walls."""
    r4 = lambda v: round(float(v), 4)  # noqa: E731
    obstacles = ([{"x": r4(x), "y": r4(y)} for x, y in centres] if radii is None else
                 [{"x": r4(x), "y": r4(y), "radius": r4(r)} for (x, y), r in zip(centres, radii)])
    return {
        "name": name,
        "robot": {"radius": r4(robot_radius), "min_turn_radius": r4(turn_radius)},
        "field": {"xmin": 0.0, "xmax": r4(w), "ymin": 0.0, "ymax": r4(h), "keep_inside": keep_inside},
        "start": {"x": r4(start[0]), "y": r4(start[1]), "heading_deg": round(start[2], 2)},
        "goal": {"x": r4(goal[0]), "y": r4(goal[1]), "heading_deg": round(goal[2], 2)},
        "obstacles": obstacles,
    }


def to_toml(d: dict, comment: str = "") -> str:
    """TOML text (``tomli_w``) of a scenario mapping, ``comment`` lines first as ``#``
    comments, in the layout of ``configs/scenarios``: each obstacle its own
    ``[[obstacles]]`` table (``tomli_w`` alone writes short ones as one inline array).
    The text is part of a cell's identity (:func:`~hga_jax.study.store.cell_id`)."""
    head = "".join(f"# {line}\n" for line in comment.splitlines())
    rest = tomli_w.dumps({k: v for k, v in d.items() if k != "obstacles"})
    return head + rest + "".join("\n[[obstacles]]\n" + tomli_w.dumps(o) for o in d["obstacles"])


def blocked(sc: Scenario) -> bool:
    """True when the straight start-goal line and all four direct Dubins paths collide."""
    (ax, ay), (bx, by) = sc.start[:2], sc.goal[:2]
    line_hits = collision.segment_hits(ax, ay, bx, by, sc.centres[:, 0], sc.centres[:, 1],
                                       sc.model_radii, 0.0)
    if not line_hits.any():
        return False
    ends = np.array([[s, g] for s in (-1, 1) for g in (-1, 1)])
    labels = np.zeros((4, sc.n + 2), np.int32)
    labels[:, 0], labels[:, -1] = ends[:, 0], ends[:, 1]
    perm = np.tile(np.arange(sc.n, dtype=np.int32), (4, 1))
    return bool(np.all(decode64(sc, perm, labels).violations > 0))


def blocked_and_wrapping(touches: int):
    """The test the held-out generators keep a scenario by: it is :func:`blocked`, and
    its exact optimum is feasible, expressible and touches at least ``touches``
    obstacles (a ``kept`` for :func:`first_kept`)."""
    def kept(sc: Scenario) -> bool:
        from hga_jax.model.exact import solve

        if not blocked(sc):
            return False
        opt = solve(sc)
        return bool(opt.feasible and opt.expressible and len(opt.touched) >= touches)

    return kept


def place_uniform(rng, n: int, w: float, h: float, start, goal, obstructed: bool) -> np.ndarray:
    """``n`` centres at least SPACING apart, clear of the start and goal points."""
    keep = np.array([start[:2], goal[:2]])
    out: list[np.ndarray] = []
    near_line = n // 2 if obstructed else 0
    tries = 0
    while len(out) < n:
        tries += 1
        if tries > 200 * n:
            raise RuntimeError("field too crowded")
        if len(out) < near_line:
            t = rng.uniform(0.15, 0.85)
            d = keep[1] - keep[0]
            normal = np.array([-d[1], d[0]]) / np.hypot(*d)
            c = keep[0] + t * d + rng.normal(0.0, 0.2) * normal
        else:
            c = np.array([rng.uniform(0.2, w - 0.2), rng.uniform(0.2, h - 0.2)])
        if not (0.2 <= c[0] <= w - 0.2 and 0.2 <= c[1] <= h - 0.2):
            continue
        if np.min(np.hypot(*(keep - c).T)) < MODEL_RADIUS + 0.1:
            continue
        if out and np.min(np.hypot(*(np.array(out) - c).T)) < SPACING:
            continue
        out.append(c)
    return np.array(out).reshape(n, 2)


def first_kept(draw, kept, name: str, tries: int, what: str) -> dict:
    """The first scene mapping that ``draw()`` makes (None: nothing placed) which loads as
    a scenario named ``name`` (a pose too close to an obstacle or a wall is drawn again)
    and is ``kept(scenario)``; ``RuntimeError`` naming ``what`` after ``tries`` draws."""
    from hga_jax.host.config import scenario_from_dict

    for _ in range(tries):
        d = draw()
        if d is None:
            continue
        try:
            sc = scenario_from_dict(d, name)
        except ValueError:
            continue
        if kept(sc):
            return d
    raise RuntimeError(f"no {what} found in {tries} tries")
