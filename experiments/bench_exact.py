"""Benchmark of the exact solver: median warm solve time for random scenes.

Scenes in the style of ``configs/scenarios/cluttered.toml``: a 4 m x 3 m field kept
inside, robot radius 0.09 m, rho 0.18 m, obstacle radii from {0.06, 0.09, 0.12} m,
centres uniform on [0.4, 3.6] x [0.4, 2.6] away from the start (bottom left) and the
goal (top right). Each scene is solved once to warm up (the decoder's jit compile for
that obstacle count), then timed over repeats. A fixed pure-Python loop is timed as
a calibration figure: the machine is shared and its speed varies.

The free-turn solver (``turns = "free"``) is timed on the same scenes, against the
tight-rope solver twice: warm (the scenario's tangent table built, as ``seconds``
reports) and cold (the table's build included, as the free-turn solver's own tangents
are). The Reeds–Shepp solver (``car = "reeds-shepp"``) is timed on the same scenes
against the free-turn solver: its own search (``seconds``) and the whole call (which
solves the free-turn and tight-rope optima first, to bound its graph).

Usage: ``python experiments/bench_exact.py [--scenes 8] [--repeats 5]``.
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from calibration import calibration

from hga_jax.model.exact import solve
from hga_jax.model.scenario import Field, Scenario


def random_scene(rng: np.random.Generator, n: int) -> Scenario:
    """A cluttered-field scene with n obstacles (start and goal clear of every model circle)."""
    robot, rho = 0.09, 0.18
    start, goal = (0.3, 0.3, np.pi / 4), (3.7, 2.7, np.pi / 2)
    centres, radii = [], []
    while len(centres) < n:
        c, r = rng.uniform([0.4, 0.4], [3.6, 2.6]), float(rng.choice([0.06, 0.09, 0.12]))
        model = max(rho, r + robot)
        if min(np.hypot(*(c - start[:2])), np.hypot(*(c - goal[:2]))) > model + 0.15:
            centres.append(c)
            radii.append(r)
    return Scenario(f"bench{n}", robot, rho, start, goal, np.array(centres), np.array(radii),
                    field=Field(0.0, 4.0, 0.0, 3.0, keep_inside=True))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=8)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    print(f"calibration: pure-Python loop of 10^6 multiply-adds: {calibration() * 1e3:.1f} ms")
    for n in (9, 25, 40):
        for collision in ("full", "paper"):
            times, infeasible, revisits = [], 0, 0
            for _ in range(args.scenes):
                sc = random_scene(rng, n)
                res = solve(sc, collision)  # warm-up (decoder compile for this n)
                infeasible += not res.feasible
                revisits += res.feasible and not res.expressible
                for _ in range(args.repeats):
                    times.append(solve(sc, collision).seconds)
            print(f"n={n:3d} {collision:5s}: median {statistics.median(times) * 1e3:7.2f} ms, "
                  f"max {max(times) * 1e3:7.2f} ms over {len(times)} solves "
                  f"({infeasible} infeasible, {revisits} revisiting scenes)")
    rng = np.random.default_rng(args.seed + 1)
    for n in (9, 15, 25, 40):
        free, warm, cold, shorter = [], [], [], 0
        for _ in range(args.scenes):
            sc = random_scene(rng, n)
            solve(sc)
            for _ in range(args.repeats):
                fresh = Scenario(sc.name, sc.robot_radius, sc.min_turn_radius, sc.start, sc.goal,
                                 sc.centres, sc.radii, field=sc.field)
                t0 = time.perf_counter()
                warm.append(solve(fresh).seconds)
                cold.append(time.perf_counter() - t0)
                res = solve(fresh, turns="free")
                free.append(res.seconds)
            shorter += res.free_arcs > 0
        f, w, c = (statistics.median(v) * 1e3 for v in (free, warm, cold))
        print(f"n={n:3d} free turns: median {f:7.2f} ms; tight rope {w:6.2f} ms warm "
              f"({f / w:5.1f}x), {c:6.2f} ms cold ({f / c:4.1f}x); {shorter} of {args.scenes} "
              "scenes shorter with free turns")
    rng = np.random.default_rng(args.seed + 2)
    for n in (9, 25, 40):
        free, own, whole, shorter = [], [], [], 0
        for _ in range(args.scenes):
            sc = random_scene(rng, n)
            solve(sc)
            for _ in range(args.repeats):
                free.append(solve(sc, turns="free").seconds)
                t0 = time.perf_counter()
                res = solve(sc, car="reeds-shepp")
                whole.append(time.perf_counter() - t0)
                own.append(res.seconds)
            shorter += res.length < res.details["free_turn_length"] - 1e-9
        f, o, w = (statistics.median(v) * 1e3 for v in (free, own, whole))
        print(f"n={n:3d} Reeds-Shepp: median {o:7.2f} ms its own search, {w:7.2f} ms the whole "
              f"call; free turns {f:6.2f} ms ({o / f:4.1f}x, whole {w / f:4.1f}x); {shorter} of "
              f"{args.scenes} scenes shorter when reversing")
    print(f"calibration again: {calibration() * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
