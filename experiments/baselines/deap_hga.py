"""The paper's HGA written with DEAP, the way a DEAP user would, on one scenario.

Same model and settings as hga-jax's paper configuration: a chromosome is a
permutation of the obstacles plus one turning label per position; roulette
selection; per pair of parents, cycle crossover (written here: DEAP has none, and
its PMX is not the textbook one) with probability pc_upper and two-point crossover
of the labels with probability pc_lower; per individual, inversion of a random
segment with probability pm_upper; per label, a redraw to another allowed value
with probability pm_lower; no elitism.

The fitness ``10000 / (Dist_m + 1)`` comes from a pure-Python decoder of the model
(``python_decoder.py``: plain floats and ``math``, one individual at a time, its
tangents kept per pair of circles), written from docs/model.md independently of
hga-jax's decoder; a test checks that both give the same length and violations.
As in DEAP's own algorithms, only individuals that an operator changed are
evaluated again (their fitness is deleted; the others keep theirs). hga-jax is
used to load the scenario, for the settings and for the exact optimum the runs are
measured against. Python's ``random`` (seeded per run) drives the search, so runs
differ from hga-jax's run for run; the statistics compare.

Usage: ``python3 experiments/baselines/deap_hga.py [SCENARIO] [--runs 200] [--seed 0]
[--generations 50] [--out results/baselines/deap_hga.csv]`` (needs ``pip install deap``,
the ``compare`` extra).
"""
from __future__ import annotations

import argparse
import csv
import os
import random
import statistics
import sys
import time

from deap import base, creator, tools

from hga_jax.host.config import load_scenario
from hga_jax.model.exact import solve
from hga_jax.search.settings import GASettings

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from python_decoder import PythonDecoder  # noqa: E402  (beside this file)

if not hasattr(creator, "HGAFitness"):
    creator.create("HGAFitness", base.Fitness, weights=(1.0,))
    creator.create("HGAIndividual", list, fitness=creator.HGAFitness)


def cycle_crossover(a: list[int], b: list[int], rng: random.Random) -> tuple[list, list]:
    """Cycle crossover: the cycle through a random position comes from one parent,
    the other positions from the other parent."""
    n = len(a)
    where = {v: i for i, v in enumerate(a)}
    i, cycle = rng.randrange(n), set()
    while i not in cycle:
        cycle.add(i)
        i = where[b[i]]
    c1 = [a[k] if k in cycle else b[k] for k in range(n)]
    c2 = [b[k] if k in cycle else a[k] for k in range(n)]
    return c1, c2


def inversion(p: list[int], rng: random.Random) -> list[int]:
    lo, hi = sorted(rng.sample(range(len(p) + 1), 2))
    return p[:lo] + p[lo:hi][::-1] + p[hi:]


def redraw(labels: list[int], pm: float, rng: random.Random) -> list[int]:
    out = list(labels)
    for k, v in enumerate(out):
        if rng.random() < pm:
            out[k] = -v if k in (0, len(out) - 1) else rng.choice([x for x in (-1, 0, 1) if x != v])
    return out


def run(sc, settings: GASettings, seed: int, k: int, decoder: PythonDecoder | None = None) -> dict:
    """One run: the best length, violations, the generation it was first reached and
    the number of evaluations made. ``decoder``: the scenario's (kept between runs)."""
    rng = random.Random(seed * 1_000_003 + k)
    random.seed(seed * 1_000_003 + k)  # DEAP's selRoulette draws from the global generator
    n, s = sc.n, settings
    decoder = decoder or PythonDecoder.from_scenario(sc, s.collision)
    evaluations = 0

    def evaluate(ind):
        nonlocal evaluations
        evaluations += 1
        fit, ind.length, ind.violations = decoder.fitness(ind[0], ind[1])
        return (fit,)

    tb = base.Toolbox()
    tb.register("select", tools.selRoulette)
    tb.register("evaluate", evaluate)

    def new():
        perm = rng.sample(range(n), n)
        labels = [rng.choice((-1, 1))] + [rng.choice((-1, 0, 1)) for _ in range(n)] + [
            rng.choice((-1, 1))]
        return creator.HGAIndividual([perm, labels])

    def clone(ind):
        c = creator.HGAIndividual([list(ind[0]), list(ind[1])])
        c.fitness.values, c.length, c.violations = ind.fitness.values, ind.length, ind.violations
        return c

    def evaluate_invalid(pop):
        for ind in pop:
            if not ind.fitness.valid:
                ind.fitness.values = tb.evaluate(ind)

    pop = [new() for _ in range(s.population)]
    evaluate_invalid(pop)
    best, best_gen = max(pop, key=lambda i: i.fitness.values[0]), 0
    for g in range(1, s.generations + 1):
        offspring = [clone(i) for i in tb.select(pop, s.population)]
        for a, b in zip(offspring[::2], offspring[1::2]):
            if rng.random() < s.pc_upper:
                a[0], b[0] = cycle_crossover(a[0], b[0], rng)
                del a.fitness.values, b.fitness.values
            if rng.random() < s.pc_lower:
                lo, hi = sorted(rng.sample(range(n + 3), 2))
                a[1][lo:hi], b[1][lo:hi] = b[1][lo:hi], a[1][lo:hi]
                del a.fitness.values, b.fitness.values
        for ind in offspring:
            if rng.random() < s.pm_upper:
                ind[0] = inversion(ind[0], rng)
                del ind.fitness.values
            labels = redraw(ind[1], s.pm_lower, rng)
            if labels != ind[1]:
                ind[1] = labels
                del ind.fitness.values
        pop = offspring
        evaluate_invalid(pop)
        top = max(pop, key=lambda i: i.fitness.values[0])
        if top.fitness.values[0] > best.fitness.values[0]:
            best, best_gen = top, g
    return {"run": k, "length": best.length, "violations": best.violations,
            "generation": best_gen, "evaluations": evaluations}


def time_runs(sc, settings: GASettings, seed: int, runs: int) -> list[float]:
    """Wall seconds of each of ``runs`` runs (one decoder for the scenario, as in main)."""
    decoder = PythonDecoder.from_scenario(sc, settings.collision)
    times = []
    for k in range(runs):
        t0 = time.perf_counter()
        run(sc, settings, seed, k, decoder)
        times.append(time.perf_counter() - t0)
    return times


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
    rows, times = [], []
    for k in range(args.runs):
        t0 = time.perf_counter()
        r = run(sc, settings, args.seed, k, decoder)
        times.append(time.perf_counter() - t0)
        feasible = r["violations"] == 0
        gap = r["length"] / opt - 1 if feasible else None
        rows.append({**r, "feasible": feasible, "gap": gap,
                     "hit": gap is not None and gap < 1e-6, "seconds": times[-1]})
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
          f"{statistics.median(times) * 1000:.0f} ms per run (median), "
          f"{statistics.median(r['evaluations'] for r in rows):.0f} evaluations per run "
          f"(median); wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
