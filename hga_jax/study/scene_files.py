"""A generated scene as a scenario mapping and as TOML text, and the obstructed rule.

Shared by the scene generators (:mod:`hga_jax.study.scenes`, :mod:`hga_jax.study.clusters`):
:func:`scene_dict` lays a scene out like a scenario file (metres, degrees, rounded),
:func:`to_toml` writes it in the layout of ``configs/scenarios``, and :func:`blocked`
is the test an obstructed scene must pass. Host code.
"""
from __future__ import annotations

import numpy as np
import tomli_w

from hga_jax.model import collision
from hga_jax.model.path import decode64
from hga_jax.model.scenario import Scenario

ROBOT_RADIUS, TURN_RADIUS = 0.09, 0.15  # the bundled RoboCup robots (m)


def scene_dict(name: str, w: float, h: float, start, goal, centres, radii=None,
               robot_radius: float = ROBOT_RADIUS, turn_radius: float = TURN_RADIUS) -> dict:
    """A scenario mapping (metres, degrees) rounded to 0.1 mm and 0.01 degree; ``radii``:
    per-obstacle physical radii (None: none written, the robot's radius)."""
    r4 = lambda v: round(float(v), 4)  # noqa: E731
    obstacles = ([{"x": r4(x), "y": r4(y)} for x, y in centres] if radii is None else
                 [{"x": r4(x), "y": r4(y), "radius": r4(r)} for (x, y), r in zip(centres, radii)])
    return {
        "name": name,
        "robot": {"radius": r4(robot_radius), "min_turn_radius": r4(turn_radius)},
        "field": {"xmin": 0.0, "xmax": r4(w), "ymin": 0.0, "ymax": r4(h), "keep_inside": True},
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
