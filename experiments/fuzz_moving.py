"""Fuzz of the tests in time among robots that move: no check calls a colliding path feasible.

Random scenes of 5-9 robots (radius 0.09 m plus 0.06-0.12 m obstacles; min turning
radius 0.15-0.3 m; the car's speed 1-2 m/s), some of them moving at 0.3-1.5 m/s on
tracks that cross the way from the start to the goal around the time the car gets
there, and random chromosomes of the three car models (the tight rope, free turns,
the Reeds–Shepp car; leg genes drawn with the model's own weights). Each chromosome is
judged by

- ``float32``: the search's fitness (:func:`hga_jax.model.fitness.evaluate` on the model's
  float32 search arrays, jitted): feasible when it counts no violation;
- ``float64``: the float64 decoder (:func:`hga_jax.model.path.decode64`);
- ``host``: the float64 path check of the result files (every violation of
  :func:`hga_jax.model.path.evaluate_path` and :func:`hga_jax.model.in_time.clearance.segment_hits`
  over its segments: feasible when neither finds one);

and every path that one of them calls feasible is measured by the independent dense
check: :func:`clearance`, each moving robot's least clearance ``|car(t) - O - t V| - R``
along the float64 path's segments, bracketed rigorously (samples every ``SPACING`` m,
then branch and bound on the Lipschitz bound of the distance; the bracket is at most
``BRACKET`` m wide). A *false feasible* is a path that a check calls feasible while the
dense check shows it closer than ``R - margin`` to a moving robot at the same time:
margin ``1e-6`` m for the float64 checks (their tolerance is 1e-7 m) and ``F32_MARGIN``
for the float32 fitness (whose tolerance is 1e-5 m, its paths' points and times being
float32 roundings of the float64 path's). There must be none.

Usage (from the repository root)::

    python3 experiments/fuzz_moving.py [--chromosomes 100000] [--seed 0] [--rows 2000] [--quiet]
        [--models tight-rope free reeds-shepp]

prints, per car model: chromosomes checked, how many each check calls feasible, the
false feasibles (must be 0), the closest approach among the feasible paths and the
time taken; exits 1 if there is a false feasible. ``tests/test_moving.py`` runs the
same fuzz (a small one in the default lane, 100,000 chromosomes marked slow).
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

MODELS = ("tight-rope", "free", "reeds-shepp")
"""The three car models: the model's name (``turns``) and, for the last, its car."""
SPACING = 1e-3
"""Metres between the dense check's first samples along the path."""
BRACKET = 1e-7
"""The dense check brackets each robot's least clearance to within this (m), and
decides exactly whether it is below each margin of :data:`MARGINS`."""
F64_MARGIN = 1e-6
"""A float64 check's false feasible: closer than ``R - F64_MARGIN`` (m)."""
F32_MARGIN = 2e-5
"""The float32 fitness's false feasible: closer than ``R - F32_MARGIN`` (m): its
tolerance (1e-5 m) and as much again for the float32 rounding of the path's points and
of the car's time (a few metres driven at 1-2 m/s; a robot at 1.5 m/s moves 1.5 um per
us of time error)."""
ROBOT_RADIUS = 0.09


# ---------------------------------------------------------------------------
# Scenes and chromosomes.

