"""The exact solver among robots that move: a lower bound, a certificate, the best path known.

Among robots that move (docs/model.md, "Moving robots"), every path feasible in time is
feasible among the robots that stand alone, so the optimum of
:meth:`~hga_jax.model.scenario.Scenario.still_scene` (any car model's ``solve``) is a
lower bound on the optimum; when its path keeps clear of every moving robot in time
(:func:`hga_jax.model.in_time.clearance.segment_hits`, float64) it *is* the optimum, and the result
says so (``optimal`` True). Otherwise the result carries the bound and the shortest path
this module knows that is feasible in time (``optimal`` False), found by solving static
scenes that freeze the moving robots where they get in the way:

- the frozen snapshot (every robot where it stands at time 0: what a planner without time
  would return);
- conflict freezing: from the still robots' optimum, each moving robot that a path meets
  in time is added as a standing robot where it is at the moment of the conflict, and the
  scene is solved again (up to ``ROUNDS`` times, copies accumulating);
- the tracks: each moving robot as standing robots along its track over the time the
  still optimum takes and half again, a copy every half model radius or, where that
  makes more than ``TRACK_COPIES`` in all, fewer.

Each candidate is re-checked in time on the scenario itself; a candidate that wraps a
frozen copy has no chromosome (only its segments are reported). Host code.
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Any, Callable

import numpy as np

from hga_jax.model.in_time import clearance
from hga_jax.model.path import Path, chromosome, evaluate_path
from hga_jax.model.touch import Touch

ROUNDS = 8
"""Rounds of conflict freezing (each adds the robots met in time and solves again)."""
TRACK_COPIES = 48
"""At most this many copies of the moving robots along their tracks (about; at least two
each): a copy every half model radius, fewer where the tracks are long (the static
scene's tables grow with the cube of its robots)."""
PAD = 16
"""The frozen scenes' robot counts are padded to a multiple of this (module code)."""
FAR = 1e4
"""m: where the padding robots stand (far from any scene)."""


def solve(scenario: Any, collision: str, static_solve: Callable[[Any], Any]) -> Any:
    """The :class:`~hga_jax.model.exact.ExactResult` of a scenario with moving robots
    (module doc); ``static_solve(scene)`` is the car model's exact solver."""
    t0 = time.perf_counter()
    still = scenario.still_scene()
    bound = static_solve(still)
    if not bound.feasible:  # no path among the standing robots: none in time either
        return dataclasses.replace(bound, optimal=True, lower_bound=None,
                                   seconds=time.perf_counter() - t0)
    path = _on_scenario(scenario, still, bound)
    if not clearance.segment_hits(scenario, bound.segments):
        return dataclasses.replace(
            bound, length=bound.length if path is None else path.length, path=path,
            best_expressible=path, expressible=path is not None,
            upper=None if path is None else path.upper,
            lower=None if path is None else path.lower,
            touched=touched_in(scenario, bound.touched) if path is None else path.touched,
            segments=bound.segments if path is None else path.segments, optimal=True, lower_bound=bound.length, seconds=time.perf_counter() - t0,
            message="optimal: the standing robots' optimum keeps clear of every moving robot "
                    "in time")
    best, how = None, ""
    for name, result in _candidates(scenario, still, bound, static_solve):
        if result is None or not result.feasible:
            continue
        if clearance.segment_hits(scenario, result.segments):
            continue
        if best is None or result.length < best.length:
            best, how = result, name
    spent = time.perf_counter() - t0
    note = ("the standing robots' optimum meets a moving robot in time; "
            f"lower_bound is its length")
    if best is None:
        return dataclasses.replace(
            bound, length=math.inf, feasible=False, expressible=True, upper=None, lower=None,
            touched=[], path=None, best_expressible=None, segments=[], optimal=False,
            lower_bound=bound.length, seconds=spent,
            message=note + "; no path feasible in time is known")
    path = _on_scenario(scenario, best.scene, best.result)
    expressible = path is not None
    return dataclasses.replace(
        best.result, length=best.length, feasible=True, expressible=expressible,
        walk_length=best.length,
        upper=path.upper if expressible else None, lower=path.lower if expressible else None,
        touched=path.touched if expressible else touched_in(scenario, best.result.touched),
        path=path,
        best_expressible=path, segments=best.result.segments, optimal=False,
        lower_bound=bound.length, seconds=spent,
        message=note + f"; the path is the shortest known feasible in time ({how})")


class _Found:
    """A static scene's optimum and the scene it was solved on."""

    def __init__(self, scene: Any, result: Any):
        self.scene, self.result = scene, result
        self.length, self.feasible, self.segments = result.length, result.feasible, result.segments


def _candidates(scenario: Any, still: Any, bound: Any, static_solve: Callable[[Any], Any]):
    """``(name, _Found)`` of the static scenes tried (module doc)."""
    centres = np.asarray(scenario.centres, float)
    vel = np.asarray(scenario.velocities, float).reshape(scenario.n, 2)
    movers = np.flatnonzero(scenario.moving)
    frozen = _with_copies(still, [(centres[j], scenario.radii[j]) for j in movers], scenario)
    yield "the frozen snapshot", _solved(frozen, static_solve)
    copies: list[tuple[np.ndarray, float]] = []
    segments = bound.segments
    for _ in range(ROUNDS):
        met = [a for a in clearance.closest_approach(scenario, segments, spacing=5e-3)
               if a.clearance < 1e-6]
        new = [(np.asarray(a.centre), scenario.radii[a.obstacle]) for a in met]
        if not new:
            break
        copies += new
        found = _solved(_with_copies(still, copies, scenario), static_solve)
        if found is None or not found.feasible:
            break
        yield "conflict freezing", found
        segments = found.segments
    horizon = 1.5 * bound.length / float(scenario.speed)
    track = []
    each = max(2, TRACK_COPIES // max(len(movers), 1))
    for j in movers:
        v = max(float(np.hypot(*vel[j])), 1e-9)
        step = max(0.5 * float(scenario.model_radii[j]) / v, horizon / (each - 1))
        for t in np.arange(0.0, horizon + 0.5 * step, step):
            track.append((centres[j] + vel[j] * t, scenario.radii[j]))
    yield "the tracks", _solved(_with_copies(still, track, scenario), static_solve)


def _with_copies(still: Any, copies: list, scenario: Any) -> Any | None:
    """``still`` with standing robots added at ``copies`` ``(centre, radius)``, leaving out
    any whose model circle holds the start or goal point or that repeats a centre."""
    if not copies:
        return still
    pts = np.array([scenario.start[:2], scenario.goal[:2]], float)
    keep_c, keep_r = [], []
    for c, r in copies:
        big = max(scenario.min_turn_radius, float(r) + scenario.robot_radius)
        if np.any(np.hypot(*(pts - c).T) < big):
            continue
        if any(np.hypot(*(c - k)) < 1e-9 for k in keep_c) or np.any(
                np.hypot(*(np.asarray(still.centres) - c).T) < 1e-9):
            continue
        keep_c.append(np.asarray(c, float))
        keep_r.append(float(r))
    if not keep_c:
        return still
    # Padded to a multiple of PAD robots with robots far away, which no path touches: the
    # float64 decoder compiles once per robot count, not once per round.
    pad = -(still.n + len(keep_c)) % PAD
    far = [np.array([FAR + 10.0 * k, FAR]) for k in range(pad)]
    return dataclasses.replace(
        still, centres=np.vstack([still.centres, *keep_c, *far]),
        radii=np.concatenate([still.radii, keep_r, np.full(pad, still.robot_radius)]),
        velocities=None)


def _solved(scene: Any, static_solve: Callable[[Any], Any]) -> _Found | None:
    if scene is None:
        return None
    return _Found(scene, static_solve(scene))


def _on_scenario(scenario: Any, scene: Any, result: Any) -> Path | None:
    """``result``'s path (an optimum of ``scene``, whose first robots are ``scenario``'s
    standing robots in order) as a path of ``scenario``: the same pieces, its chromosome
    and touches numbered as ``scenario``'s robots (the moving ones last, untouched). Its
    static violations are the scene's (the same standing robots and field) and it is
    called only for paths the float64 check found clear in time. None when it has no
    chromosome or wraps a robot ``scenario`` does not stand (a frozen copy): then only
    its segments are reported."""
    found = result.path
    if found is None or found.upper is None:
        return None
    number = _numbers(scenario, scene)  # the scene's robots as the scenario's (from 0)
    touched_in_scene = [t.obstacle - 1 for t in found.touched]
    if any(number.get(k) is None for k in touched_in_scene) or len(
            {number[k] for k in touched_in_scene}) < len(touched_in_scene):
        return None
    inner = [u - 1 for u in found.upper[1:-1]]  # the scene's obstacles in position order
    at = {k: i + 1 for i, k in enumerate(inner)}  # obstacle -> its position
    touched = touched_in_scene
    order = [number[k] for k in touched]
    rest = [k for k in range(scenario.n) if k not in set(order)]
    lower = ([found.lower[0]] + [found.lower[at[k]] for k in touched] + [0] * len(rest)
             + [found.lower[-1]])
    legs = None
    if found.legs is not None:  # positional: each touched position keeps its gene
        legs = ([found.legs[0]] + [found.legs[at[k]] for k in touched] + [0] * len(rest)
                + [found.legs[-1]])
    upper, lower = chromosome(np.asarray(order + rest), lower)
    touches = [Touch(number[t.obstacle - 1] + 1, t.label) for t in found.touched]
    return Path(found.length, found.violations, upper, lower, found.segments, touches, [],
                legs)


def _numbers(scenario: Any, scene: Any) -> dict[int, int | None]:
    """The robots of ``scene`` (the standing robots of ``scenario`` in order, then frozen
    copies) as ``scenario``'s robots (indices from 0): a copy is the moving robot whose
    centre it is at some moment, where a chromosome wraps it there (``wrap_moving =
    "at-best"``, whose circles stand where the best path known passes), else None."""
    idx = scenario.still_index
    out: dict[int, int | None] = {k: int(i) for k, i in enumerate(idx)}
    if scenario.wrap_moving != "at-best":
        return out
    for k in range(idx.size, scene.n):
        seg = {"type": "arc", "center": list(np.asarray(scene.centres[k], float)),
               "radius": float(scene.model_radii[k])}
        mover = clearance.moments_wrapped(scenario, [seg])
        out[k] = next(iter(mover)) if mover else None
    return out


def touched_in(scenario: Any, touched: list[Touch]) -> list[Touch]:
    """The still scene's touches numbered as ``scenario``'s robots (from 1); a frozen
    copy keeps a number past ``scenario.n``."""
    idx = scenario.still_index
    return [Touch(int(idx[t.obstacle - 1]) + 1 if t.obstacle <= idx.size
                  else scenario.n + t.obstacle - idx.size, t.label) for t in touched]

