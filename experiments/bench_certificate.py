"""Benchmark of the exact solver among robots that move: what the certificate costs.

On 9-robot scenes of ``bench_exact.py``'s style with 5 of the robots moving (random
straight-line velocities of 0.3-1.5 m/s, car speed 1 m/s), the median time of
``hga_jax.solve`` over many solves in one process, each on a fresh copy of the scene
(no table kept from the solve before), against the same scene with every robot
standing (the static solve). Scenes are split by the answer: certified (the standing
robots' optimum keeps clear in time, which costs one more float64 check) and not
certified (then the frozen scenes are solved too; their decoder compiles once per
obstacle count, so the first solve of such a scene is slower). A fixed pure-Python
loop is timed as a calibration figure: the machine is shared and its speed varies.

Usage: ``python experiments/bench_certificate.py [--scenes 10] [--solves 200]``.
"""
from __future__ import annotations

import argparse
import dataclasses
import statistics
import time

import numpy as np

from bench_exact import random_scene
from calibration import calibration

from hga_jax.model.exact import solve


def moving_scene(rng: np.random.Generator, n: int = 9, movers: int = 5):
    """A ``random_scene`` of ``n`` robots, ``movers`` of them driving straight on."""
    sc = random_scene(rng, n)
    vel = np.zeros((n, 2))
    for k in rng.choice(n, movers, replace=False):
        speed, angle = rng.uniform(0.3, 1.5), rng.uniform(0.0, 2.0 * np.pi)
        vel[k] = speed * np.cos(angle), speed * np.sin(angle)
    return dataclasses.replace(sc, velocities=vel, speed=1.0)


def median_ms(scene, solves: int) -> float:
    """Median wall time of ``solve`` on fresh copies of ``scene`` (ms), after one warm-up."""
    solve(dataclasses.replace(scene))
    times = []
    for _ in range(solves):
        copy = dataclasses.replace(scene)
        t0 = time.perf_counter()
        solve(copy)
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", type=int, default=10)
    ap.add_argument("--solves", type=int, default=200)
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    print(f"calibration (10^6 pure-Python multiply-adds): {calibration():.4f} s")
    print(f"{'scene':>5}  {'answer':<13} {'static ms':>9} {'moving ms':>9} {'ratio':>6}")
    ratios: dict[str, list[float]] = {"certified": [], "not certified": []}
    for i in range(args.scenes):
        sc = moving_scene(rng)
        standing = dataclasses.replace(sc, velocities=None)
        opt = solve(dataclasses.replace(sc))
        if not solve(standing).feasible or (not opt.feasible and opt.optimal):
            continue
        answer = "certified" if opt.optimal else "not certified"
        a, b = median_ms(standing, args.solves), median_ms(sc, args.solves)
        ratios[answer].append(b / a)
        print(f"{i:>5}  {answer:<13} {a:9.2f} {b:9.2f} {b / a:6.2f}")
    for answer, r in ratios.items():
        if r:
            print(f"{answer}: {len(r)} scenes, ratio median {statistics.median(r):.2f}, "
                  f"max {max(r):.2f}")
    print(f"calibration at the end: {calibration():.4f} s")


if __name__ == "__main__":
    main()