def scene_dict(rng: np.random.Generator, car: str = "dubins", n: int | None = None,
               m: int | None = None) -> dict:
    """A scenario mapping (:func:`hga_jax.scenario_from_dict`) of ``n`` robots (5-9 when
    None), ``m`` of them (1 to ``n`` when None) moving on a track that crosses the way from
    the start to the goal near the time the car could be there."""
    n = int(rng.integers(5, 10)) if n is None else n
    m = int(rng.integers(1, n + 1)) if m is None else m
    rho = float(rng.uniform(0.15, 0.3))
    speed = float(rng.uniform(1.0, 2.0))
    start = np.array([0.3, rng.uniform(0.5, 1.8)])
    goal = np.array([2.7, rng.uniform(0.5, 1.8)])
    way = goal - start
    normal = np.array([-way[1], way[0]]) / np.linalg.norm(way)
    moving = np.zeros(n, bool)
    moving[rng.permutation(n)[:m]] = True
    obstacles = []
    for k in range(n):
        item: dict[str, Any] = {"radius": float(rng.uniform(0.06, 0.12))}
        if moving[k]:
            meet = start + rng.uniform(0.1, 0.9) * way + rng.normal(0.0, 0.35) * normal
            when = float(np.linalg.norm(meet - start)) / speed * rng.uniform(0.6, 2.0)
            v = rng.uniform(0.3, 1.5)
            a = rng.uniform(0.0, 2.0 * math.pi)
            vel = v * np.array([math.cos(a), math.sin(a)])
            at0 = meet - when * vel
            item.update(x=float(at0[0]), y=float(at0[1]), vx=float(vel[0]), vy=float(vel[1]))
        else:
            item.update(x=float(rng.uniform(0.6, 2.4)), y=float(rng.uniform(0.1, 2.2)))
        obstacles.append(item)
    robot = {"radius": ROBOT_RADIUS, "min_turn_radius": rho, "speed": speed}
    if car != "dubins":
        robot["car"] = car
    return {"name": "moving", "robot": robot,
            "start": {"x": float(start[0]), "y": float(start[1]),
                      "heading_deg": float(rng.uniform(-180.0, 180.0))},
            "goal": {"x": float(goal[0]), "y": float(goal[1]),
                     "heading_deg": float(rng.uniform(-180.0, 180.0))},
            "obstacles": obstacles}


def scene(rng: np.random.Generator, car: str = "dubins", n: int | None = None,
          m: int | None = None):
    """``(scenario, mapping)``: a random moving scene (:func:`scene_dict`), drawn again
    until the loader takes it (no start inside a robot at time 0, no goal inside a standing
    robot)."""
    from hga_jax import scenario_from_dict
    from hga_jax.errors import ConfigError

    while True:
        d = scene_dict(rng, car, n, m)
        try:
            return scenario_from_dict(d, "moving"), d  # (nothing solved until its arrays)
        except ConfigError:
            continue


EXTRA = ("wrap_moving", "placed")
"""Keys of the fuzz's scene mappings beside a scenario file's: how a chromosome wraps a
moving robot (``Scenario.wrap_moving``) and the moments its circle stands in the tables
(``Scenario.placement_times``), when they are given rather than solved for."""


def build(d: dict):
    """The scenario of a fuzz scene mapping (a scenario file's, with :data:`EXTRA`)."""
    from hga_jax import scenario_from_dict

    sc = scenario_from_dict({k: v for k, v in d.items() if k not in EXTRA}, d.get("name", "fuzz"))
    if "wrap_moving" in d:
        sc = dataclasses.replace(sc, wrap_moving=d["wrap_moving"])
    if "placed" in d:  # the moments given: kept with the scenario where it keeps its own
        times = np.asarray(d["placed"], float)
        got = sc.cached("placement times", lambda: times)
        if got is not times:
            raise RuntimeError("the scenario's placement times are no longer kept under "
                               "'placement times': update fuzz_moving.build")
    return sc


MODES = ("at-pass", "given", "never", "at-best")
"""How the fuzz's scenes place moving robots' circles, in turn: ``wrap_moving`` as named,
or ``"given"``: at random moments (0 to 3 s) given to the scenario (:func:`build`)."""
SLOW_MODES = {"reeds-shepp": ("at-best",)}
"""Left out per car model: the Reeds–Shepp car's ``at-best`` placement solves the scene
in time before its arrays exist (minutes on some scenes)."""


def car_of(model: str) -> str:
    return "reeds-shepp" if model == "reeds-shepp" else "dubins"


def chromosomes(rng: np.random.Generator, model: str, n: int, rows: int):
    """``rows`` random chromosomes of ``model``: ``(perm, labels, legs)`` (legs None for
    the tight rope; drawn with the model's gene weights otherwise). Each row touches an
    obstacle with a probability drawn in 0.05-0.35, so short and long paths both occur."""
    from hga_jax.model import car_model

    perm = np.argsort(rng.random((rows, n)), axis=1).astype(np.int32)
    touch = rng.uniform(0.05, 0.35, (rows, 1))
    u = rng.random((rows, n + 2))
    labels = np.where(u < touch / 2, -1, np.where(u < touch, 1, 0)).astype(np.int32)
    labels[:, [0, -1]] = rng.choice(np.array([-1, 1], np.int32), (rows, 2))
    genes = car_model.get(model).genes
    if not genes:
        return perm, labels, None
    w = np.asarray(genes[0].weights, float)
    legs = rng.choice(w.size, size=(rows, n + 2), p=w / w.sum()).astype(np.int32)
    return perm, labels, legs


