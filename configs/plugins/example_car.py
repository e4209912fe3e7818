"""An example plugin: a car model of one module and one registration.

``free-legs`` is the free-turn car held to the free turns that a chromosome's leg genes
express: a free circle of radius rho that touches two circles the path turns on. Its
optimum is the best path of the GA's own chromosome space, never shorter than the
free-turn optimum and never longer than the tight-rope one, so a run's gap to it says
how well the search does on the paths it can reach.

Use it with ``hga-jax exact SCENARIO.toml --plugin configs/plugins/example_car.py
--turns free-legs`` or ``hga-jax run ... --turns free-legs``, in a study file with
``plugins = ["../plugins/example_car.py"]`` and ``turns = "free-legs"`` (or
``yardstick = "free-legs"``), or in Python by importing it before building the
settings (docs/model.md, "Adding a car model").

It inherits everything from free turns (leg genes and their operators, device arrays,
the need for the full collision test) except the graph and the optimum.
"""
import dataclasses
import math
import time

from hga_jax.model import car_model
from hga_jax.model.cars.free_turns import leg_space
from hga_jax.model.cars.free_turns.model import FreeTurns
from hga_jax.model.exact import ExactResult, no_path, solve_tight_rope


class FreeLegs(FreeTurns):
    """Free turns that leg genes express (module doc)."""

    name = "free-legs"
    describe = "free turns that leg genes express: a free circle touching two of the path's"
    adjective = "free-leg"
    optimum_name = "free-leg optimum"
    words = "free legs"
    includes = (car_model.DEFAULT,)
    yardstick_note = ("Gaps and hits are measured against the free-leg optimum: the best "
                      "path a chromosome with leg genes expresses.")

    def graph(self, scenario, collision):
        return leg_space.graph(scenario)[0]

    def solve(self, scenario, collision):
        tight = solve_tight_rope(scenario, "full")
        t0 = time.perf_counter()
        length, segments, touched, free = leg_space.shortest(scenario)
        seconds = time.perf_counter() - t0
        if not math.isfinite(length):
            return dataclasses.replace(no_path(scenario, "full", self.name, seconds),
                                       tight_rope_length=math.inf)
        if not free and length >= tight.length - 1e-9 * max(1.0, tight.length):
            return dataclasses.replace(tight, turns=self.name, tight_rope_length=tight.length,
                                       seconds=seconds)  # the tight rope's, with its chromosome
        return ExactResult(length, True, "full", length, False, None, None, touched, None,
                           tight.path or tight.best_expressible, segments, seconds,
                           f"free legs: {free} free arc(s)", turns=self.name,
                           tight_rope_length=tight.length, free_arcs=free)


FREE_LEGS = car_model.register(FreeLegs())
