"""Scene families with robots that move: ``leaving``, ``crossing``, ``random_moving`` and
their control ``standing``.

RoboCup small-size-league sizes: every robot of radius 0.09 m; per scene the car's
minimum turning radius in [0.15, 0.30] m and its speed in [1, 2] m/s (``[robot] speed``,
docs/model.md "Moving robots"); a field of 4.5 m x 3.0 m (a quarter of the division B
field) whose edges are walls (``keep_inside``) in half of the scenes, drawn per scene.
The start pose near the left edge, the goal pose near the right edge, headings within
60 degrees of +x. Of ``n`` robots, 4 to 6 stand (at most ``n - 1``: at least one moves),
placed as the ``obstructed`` family places them (half of them near the straight
start-goal line, :func:`hga_jax.study.scene_files.place_uniform`); the others move at
constant velocity, each at a speed in :data:`ROBOT_SPEED`, their centres at time 0 inside
the field, at least :data:`~hga_jax.study.scene_files.SPACING` from every other centre
and clear of the start and goal points by their model radius. Where they are placed
uses the standing robots' optimum (the *still path*, :meth:`Scenario.still_scene`):

- ``leaving``: each moving robot on or near the still path (within 0.25 m, between 15 %
  and 95 % of its length), moving away from it (within 30 degrees of the path's normal)
  fast enough to be a model radius and 0.1 m from where it stood by the time the car
  gets there: a certified optimum is likely.
- ``crossing``: each moving robot's straight track crosses the still path (at 60 to 120
  degrees to it, between 20 % and 85 % of its length) within 0.15 s of the moment the
  car gets to that point; the scene is kept only when the still path collides in time
  and :func:`hga_jax.model.exact.solve` knows a path feasible in time (a way round).
- ``random_moving``: moving robots placed uniformly over the field, each in a uniform
  direction.
- ``standing``: the ``random_moving`` scene of the same ``(seed, n, index)`` with every
  velocity 0 (the control: the same robots, standing).

Every family keeps a scene only when the standing robots' optimum exists and the exact
module knows a path feasible in time, so that every scene has a best known path to
measure against; where that optimum keeps clear in time (a certified optimum), only when
a chromosome expresses it, so that a run can hit it. ``random_moving`` keeps a scene only when its
robots, all standing, have an optimum that a chromosome expresses, so that ``standing``
keeps the same draws. Scene ``i`` with ``n`` robots of a family with seed ``s`` depends
on ``(s, n, i)`` alone. Units: metres, degrees, m/s (as in a scenario file). Host code.
"""
from __future__ import annotations

import math

import numpy as np

from hga_jax.model.exact import solve
from hga_jax.model.in_time import clearance
from . import scene_files

KINDS = ("leaving", "crossing", "random_moving", "standing")
STREAM = 0x3071  # a word of the seed: streams apart from the other generators'
FIELD_W, FIELD_H = 4.5, 3.0  # m
ROBOT_RADIUS = 0.09  # m
TURN_RADIUS = (0.15, 0.30)  # m
CAR_SPEED = (1.0, 2.0)  # m/s
ROBOT_SPEED = (0.3, 1.5)  # m/s, every moving robot's
STANDING = (4, 6)  # robots that stand (at most n - 1)
WALLS = 0.5  # probability that the field's edges are kept
NEAR = 0.25  # m: a leaving robot's distance from the still path at time 0, at most
LEAVE_BY = 0.1  # m: a leaving robot is its model radius and this far away by the car's pass
CROSS_JITTER = 0.15  # s: a crossing robot meets the path within this of the car
MAX_TRIES = 400
PLACE_TRIES = 60  # per moving robot


def _round(v: float, places: int = 4) -> float:
    return round(float(v), places)


def _base(rng: np.random.Generator, n: int, name: str) -> dict | None:
    """The standing robots' scene of a draw (robot, field, poses, standing robots) with
    the moving robots' count in ``"_moving"``, or None when the field is too full."""
    w, h = FIELD_W, FIELD_H
    rho = rng.uniform(*TURN_RADIUS)
    speed = rng.uniform(*CAR_SPEED)
    walls = bool(rng.random() < WALLS)
    still = min(int(rng.integers(STANDING[0], STANDING[1] + 1)), n - 1)
    start = [rng.uniform(0.3, 0.6), rng.uniform(0.4, h - 0.4), rng.uniform(-60, 60)]
    goal = [rng.uniform(w - 0.6, w - 0.3), rng.uniform(0.4, h - 0.4), rng.uniform(-60, 60)]
    try:
        centres = scene_files.place_uniform(rng, still, w, h, start, goal, True)
    except RuntimeError:
        return None
    d = scene_files.scene_dict(name, w, h, start, goal, centres, robot_radius=ROBOT_RADIUS,
                               turn_radius=rho, keep_inside=walls)
    d["robot"]["speed"] = _round(speed, 3)
    d["_moving"] = n - still
    return d


def _still_path(d: dict, name: str):
    """The standing robots' optimum of ``d`` as ``(x, y, t)`` samples every 2 cm and its
    length, or None when it does not exist (or the scene does not load)."""
    from hga_jax.host.config import scenario_from_dict

    try:
        sc = scenario_from_dict({k: v for k, v in d.items() if not k.startswith("_")}, name)
    except ValueError:
        return None
    opt = solve(sc)
    if not opt.feasible:
        return None
    x, y, t = clearance.sample(opt.segments, sc.speed, 0.02)
    return x, y, t, float(opt.length)