# ---------------------------------------------------------------------------
# The dense check.

def _points(seg: dict, u: np.ndarray):
    """The segment's points at fractions ``u`` of its length (float64)."""
    if seg["type"] == "line":
        (x0, y0), (x1, y1) = seg["start"], seg["end"]
        return x0 + (x1 - x0) * u, y0 + (y1 - y0) * u
    (cx, cy), r = seg["center"], float(seg["radius"])
    a = float(seg["start_angle"]) + float(seg["sweep"]) * u
    return cx + r * np.cos(a), cy + r * np.sin(a)


def clearance(scenario: Any, segments: list[dict], spacing: float = SPACING,
              bracket: float = BRACKET, decide: tuple[float, ...] = ()
              ) -> tuple[np.ndarray, np.ndarray]:
    """``(lower, upper)`` (m), per moving robot (in the order of ``scenario.moving``): its
    least clearance ``|car(t) - O - t V| - R`` along the path, bracketed rigorously.

    ``upper`` is the clearance at a point of the path (the car there at that time): the
    path comes at least that close. ``lower`` is a proven bound below: on each segment,
    of length ``len`` and entered at time ``t0``, the distance ``f(u)`` at fraction ``u``
    changes by at most ``L = len (1 + |V| / speed)`` per unit of ``u`` (the car moves
    ``len`` m, the robot ``len |V| / speed`` m), so over a sampled interval ``[a, b]``
    ``f >= (f(a) + f(b)) / 2 - L (b - a) / 2``. Intervals whose bound is not above the
    best sample by ``bracket`` are cut in 16 and sampled again, until every bound is; and
    so are those whose bound is below a clearance ``-margin`` of ``decide`` that the best
    sample is not below, so that the bracket decides each of them exactly (but for an
    interval that cannot be cut further, never seen). Independent of
    :mod:`hga_jax.model.in_time.clearance`."""
    idx = np.flatnonzero(scenario.moving)
    vel = np.asarray(scenario.velocities, float).reshape(scenario.n, 2)[idx]
    cen = np.asarray(scenario.centres, float)[idx]
    big_r = np.asarray(scenario.model_radii, float)[idx]
    speed = float(scenario.speed)
    timed = [ts for ts in _timed(segments, speed) if ts.length > 0.0]
    if not timed:  # the car stays at the start at time 0
        d = np.hypot(scenario.start[0] - cen[:, 0], scenario.start[1] - cen[:, 1]) - big_r
        return d, d
    m = idx.size
    lip = 1.0 + np.hypot(vel[:, 0], vel[:, 1]) / speed  # per metre driven
    best = np.full(m, np.inf)
    low = np.full(m, np.inf)  # the least bound of the intervals settled so far
    pending = []  # per segment: robot rows j, intervals [a, b], f at their ends
    for ts in timed:
        k = max(1, int(math.ceil(ts.length / spacing)))
        u = np.arange(k + 1) / k
        f = _dist(ts, u[None], cen, vel)  # (m, k + 1)
        best = np.minimum(best, f.min(axis=1))
        j = np.repeat(np.arange(m), k)
        pending.append((ts, j, np.tile(u[:-1], m), np.tile(u[1:], m), f[:, :-1].ravel(),
                        f[:, 1:].ravel()))
    levels = np.sort(-np.asarray(decide, float))  # clearances to decide, lowest first
    for _ in range(40):
        # per robot: the highest level the best sample is not below (-inf: none)
        target = np.full(m, -np.inf)
        for lv in levels:  # the highest level not above it wins
            target = np.where(best - big_r >= lv, lv, target)
        goal = np.maximum(best - bracket, target + big_r)
        cut = []
        for ts, j, a, b, fa, fb in pending:
            lb = 0.5 * (fa + fb) - 0.5 * ts.length * lip[j] * (b - a)
            keep = (lb < goal[j]) & (b - a > 1e-15)
            np.minimum.at(low, j[~keep], lb[~keep])
            if keep.any():
                j, a, b = j[keep], a[keep], b[keep]
                u = a[:, None] + (b - a)[:, None] * (np.arange(17) / 16.0)[None]
                f = _dist(ts, u, cen[j], vel[j])  # (kept, 17)
                np.minimum.at(best, j, f.min(axis=1))
                jj = np.repeat(j, 16)
                cut.append((ts, jj, u[:, :-1].ravel(), u[:, 1:].ravel(), f[:, :-1].ravel(),
                            f[:, 1:].ravel()))
        pending = cut
        if not pending:
            break
    for ts, j, a, b, fa, fb in pending:  # not settled (never seen): what is left bounds it
        np.minimum.at(low, j, 0.5 * (fa + fb) - 0.5 * ts.length * lip[j] * (b - a))
    return np.minimum(low, best) - big_r, best - big_r


