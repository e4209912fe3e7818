"""Evaluations per second of the GA under free turns against the tight rope.

Free-turn chromosomes carry a third module (one leg gene per position) and their
fitness looks turns up in a table nine times the tight rope's
(:mod:`hga_jax.model.cars.free_turns.legs`). This times both models with the same settings on
the same scenes: ``robocup_paper.toml`` (n = 9) and clutter scenes of the studies'
generator (seed 3, scene 0) with 25 and 40 obstacles, for the paper's and the
recommended preset; the median search time over repeats after a warm-up run (the
compile is not counted), evaluations/s ``runs * population * (generations + 1) /
search`` and the ratio tight / free, with a calibration figure before and after (the
machine is shared and its speed varies).

Usage (from the repository root)::

    python3 experiments/bench_free_turns.py [--quick] [--sizes 9 25 40] [--runs 1000]
        [--repeats 3]
"""
from __future__ import annotations

import argparse
import dataclasses
import statistics

from calibration import calibration

from hga_jax import load_scenario, scenario_from_dict
from hga_jax.running.runner import run_many
from hga_jax.search.settings import PRESETS
from hga_jax.study.scenes import generate


def scene(n: int):
    if n == 9:
        return load_scenario("configs/scenarios/robocup_paper.toml")
    return scenario_from_dict(generate("clutter", n, 3, 0, f"clutter{n}"), f"clutter{n}")


def rate(sc, settings, runs: int, repeats: int) -> float:
    run_many(sc, settings, seed=0, runs=runs, exact=False)  # compile
    times = [run_many(sc, settings, seed=1 + k, runs=runs, exact=False).search_s
             for k in range(repeats)]
    return runs * settings.population * (settings.for_obstacles(sc.n).generations + 1) / \
        statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="n = 9 only, 200 runs, one repeat")
    ap.add_argument("--sizes", type=int, nargs="+", default=[9, 25, 40])
    ap.add_argument("--runs", type=int, default=1000,
                    help="runs per timed search (the recommended preset: a twentieth)")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()
    sizes, runs, repeats = ([9], 200, 1) if args.quick else (args.sizes, args.runs, args.repeats)
    print(f"calibration: pure-Python loop of 10^6 multiply-adds: {calibration() * 1e3:.1f} ms")
    print("  n  preset        tight-rope M/s   free M/s   tight / free")
    for n in sizes:
        sc = scene(n)
        for name in ("paper", "recommended"):
            base = PRESETS[name]
            r = max(20, runs // (20 if name == "recommended" else 1))
            tight = rate(sc, base, r, repeats)
            free = rate(sc, dataclasses.replace(base, turns="free"), r, repeats)
            print(f"{n:3d}  {name:12s} {tight / 1e6:14.2f} {free / 1e6:10.2f} "
                  f"{tight / free:14.2f}", flush=True)
    print(f"calibration again: {calibration() * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
