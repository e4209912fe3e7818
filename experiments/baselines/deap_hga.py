"""The paper's HGA written with DEAP (:mod:`hga_jax.peers.deap_ga`) on one scenario, alone.

A study compares it with the HGA on the same scenes (``solver = "deap"`` in a study
file: ``configs/studies/baselines.toml``); this script times it by hand and writes
one CSV row per run.

Usage: ``python3 experiments/baselines/deap_hga.py [SCENARIO] [--runs 200] [--seed 0]
[--generations 50] [--out results/baselines/deap_hga.csv]`` (needs the ``compare``
extra).
"""
from __future__ import annotations

import argparse
import csv
import os
import statistics

from hga_jax.host.config import load_scenario
from hga_jax.model.exact import solve
from hga_jax.peers.deap_ga import run
from hga_jax.peers.python_decoder import PythonDecoder
from hga_jax.search.settings import GASettings


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("scenario", nargs="?", default="configs/scenarios/robocup_paper.toml")
    p.add_argument("--runs", type=int, default=200)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--generations", type=int, default=50)
    p.add_argument("--out", default=os.path.join("results", "baselines", "deap_hga.csv"))
    args = p.parse_args(argv)
    sc = load_scenario(args.scenario)
    settings = GASettings(generations=args.generations)
    opt = solve(sc).length
    decoder = PythonDecoder.from_scenario(sc, settings.collision)
    rows = []
    for k in range(args.runs):
        r = run(sc, settings, args.seed, k, decoder)
        feasible = r["violations"] == 0
        gap = r["length"] / opt - 1 if feasible else None
        rows.append({"run": k, "length": r["length"], "violations": r["violations"],
                     "generation": r["generation"], "evaluations": r["evaluations"],
                     "feasible": feasible, "gap": gap, "hit": gap is not None and gap < 1e-6,
                     "seconds": r["seconds"]})
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    hits = sum(r["hit"] for r in rows)
    gaps = [r["gap"] if r["gap"] is not None else float("inf") for r in rows]
    print(f"DEAP HGA on {sc.name}: {args.runs} runs of {args.generations} generations: "
          f"hit rate {hits / args.runs:.1%}, median gap {statistics.median(gaps):.2%}, "
          f"feasible {sum(r['feasible'] for r in rows)}/{args.runs}, "
          f"{statistics.median(r['seconds'] for r in rows) * 1000:.0f} ms per run (median), "
          f"{statistics.median(r['evaluations'] for r in rows):.0f} evaluations per run "
          f"(median); wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