class _Timed(NamedTuple):
    segment: dict
    t0: float
    t1: float
    length: float


def _timed(segments: list[dict], speed: float) -> list[_Timed]:
    """Each segment with the car's times on it: arc length so far over the speed."""
    out, s = [], 0.0
    for seg in segments:
        if seg["type"] == "arc":
            length = float(seg["radius"]) * abs(float(seg["sweep"]))
        else:
            length = math.hypot(seg["end"][0] - seg["start"][0], seg["end"][1] - seg["start"][1])
        out.append(_Timed(seg, s / speed, (s + length) / speed, length))
        s += length
    return out


def _dist(ts, u, centre, vel):
    """Distances between the car at fractions ``u`` of segment ``ts`` and robots of
    centres ``centre`` (at time 0) and velocities ``vel`` (..., 2), broadcast."""
    x, y = _points(ts.segment, u)
    t = ts.t0 + (ts.t1 - ts.t0) * u
    return np.hypot(x - (centre[..., 0:1] + vel[..., 0:1] * t),
                    y - (centre[..., 1:2] + vel[..., 1:2] * t))


# ---------------------------------------------------------------------------
# The fuzz.

SHAPES = ((9, 5), (5, 2), (7, 7), (8, 1), (6, 3))
"""``(robots, moving robots)`` of the fuzz's scenes: a few shapes, so that the programs
compile once per shape and model (their arrays' shapes follow both)."""
CHECKS = ("float32", "float64", "host")
MARGINS = {"float32": F32_MARGIN, "float64": F64_MARGIN, "host": F64_MARGIN}


@dataclass
class Tally:
    """One car model's counts (module doc)."""

    model: str
    checked: int = 0
    scenes: int = 0
    feasible: dict = field(default_factory=lambda: dict.fromkeys(CHECKS, 0))
    false: dict = field(default_factory=lambda: dict.fromkeys(CHECKS, 0))
    undecided: dict = field(default_factory=lambda: dict.fromkeys(CHECKS, 0))
    in_tolerance: int = 0  # float32 feasible, closer than R - 1e-6 m but not R - F32_MARGIN
    closest: dict = field(default_factory=lambda: dict.fromkeys(CHECKS, math.inf))
    measured: int = 0  # paths the dense check measured (clear of the standing robots)
    colliding: int = 0  # of those, how many it shows closer than R - 1e-6 to a moving robot
    boundary: int = 0  # of those, how many come within 0.1 mm of R (either side)
    sampled_below: int = 0  # closest_approach(spacing) below the bracket: never
    seconds: float = 0.0
    examples: list = field(default_factory=list)  # (scene, perm, labels, legs, check, clearance)


BLOCK = 64
"""Rows per call of the fuzz's programs (as :func:`hga_jax.model.path.decode64`'s)."""


def _padded(a, pad: int):
    return a if pad == 0 else np.concatenate([a, np.repeat(a[:1], pad, axis=0)])


def _programs(exact_select: bool = True):
    """The jitted float32 fitness and, with ``exact_select``, the float64 violations in
    time alone (:func:`judge` tells the rows clear of the standing robots by them)."""
    import jax

    from hga_jax.model.fitness import evaluate
    from hga_jax.model.in_time import clearance as mv

    return (jax.jit(evaluate, static_argnames="collision"),
            jax.jit(mv.violations, static_argnums=(2, 3)) if exact_select else None)


NEAR = 2
"""Without the float64 violations in time alone (``exact_select`` False, which saves a
compile of some seconds), :func:`judge` takes the host check's candidates to be the rows
with at most this many float64 violations."""


