"""The free-turn car model (``turns = "free"``): the car's shortest path among the obstacles.

A car with minimum turning radius rho may turn on any circle of radius rho in free
space too, not only on the model circles (:mod:`hga_jax.model.cars.free_turns.turns`). Its
chromosomes carry a gene per leg (:mod:`hga_jax.model.cars.free_turns.legs`): straight, or over a
free circle that touches both neighbouring circles. Arcs on free circles are judged
against every obstacle, so the model needs the full collision test. Every tight-rope
path is a free-turn path, so the free-turn optimum is never longer; it is reported
beside the tight-rope optimum. Host code; metres.
"""
from __future__ import annotations

import dataclasses
import math
import time
from typing import Any

import numpy as np

from hga_jax.errors import ModelMismatchError
from hga_jax.words import count
from hga_jax.model import car_model

LEGS = car_model.GeneModule(name="legs", weights=(2, 1, 1), crossover="leg_crossover",
                            mutation="leg_mutation", pc="pc_legs", pm="pm_legs",
                            words="leg genes", straight="straight_of_best",
                            tight="tight_of_best")
"""One gene per leg: 0 a straight tangent, 1 or 2 a free circle on one side or the other;
fresh genes are straight half the time (uniform genes cost hits where the tight rope is
optimal, 91.8 % instead of 99.0 % of runs on the bundled RoboCup scene; straight ones a
third of the hits where free turns win). ``straight_of_best`` children per generation
are the parents' best with every leg straight, ``tight_of_best`` more such copies moved
as the tight rope would move them (:mod:`hga_jax.search.variation`)."""


class FreeTurns(car_model.CarModel):
    """Free turns (module doc)."""

    name = "free"
    describe = ("the car's shortest path: turns on circles of radius rho in free space too; "
                "the full collision test only")
    words = "free turns"
    optimum_name = "free-turn optimum"
    adjective = "free-turn"
    genes = (LEGS,)
    segment_flags = {"free": "free turn (radius $\\rho$)"}
    includes = (car_model.DEFAULT,)
    yardstick_note = ("Gaps and hits are measured against the free-turn optimum (turns in "
                      "free space too), not the tight-rope one. Configurations with turns = "
                      "\"free\" search free-turn chromosomes (leg genes); the others search "
                      "tight-rope paths.")

    def problem(self, collision: str) -> str | None:
        if collision != "full":
            return ("free turns need the full collision test (the paper's judges no arc "
                    f"against an obstacle), got collision {collision!r}")
        return None

    def search_arrays(self, scenario: Any, dtype: Any, collision: str,
                      with_legs: bool = False) -> Any:
        from hga_jax.model.cars.free_turns.legs import search_arrays

        return search_arrays(scenario, dtype, with_legs)

    def decode_arrays(self, scenario: Any) -> Any:
        from hga_jax.model.cars.free_turns.legs import leg_table

        return scenario.arrays(np.float64)._replace(free_legs=leg_table(scenario))

    def graph(self, scenario: Any, collision: str) -> Any:
        from hga_jax.model.cars.free_turns.turns import build

        return build(scenario)

    def solve(self, scenario: Any, collision: str) -> Any:
        return solve_free(scenario)

    def extras(self, optimum: Any) -> dict[str, Any]:
        tight = optimum.tight_rope_length
        return {"tight_rope_length": car_model.finite(tight),
                "free_arcs": optimum.free_arcs}

    def summary(self, optimum: Any) -> dict[str, Any]:
        tight = self.extras(optimum)["tight_rope_length"]
        return {"optimum_turns": self.name, "tight_rope_length": tight,
                "free_to_tight_rope": optimum.length / tight if tight else None}

    def head(self, optimum: Any) -> str:
        return ", " + count(optimum.free_arcs, "free arc")

    def notes(self, optimum: Any, searched: car_model.CarModel | None = None) -> list[str]:
        if searched is None:
            lines = [tight_rope_line(optimum)]
            if not optimum.free_arcs:  # the tight-rope optimum itself, with its chromosome
                lines += car_model.get(car_model.DEFAULT).notes(optimum, None)
            return lines
        reach = ("which the GA's leg genes express where a free circle joins two of the "
                 "path's circles" if LEGS in searched.genes else
                 "which the GA's tight-rope paths cannot reach where it is shorter")
        return [f"the optimum is the free-turn one (turns in free space too), {reach}; "
                + tight_rope_line(optimum)]


def tight_rope_line(optimum: Any) -> str:
    """The tight-rope optimum beside a free-turn one: its length and the ratio."""
    from hga_jax.model.no_path import NO_PATH

    tight = optimum.tight_rope_length
    if tight is None or not math.isfinite(tight):
        return f"tight-rope optimum: {NO_PATH}"
    if optimum.length >= tight - 1e-9 * max(1.0, tight):
        return f"tight-rope optimum {tight:.6f} m: the same path (no free turn shortens it)"
    return (f"tight-rope optimum {tight:.6f} m; free turns are "
            f"{100 * (1 - optimum.length / tight):.2f}% shorter (ratio "
            f"{optimum.length / tight:.6f})")


def solve_free(scenario: Any) -> Any:
    """The free-turn optimum (:func:`hga_jax.model.cars.free_turns.turns.shortest`), with the
    tight-rope optimum beside it. A path without free arcs that is no shorter than the
    tight-rope optimum is that optimum (with its chromosome). ``seconds``: the free-turn
    search alone. Raises :class:`ModelMismatchError` if the free-turn optimum were longer
    than the tight-rope one (the free graph holds every tight-rope path: a bug)."""
    from hga_jax.model.cars.free_turns import turns
    from hga_jax.model.exact import ExactResult, no_path, solve_tight_rope

    tight = solve_tight_rope(scenario, "full")
    t0 = time.perf_counter()
    # Only what a path shorter than the tight-rope optimum can use (the bound is exact:
    # every piece of that optimum is kept, so the search never returns longer).
    bound = tight.length * (1.0 + 1e-9) + 1e-12
    length, segs, touched, free = turns.shortest(scenario, bound)
    spent = time.perf_counter() - t0
    if not math.isfinite(length):  # no free-turn path, so no tight-rope one either
        return dataclasses.replace(no_path(scenario, "full", FREE_TURNS.name, spent),
                                   tight_rope_length=math.inf)
    if math.isfinite(tight.length) and not length <= tight.length + 1e-9 * max(1.0, tight.length):
        raise ModelMismatchError(
            f"{scenario.source}: the free-turn optimum ({length!r} m) is longer than the "
            f"tight-rope optimum ({tight.length!r} m)")
    if not free and length >= tight.length - 1e-9 * max(1.0, tight.length):
        return dataclasses.replace(tight, turns=FREE_TURNS.name, tight_rope_length=tight.length,
                                   seconds=spent)
    ratio = length / tight.length if math.isfinite(tight.length) else 0.0
    message = (f"free turns: {free} free arc(s), {100 * (1 - ratio):.2f}% shorter than the "
               "tight-rope optimum" if math.isfinite(tight.length) else
               f"free turns: {free} free arc(s); no tight-rope path exists")
    return ExactResult(length, True, "full", length, False, None, None, touched, None,
                       tight.path or tight.best_expressible, segs, spent, message,
                       turns=FREE_TURNS.name, tight_rope_length=tight.length, free_arcs=free)


FREE_TURNS = car_model.register(FreeTurns())
