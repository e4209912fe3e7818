"""Scene families with degenerate geometry, whole-scene transforms and random chromosomes.

Test helpers (host code). Scenes are mappings laid out like scenario files (metres,
degrees), loaded with :func:`hga_jax.scenario_from_dict`, so every scene is valid.

Families:
- ``grid``: centres, poses and field on a 0.09 m grid, headings multiples of 45
  degrees, robot radius 0.09 and rho in {0.09, 0.135, 0.18, 0.27}: model circles
  that touch each other or the turning circles, segment ends on other circles,
  half-circle arcs.
- ``overlapping``: clusters of obstacles whose model circles overlap.
- ``degenerate``: constructed cases (goal on a start turning circle, U-turns,
  obstacles touching a turning circle or each other, obstacles tangent to the start
  heading line), then rotated and translated by random amounts so that each
  degeneracy holds only up to rounding.
- ``random``: uniform scenes.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np

from hga_jax import ConfigError, scenario_from_dict

FAMILIES = ("grid", "overlapping", "degenerate", "random")
STEP = 0.09
FIELD = {"xmin": 0.0, "xmax": 2.7, "ymin": 0.0, "ymax": 2.25}


def _pose(x, y, h):
    return {"x": float(x), "y": float(y), "heading_deg": float(h)}


def _grid(rng) -> dict[str, Any]:
    rho = float(rng.choice([0.09, 0.135, 0.18, 0.27]))
    cells = [(i, j) for i in range(2, 29) for j in range(2, 24)]
    n = int(rng.integers(1, 6))
    # A compact block of cells so that circles meet.
    ci, cj = rng.integers(6, 24), rng.integers(6, 19)
    near = [(i, j) for i, j in cells if abs(i - ci) <= 8 and abs(j - cj) <= 8]
    pick = rng.choice(len(near), size=n + 2, replace=False)
    pts = [near[k] for k in pick]
    scene = {
        "name": "grid", "robot": {"radius": 0.09, "min_turn_radius": rho},
        "start": _pose(pts[0][0] * STEP, pts[0][1] * STEP, 45 * rng.integers(8)),
        "goal": _pose(pts[1][0] * STEP, pts[1][1] * STEP, 45 * rng.integers(8)),
        "obstacles": [{"x": i * STEP, "y": j * STEP} for i, j in pts[2:]],
    }
    if rng.random() < 0.6:
        scene["field"] = dict(FIELD, keep_inside=bool(rng.random() < 0.8))
    return scene


def _overlapping(rng) -> dict[str, Any]:
    n = int(rng.integers(2, 7))
    centre = rng.uniform(0.8, 1.8, 2)
    obstacles = [{"x": float(x), "y": float(y)} for x, y in centre + rng.normal(0, 0.15, (n, 2))]
    return {
        "name": "overlapping", "robot": {"radius": 0.09, "min_turn_radius": float(rng.uniform(0.08, 0.3))},
        "start": _pose(*rng.uniform(0, 0.5, 2), rng.uniform(-180, 180)),
        "goal": _pose(*rng.uniform(2.1, 2.6, 2), rng.uniform(-180, 180)),
        "obstacles": obstacles,
    }


def _degenerate(rng) -> dict[str, Any]:
    r, rho = 0.09, float(rng.choice([0.09, 0.135, 0.18, 0.25]))
    big_r = max(rho, 2 * r)
    sx, sy, th = 0.0, 0.0, 0.0  # the start pose before the final rotation and translation
    side = float(rng.choice([-1.0, 1.0]))  # start circle used for the construction
    scx, scy = 0.0, -side * rho  # its centre (CW +1 on the right, CCW -1 on the left)
    kind = rng.integers(4)
    if kind == 0:  # goal on the start circle, travelling along it or against it
        a = rng.choice([math.pi / 2, math.pi, 3 * math.pi / 2, rng.uniform(0, 2 * math.pi)])
        ang = math.atan2(sy - scy, sx - scx) - side * a
        gx, gy = scx + rho * math.cos(ang), scy + rho * math.sin(ang)
        gh = math.degrees(-side * a) + (180.0 if rng.random() < 0.3 else 0.0)
    elif kind == 1:  # U-turn: half a circle back
        gx, gy, gh = 0.0, -2 * side * rho, 180.0
    else:
        gx, gy, gh = rng.uniform(0.8, 2.0), rng.uniform(-1, 1), rng.uniform(-180, 180)
    obstacles = []
    for _ in range(int(rng.integers(1, 5))):
        how = rng.integers(4)
        if how == 0:  # touching the start circle from outside
            a = rng.uniform(0, 2 * math.pi)
            obstacles.append((scx + (rho + big_r) * math.cos(a), scy + (rho + big_r) * math.sin(a)))
        elif how == 1:  # tangent to the start heading line
            obstacles.append((rng.uniform(0.4, 1.5), float(rng.choice([-1, 1])) * big_r))
        elif how == 2 and obstacles:  # touching the previous obstacle
            a = rng.uniform(0, 2 * math.pi)
            px, py = obstacles[-1]
            obstacles.append((px + 2 * big_r * math.cos(a), py + 2 * big_r * math.sin(a)))
        else:  # in line with the U-turn / across the goal's path
            obstacles.append((gx + rng.uniform(-0.1, 0.1), gy + float(rng.choice([-1, 1])) * (
                2 * big_r + rng.choice([0.0, 0.5 * rho]))))
    # Rotate and translate everything by random amounts (rounding breaks each tie a little).
    phi = rng.uniform(-math.pi, math.pi)
    tx, ty = rng.uniform(0.8, 1.8, 2)

    def move(x, y):
        return (tx + x * math.cos(phi) - y * math.sin(phi), ty + x * math.sin(phi) + y * math.cos(phi))

    deg = math.degrees(phi)
    return {
        "name": "degenerate", "robot": {"radius": r, "min_turn_radius": rho},
        "start": _pose(*move(sx, sy), th + deg), "goal": _pose(*move(gx, gy), gh + deg),
        "obstacles": [dict(zip("xy", move(x, y))) for x, y in obstacles],
    }


def _random(rng) -> dict[str, Any]:
    n = int(rng.integers(0, 9))
    scene = {
        "name": "random", "robot": {"radius": 0.09, "min_turn_radius": float(rng.uniform(0.05, 0.4))},
        "start": _pose(*rng.uniform(0.2, 2.5, 2), rng.uniform(-180, 180)),
        "goal": _pose(*rng.uniform(0.2, 2.0, 2), rng.uniform(-180, 180)),
        "obstacles": [{"x": float(x), "y": float(y), "radius": float(q)} for x, y, q in zip(
            *rng.uniform(0.1, 2.6, (2, n)), rng.uniform(0.03, 0.2, n))],
    }
    if rng.random() < 0.3:
        scene["field"] = dict(FIELD, keep_inside=True)
    return scene


MAKERS = {"grid": _grid, "overlapping": _overlapping, "degenerate": _degenerate, "random": _random}


def scenes(family: str, seed: int, count: int) -> list[dict[str, Any]]:
    """``count`` valid scenes of ``family`` (mappings), drawn from ``seed``."""
    rng = np.random.default_rng([seed, FAMILIES.index(family)])
    out = []
    while len(out) < count:
        d = MAKERS[family](rng)
        try:
            scenario_from_dict(d)
        except ConfigError:
            continue
        out.append(d)
    return out


def chromosomes(rng, n: int, count: int, p_zero: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Random ``(perm, labels)`` batches: obstacle labels 0 with probability ``p_zero``."""
    perm = np.argsort(rng.random((count, n)), axis=1).astype(np.int32)
    inner = rng.choice([-1, 0, 1], size=(count, n), p=[(1 - p_zero) / 2, p_zero, (1 - p_zero) / 2])
    ends = rng.choice([-1, 1], size=(count, 2))
    return perm, np.concatenate([ends[:, :1], inner, ends[:, 1:]], axis=1).astype(np.int32)