def judge(sc, model: str, perm, labels, legs, programs=None, tally: Tally | None = None,
          scene_dict_: dict | None = None) -> tuple[Tally, dict]:
    """Judge a batch of chromosomes of ``model`` on scene ``sc`` by the three checks and
    the dense check; counts go to ``tally``. Returns it and the float64 paths of the rows
    that keep clear of the standing robots and the field (row: path)."""
    import jax

    from hga_jax.model import car_model
    from hga_jax.model.in_time import clearance as mv
    from hga_jax.model.path import decode64, evaluate_path

    evaluate, in_time = programs or _programs()
    tally = tally or Tally(model)
    t0 = time.perf_counter()
    sa = car_model.get(model).search_arrays(sc, np.float32, "full")
    rows_in = perm.shape[0]
    pad = -rows_in % BLOCK  # every program runs on blocks of BLOCK rows: one compile a shape
    perm, labels = _padded(perm, pad), _padded(labels, pad)
    legs = None if legs is None else _padded(legs, pad)
    v32 = np.concatenate([np.asarray(evaluate(
        sa, perm[i:i + BLOCK], labels[i:i + BLOCK], "full",
        None if legs is None else legs[i:i + BLOCK]).violations)
        for i in range(0, perm.shape[0], BLOCK)])
    d64 = decode64(sc, perm, labels, "full", legs)
    v64 = np.asarray(d64.violations)
    if in_time is None:  # the rows with few violations: most of those clear of standing robots
        mv64 = np.where(v64 <= NEAR, v64, 0)
    else:
        with jax.enable_x64(True):
            motion = sc.motion(np.float64)
            mv64 = np.concatenate([np.asarray(in_time(
                jax.tree.map(lambda a: a[i:i + BLOCK], d64), motion, sc.n, mv.SUBARCS_64))
                for i in range(0, perm.shape[0], BLOCK)])
    perm, labels = perm[:rows_in], labels[:rows_in]
    legs = None if legs is None else legs[:rows_in]
    v32, v64, mv64 = v32[:rows_in], v64[:rows_in], mv64[:rows_in]
    # The others are infeasible by every check: the float32 and float64 fitness say so, and
    # the host check finds the float64 decoder's violations against standing robots too.
    rows = np.flatnonzero((v32 == 0) | (v64 == 0) | (v64 == mv64))
    tally.checked += perm.shape[0]
    tally.scenes += 1
    clean = {}
    for i in rows:
        p = evaluate_path(sc, perm[i], labels[i], "full", None if legs is None else legs[i])
        still = [w for w in p.violations_at if w["kind"] != "moving obstacle"]
        hits = mv.segment_hits(sc, p.segments)
        verdict = {"float32": v32[i] == 0, "float64": v64[i] == 0,
                   "host": not still and not hits}
        assert p.violations == v64[i]  # one decoder, alone or in a batch
        if any(w["kind"] not in ("moving obstacle", "moving obstacle wrapped")
               for w in p.violations_at) and not (verdict["float32"] or verdict["float64"]):
            continue  # a standing robot or the field: not measured
        if not still:
            clean[int(i)] = p
        lower, upper = clearance(sc, p.segments, decide=tuple(MARGINS.values()))
        sampled = min((a.clearance for a in mv.closest_approach(sc, p.segments, SPACING,
                                                                     start=sc.start[:2])),
                      default=math.inf)
        tally.sampled_below += int(sampled < float(lower.min()) - 1e-12)
        low, up = float(lower.min()), float(upper.min())
        tally.measured += 1
        tally.colliding += int(up < -F64_MARGIN)
        tally.boundary += int(abs(up) < 1e-4)
        for check, ok in verdict.items():
            if not ok:
                continue
            tally.feasible[check] += 1
            tally.closest[check] = min(tally.closest[check], up)
            margin = MARGINS[check]
            if up < -margin:
                tally.false[check] += 1
                if len(tally.examples) < 20:
                    tally.examples.append((scene_dict_, perm[i].tolist(), labels[i].tolist(),
                                           None if legs is None else legs[i].tolist(),
                                           check, up))
            elif low < -margin:
                tally.undecided[check] += 1
            elif check == "float32" and up < -F64_MARGIN:
                tally.in_tolerance += 1
    tally.seconds += time.perf_counter() - t0
    return tally, clean


