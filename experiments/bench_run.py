"""Benchmark of the GA: many seeded runs of the paper's settings on a scenario.

Prints, for each batch size, the compile time (once per process and shape), the
median search time over repeats, evaluations per second, and the time of the
float64 re-evaluation plus the exact optimum ("finish"). A fixed pure-Python loop
is timed as a calibration figure: the machine is shared and its speed varies.

Usage: ``python experiments/bench_run.py [SCENARIO] [--runs 1000 10000] [--repeats 3]``.
The target of the project: 1000 runs of ``robocup_paper.toml`` in under 20 s,
compile included, on a 2-core machine.
"""
from __future__ import annotations

import argparse
import statistics
import time

from calibration import calibration

from hga_jax.config import load_scenario
from hga_jax.runner import run_many


def bench(path: str, runs: int, repeats: int) -> dict[str, float]:
    """Compile once, then time ``repeats`` searches of ``runs`` runs (different seeds)."""
    sc = load_scenario(path)
    t0 = time.perf_counter()
    first = run_many(sc, seed=0, runs=runs)
    wall = time.perf_counter() - t0
    search = [first.search_s]
    for seed in range(1, repeats):
        search.append(run_many(sc, seed=seed, runs=runs).search_s)
    med = statistics.median(search)
    return {"runs": runs, "first_call_wall_s": wall, "compile_s": first.compile_s,
            "search_median_s": med, "finish_s": first.finish_s,
            "evaluations_per_s": first.evaluations / med, "hit_rate": first.summary()["hit_rate"]}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenario", nargs="?", default="configs/scenarios/robocup_paper.toml")
    p.add_argument("--runs", type=int, nargs="+", default=[1000, 10000])
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    print(f"calibration: 10^6 pure-Python multiply-adds in {calibration():.4f} s")
    for runs in args.runs:
        r = bench(args.scenario, runs, args.repeats)
        print(f"{runs} runs: first call {r['first_call_wall_s']:.2f} s in all (compile "
              f"{r['compile_s']:.2f} s, search {r['search_median_s']:.2f} s median of "
              f"{args.repeats}, finish {r['finish_s']:.2f} s); {r['evaluations_per_s']:,.0f} "
              f"evaluations/s; hit rate {r['hit_rate']:.1%}")
    print(f"calibration after: {calibration():.4f} s")


if __name__ == "__main__":
    main()
