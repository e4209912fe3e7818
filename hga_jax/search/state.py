"""The state of a run and what it records: typed pytrees of the GA loop.

A state holds one run's population (``P`` chromosomes with their evaluation), its
best-so-far, the number of generations made, the problem (the scenario's device
arrays), the settings' structure (static: no arrays, part of a compiled program's
identity) and their rates (arrays, so that configurations differing only in rates
run one program: :data:`~hga_jax.search.settings.RATES`). Lengths are metres without penalty; fitness is ``10000 / (Dist_m + 1)``.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import jax.numpy as jnp
import numpy as np

from hga_jax.model.reductions import tree_sum
from hga_jax.model.scenario import ScenarioArrays

from hga_jax.jax_compat import static_pytree
from .settings import GASettings


class Population(NamedTuple):
    """A population of P chromosomes with their evaluation."""

    perm: Any  # (P, n) int32
    labels: Any  # (P, n + 2) int32
    fitness: Any  # (P,)
    length: Any  # (P,) metres, without penalty
    violations: Any  # (P,) int32
    legs: Any = None  # (P, n + 2) int32 leg genes (free turns), in the labels' binding


class Best(NamedTuple):
    """Best-so-far individual of a run and the generation it was first reached."""

    perm: Any  # (n,)
    labels: Any  # (n + 2,)
    fitness: Any  # ()
    length: Any  # () metres
    violations: Any  # ()
    generation: Any  # () int32
    legs: Any = None  # (n + 2,) positional leg genes (free turns), else None



static_pytree(GASettings)  # settings ride in the state as static data


class GAState(NamedTuple):
    """A run between two generations. ``problem`` is None inside programs that pass
    the scenario's arrays apart (the runner's blocks), so they are not carried."""

    pop: Population
    best: Best
    generation: Any  # () int32: generations made so far, so the number of the next one
    problem: Any  # ScenarioArrays (float32 or float64, with legs if the settings use them)
    settings: GASettings  # static: the structure, without its rates (GASettings.structure)
    rates: Any = None  # Rates: the settings' rates, data of the program (GASettings.rates)


class Record(NamedTuple):
    """What a run records per generation."""

    best_fitness: Any  # best fitness in this generation's population
    mean_fitness: Any  # mean fitness of this generation's population
    best_so_far_fitness: Any
    best_so_far_length: Any  # metres, without penalty
    best_so_far_violations: Any


def blank(problem: ScenarioArrays, settings: GASettings) -> GAState:
    """A run before generation 0: an empty population (generation 0 replaces it whole)
    and a best-so-far that any individual beats. Made with numpy (no device program
    runs), in the shapes and dtypes of every later state."""
    n, p = problem.centres.shape[0], settings.population
    dt = problem.centres.dtype
    free = bool(settings.model.genes)  # the car model adds a module of genes
    pop = Population(np.zeros((p, n), np.int32), np.zeros((p, n + 2), np.int32),
                     np.zeros(p, dt), np.zeros(p, dt), np.zeros(p, np.int32),
                     np.zeros((p, n + 2), np.int32) if free else None)
    best = Best(np.zeros(n, np.int32), np.zeros(n + 2, np.int32), np.array(-np.inf, dt),
                np.zeros((), dt), np.zeros((), np.int32), np.zeros((), np.int32),
                np.zeros(n + 2, np.int32) if free else None)
    return GAState(pop, best, np.zeros((), np.int32), problem, settings.structure(),
                   settings.rates(dt))


def record(state: GAState) -> Record:
    """What a run records of the generation ``state`` holds (the history's row)."""
    pop, best = state.pop, state.best
    mean = tree_sum(pop.fitness) / pop.fitness.shape[-1]
    return Record(jnp.max(pop.fitness), mean, best.fitness, best.length, best.violations)