GRAZE_BATCH = 8
"""Chromosomes judged on each grazing scene (:func:`graze`): the grazed one and others."""


def graze(rng: np.random.Generator, d: dict, perm, labels, path) -> dict | None:
    """A scene mapping made from ``d`` so that one of its moving robots that the
    chromosome ``(perm, labels)`` does not touch grazes the path ``path`` (its float64
    path on ``d``): at a random point of the path the robot's centre is ``D = R + delta``
    from the car's point at that moment (``|delta|`` log-uniform in 1e-7 .. 1e-2 m, either
    sign), across their relative velocity, so that ``D`` is the least distance of their
    relative motion there (on a line, over the whole line; the dense check has the last
    word). None where there is no such robot or segment."""
    import copy

    from hga_jax.model.in_time import clearance as mv

    n = len(d["obstacles"])
    touched = set(int(perm[q - 1]) for q in range(1, n + 1) if labels[q] != 0)
    free_robots = [k for k, o in enumerate(d["obstacles"]) if "vx" in o and k not in touched]
    speed = float(d["robot"]["speed"])
    timed = [ts for ts in mv.timed(path.segments, speed) if ts.length > 0.0]
    if not free_robots or not timed:
        return None
    k = free_robots[int(rng.integers(len(free_robots)))]
    w = np.array([ts.length for ts in timed])
    ts = timed[int(rng.choice(w.size, p=w / w.sum()))]
    u = float(rng.uniform(0.02, 0.98))
    seg = ts.segment
    (x,), (y,) = _points(seg, np.array([u]))
    if seg["type"] == "line":
        (x0, y0), (x1, y1) = seg["start"], seg["end"]
        tx, ty = (x1 - x0) / ts.length, (y1 - y0) / ts.length
    else:
        a = float(seg["start_angle"]) + float(seg["sweep"]) * u
        s = 1.0 if float(seg["sweep"]) > 0 else -1.0
        tx, ty = -s * math.sin(a), s * math.cos(a)
    when = ts.t0 + (ts.t1 - ts.t0) * u
    ang = rng.uniform(0.0, 2.0 * math.pi)
    vel = rng.uniform(0.3, 1.5) * np.array([math.cos(ang), math.sin(ang)])
    rel = speed * np.array([tx, ty]) - vel  # the car's velocity relative to the robot's
    if np.hypot(*rel) < 1e-9:
        return None
    nx, ny = np.array([-rel[1], rel[0]]) / np.hypot(*rel) * rng.choice([-1.0, 1.0])
    out = copy.deepcopy(d)
    o = out["obstacles"][k]
    big_r = max(float(d["robot"]["min_turn_radius"]), o.get("radius", ROBOT_RADIUS) + ROBOT_RADIUS)
    dist = big_r + rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-7.0, -2.0)
    o.update(x=float(x + dist * nx - when * vel[0]), y=float(y + dist * ny - when * vel[1]),
             vx=float(vel[0]), vy=float(vel[1]))
    return out