# Whole-scene transforms. Each returns the new mapping and whether labels flip (mirror).

def _map_points(scene: dict[str, Any], fn, dh, flip: bool) -> dict[str, Any]:
    out = {k: v for k, v in scene.items() if k not in ("start", "goal", "obstacles", "field")}
    for key in ("start", "goal"):
        p = scene[key]
        x, y = fn(p["x"], p["y"])
        h = -p["heading_deg"] if flip else p["heading_deg"]
        out[key] = _pose(x, y, h + dh)
    out["obstacles"] = [dict(o, **dict(zip("xy", fn(o["x"], o["y"])))) for o in scene.get("obstacles", [])]
    if "field" in scene:
        f = scene["field"]
        xs, ys = zip(*(fn(x, y) for x in (f["xmin"], f["xmax"]) for y in (f["ymin"], f["ymax"])))
        out["field"] = dict(f, xmin=min(xs), xmax=max(xs), ymin=min(ys), ymax=max(ys))
    return out


def rotate(scene: dict[str, Any], deg: float, about=(0.0, 0.0)) -> dict[str, Any]:
    """Rotate the whole scene by ``deg`` degrees about ``about`` (quarter turns are exact)."""
    quarter = deg % 90 == 0
    c, s = (round(math.cos(math.radians(deg))), round(math.sin(math.radians(deg)))) if quarter else (
        math.cos(math.radians(deg)), math.sin(math.radians(deg)))
    ox, oy = about

    def fn(x, y):
        x, y = x - ox, y - oy
        return ox + c * x - s * y, oy + s * x + c * y

    return _map_points(scene, fn, deg, False)


def translate(scene: dict[str, Any], dx: float, dy: float) -> dict[str, Any]:
    return _map_points(scene, lambda x, y: (x + dx, y + dy), 0.0, False)


def mirror(scene: dict[str, Any]) -> dict[str, Any]:
    """Mirror in the x axis (y -> -y): headings negate, CW and CCW swap."""
    return _map_points(scene, lambda x, y: (x, -y), 0.0, True)