def _clear(c, big_r: float, taken: list, ends) -> bool:
    """Whether a centre ``c`` (model radius ``big_r``) at time 0 is inside the field, at
    least SPACING from the centres ``taken`` and clear of the start and goal points."""
    if not (0.2 <= c[0] <= FIELD_W - 0.2 and 0.2 <= c[1] <= FIELD_H - 0.2):
        return False
    if np.min(np.hypot(*(ends - c).T)) < big_r + 0.05:
        return False
    return not taken or np.min(np.hypot(*(np.asarray(taken) - c).T)) >= scene_files.SPACING


def _at(path, u: float):
    """The still path's point, unit tangent and time at fraction ``u`` of its length."""
    x, y, t, length = path
    s = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])
    i = int(np.clip(np.searchsorted(s, u * length), 1, len(x) - 1))
    tx, ty = x[i] - x[i - 1], y[i] - y[i - 1]
    norm = math.hypot(tx, ty) or 1.0
    return np.array([x[i], y[i]]), np.array([tx, ty]) / norm, float(t[i])


def _rotate(v, angle: float):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _movers(kind: str, rng: np.random.Generator, d: dict, path, count: int):
    """``count`` moving robots ``(centre, velocity)`` of ``kind``, or None."""
    rho = d["robot"]["min_turn_radius"]
    big_r = max(rho, 2 * ROBOT_RADIUS)
    ends = np.array([[d["start"]["x"], d["start"]["y"]], [d["goal"]["x"], d["goal"]["y"]]])
    taken = [[o["x"], o["y"]] for o in d["obstacles"]]
    out = []
    for _ in range(count):
        for _ in range(PLACE_TRIES):
            v = rng.uniform(*ROBOT_SPEED)
            if kind == "random_moving":
                c = rng.uniform([0.2, 0.2], [FIELD_W - 0.2, FIELD_H - 0.2])
                a = rng.uniform(-math.pi, math.pi)
                vel = v * np.array([math.cos(a), math.sin(a)])
            elif kind == "leaving":
                p, tangent, t = _at(path, rng.uniform(0.15, 0.95))
                normal = np.array([-tangent[1], tangent[0]])
                off = rng.uniform(-NEAR, NEAR)
                side = math.copysign(1.0, off) if off != 0 else 1.0
                c = p + off * normal
                need = (big_r + LEAVE_BY) / (max(t, 1e-9) * math.cos(math.radians(30)))
                if need > ROBOT_SPEED[1]:
                    continue
                v = rng.uniform(max(ROBOT_SPEED[0], need), ROBOT_SPEED[1])
                vel = v * _rotate(side * normal, math.radians(rng.uniform(-30, 30)))
            else:  # crossing
                p, tangent, t = _at(path, rng.uniform(0.2, 0.85))
                t = max(0.0, t + rng.uniform(-CROSS_JITTER, CROSS_JITTER))
                turn = math.radians(rng.uniform(60, 120)) * rng.choice([-1.0, 1.0])
                vel = v * _rotate(tangent, turn)
                c = p - vel * t
            if _clear(c, big_r, taken, ends):
                taken.append(list(c))
                out.append((c, vel))
                break
        else:
            return None
    return out


def draw(kind: str, rng: np.random.Generator, n: int, name: str) -> dict | None:
    """One candidate scene of ``kind`` (a moving kind; not yet kept), or None."""
    d = _base(rng, n, name)
    if d is None:
        return None
    path = _still_path(d, name)
    if path is None:
        return None
    movers = _movers(kind, rng, d, path, d.pop("_moving"))
    if movers is None:
        return None
    for c, vel in movers:
        d["obstacles"].append({"x": _round(c[0]), "y": _round(c[1]),
                               "vx": _round(vel[0]), "vy": _round(vel[1])})
    return d


def kept(kind: str):
    """The keep rule of ``kind`` (module doc): a test of a loaded scenario."""
    import dataclasses

    def keep(sc) -> bool:
        if not sc.has_motion:  # rounded to a standstill: not a scene of the family
            return False
        bound = solve(sc.still_scene())
        if not bound.feasible:
            return False
        certified = not clearance.segment_hits(sc, bound.segments)
        if certified and not bound.expressible:  # an optimum no chromosome can hit
            return False
        if kind == "crossing" and certified:
            return False
        if not certified and not solve(sc).feasible:  # no path feasible in time known
            return False
        if kind == "random_moving":  # its standing control's optimum: hittable too
            still = solve(dataclasses.replace(sc, velocities=None))
            return bool(still.feasible and still.expressible)
        return True

    return keep


def generate(kind: str, n: int, seed: int, index: int, name: str,
             density: float | None = None, car: str | None = None) -> dict:
    """Scene ``index`` with ``n`` robots of a ``kind`` family (:data:`KINDS`) with
    ``seed``: a scenario mapping (metres, degrees, m/s); ``density`` must be None.
    ``car``: the scenes' car (default the forward car), set before the keep rule."""
    if kind not in KINDS:
        raise ValueError(f"kind: must be one of {', '.join(KINDS)}, got {kind!r}")
    if density is not None:
        raise ValueError(f"{kind} scenes take no density (their field is fixed)")
    if n < 2:
        raise ValueError(f"{kind} scenes need at least 2 robots (one standing, one moving)")
    if kind == "standing":  # the random_moving draw, every robot standing
        d = generate("random_moving", n, seed, index, name, None, car)
        for o in d["obstacles"]:
            o.pop("vx", None)
            o.pop("vy", None)
        return d
    rng = np.random.default_rng([seed, n, index, STREAM, KINDS.index(kind)])

    def candidate():
        d = draw(kind, rng, n, name)
        if d is not None and car is not None:
            d["robot"]["car"] = car
        return d

    return scene_files.first_kept(candidate, kept(kind), name, MAX_TRIES,
                                  f"{kind} scene with {n} robots")