def fuzz(total: int, seed: int = 0, rows: int = 2000, models=MODELS,
         shapes=SHAPES, graze_count: int | None = None, modes=None,
         exact_select: bool = True, progress: bool = False) -> dict[str, Tally]:
    """``total`` chromosomes shared among ``models``: per scene ``rows`` random ones, then
    ``graze_count`` (default ``rows // 50``) grazing scenes of :data:`GRAZE_BATCH` each
    (:func:`graze`); the scenes' shapes cycle through ``shapes`` and their placements of
    the moving robots' circles through ``modes`` (default :data:`MODES`, less
    :data:`SLOW_MODES`). A grazing scene keeps its scene's placement moments.
    ``exact_select`` False: the host check judges only the rows with at most :data:`NEAR`
    float64 violations (a quicker fuzz)."""
    programs = _programs(exact_select)
    out = {}
    for m_i, model in enumerate(models):
        mine = [x for x in (modes or MODES) if x not in SLOW_MODES.get(model, ())]
        rng = np.random.default_rng([seed, m_i])
        tally = Tally(model)
        per_model = -(-total // len(models))
        k = 0
        while tally.checked < per_model:
            n, m = shapes[k % len(shapes)]
            k += 1
            _, d = scene(rng, car_of(model), n, m)
            mode = mine[(k - 1) % len(mine)]
            if mode == "given":
                d["wrap_moving"] = "at-best"
                d["placed"] = [float(rng.uniform(0.0, 3.0)) if "vx" in o else 0.0
                               for o in d["obstacles"]]
            else:
                d["wrap_moving"] = mode
            sc = build(d)
            b = min(rows, per_model - tally.checked)
            perm, labels, legs = chromosomes(rng, model, n, rows)
            _, clean = judge(sc, model, perm[:b], labels[:b],
                             None if legs is None else legs[:b], programs, tally, d)
            if mode != "never":  # the grazing scenes keep these moments (none solved again)
                d = {**d, "placed": [float(t) for t in sc.placement_times()]}
            _grazing(rng, model, d, perm, labels, legs, clean,
                     rows // 50 if graze_count is None else graze_count, programs, tally)
            if progress:
                print(f"{model}: scene {k} ({n} robots, {m} moving, {mode}): "
                      f"{tally.checked} checked, {tally.seconds:.0f} s", file=sys.stderr,
                      flush=True)
        out[model] = tally
    return out


def _grazing(rng, model, d, perm, labels, legs, clean, count, programs, tally) -> None:
    """Up to ``count`` grazing scenes (:func:`graze`) of the scene ``d``, each made for one
    of its ``clean`` rows, and on each that row and :data:`GRAZE_BATCH` - 1 others judged."""
    from hga_jax.errors import ConfigError

    rows = np.array(sorted(clean), int)
    if rows.size == 0:
        return
    for i in rng.permutation(rows)[:count]:
        made = graze(rng, d, perm[i], labels[i], clean[int(i)])
        if made is None:
            continue
        try:
            sc = build(made)
        except ConfigError:  # the start inside the robot at time 0
            continue
        pick = np.concatenate([[i], rng.choice(perm.shape[0], GRAZE_BATCH - 1, replace=False)])
        judge(sc, model, perm[pick], labels[pick], None if legs is None else legs[pick],
              programs, tally, made)


def report(tallies: dict[str, Tally]) -> str:
    lines = [f"{'model':<12} {'checked':>8}  {'feasible f32/f64/host':>22}  "
             f"{'false feasible':>14}  {'f32 in tol':>10}  {'undecided':>9}  "
             f"{'measured':>8} {'colliding':>9} "
             f"{'boundary':>8}  {'closest feasible (mm) f32/f64/host':>34}  {'time s':>7}"]
    for t in tallies.values():
        feas = "/".join(str(t.feasible[c]) for c in CHECKS)
        false = "/".join(str(t.false[c]) for c in CHECKS)
        und = "/".join(str(t.undecided[c]) for c in CHECKS)
        close = "/".join(f"{t.closest[c] * 1e3:.4f}" for c in CHECKS)
        lines.append(f"{t.model:<12} {t.checked:>8}  {feas:>22}  {false:>14}  "
                     f"{t.in_tolerance:>10}  {und:>9}  "
                     f"{t.measured:>8} {t.colliding:>9} {t.boundary:>8}  {close:>34}  "
                     f"{t.seconds:>7.1f}")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--chromosomes", type=int, default=100_000,
                    help="chromosomes in all, shared among the three car models")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--rows", type=int, default=2000, help="chromosomes per scene")
    ap.add_argument("--quiet", action="store_true", help="no line per scene on stderr")
    ap.add_argument("--models", nargs="+", choices=MODELS, default=list(MODELS),
                    help="the car models fuzzed (default: all three)")
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    tallies = fuzz(args.chromosomes, args.seed, args.rows, models=tuple(args.models),
                   progress=not args.quiet)
    print(report(tallies))
    print("false feasible: a check calls the path feasible, the dense check shows it closer "
          f"than R - {F32_MARGIN:g} m (float32) or R - {F64_MARGIN:g} m (float64, host) to "
          "a moving robot at the same time")
    print(f"dense check: samples every {SPACING:g} m, least clearance bracketed to "
          f"{BRACKET:g} m; closest_approach below the bracket: "
          f"{sum(t.sampled_below for t in tallies.values())}")
    print(f"total {time.perf_counter() - t0:.1f} s")
    bad = [ex for t in tallies.values() for ex in t.examples]
    for ex in bad[:5]:
        print("false feasible:", ex)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
