"""The paper's HGA written with DEAP, the way a DEAP user would (a study peer).

Same model and settings as hga-jax's paper configuration: a chromosome is a
permutation of the obstacles plus one turning label per position; roulette
selection; per pair of parents, cycle crossover (written here: DEAP has none, and
its PMX is not the textbook one) with probability ``pc_upper`` and two-point
crossover of the labels with probability ``pc_lower``; per individual, inversion of
a random segment with probability ``pm_upper``; per label, a redraw to another
allowed value with probability ``pm_lower``; no elitism.

The fitness ``10000 / (Dist_m + 1)`` comes from a pure-Python decoder of the model
(:mod:`hga_jax.peers.python_decoder`: plain floats and ``math``, one individual at a
time), written from docs/model.md independently of hga-jax's decoder. As in DEAP's
own algorithms, only individuals that an operator changed are evaluated again.
Python's ``random`` (seeded by ``(seed, k)``) drives run ``k``, so runs are
reproducible but differ from hga-jax's run for run; the statistics compare.

Needs the ``deap`` package (the ``compare`` extra). Host code: one run at a time,
single-threaded, timed by the wall clock.
"""
from __future__ import annotations

import random
import time
from typing import Any

from deap import base, creator, tools

from hga_jax.search.settings import GASettings
from .python_decoder import PythonDecoder

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


def run(sc, settings: GASettings, seed: int, k: int, decoder: PythonDecoder | None = None
        ) -> dict[str, Any]:
    """Run ``k`` of ``seed``: the best chromosome (``perm`` from 0, ``labels``), its
    ``length`` (m) and ``violations``, the generation it was first reached, the
    evaluations made, the wall ``seconds``, and ``trace``: per generation (0 first)
    ``(seconds since the start, evaluations so far, best length, its violations)``.
    ``decoder``: the scenario's (kept between runs, as a user would)."""
    t0 = time.perf_counter()
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
    trace = [(time.perf_counter() - t0, evaluations, best.length, best.violations)]
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
        trace.append((time.perf_counter() - t0, evaluations, best.length, best.violations))
    return {"run": k, "perm": list(best[0]), "labels": list(best[1]), "length": best.length,
            "violations": best.violations, "generation": best_gen, "evaluations": evaluations,
            "seconds": time.perf_counter() - t0, "trace": trace}
