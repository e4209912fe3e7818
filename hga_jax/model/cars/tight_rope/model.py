"""The paper's car model: the tight rope (``turns = "tight-rope"``, the default).

A path turns only on the start and goal turning circles and on the obstacles' model
circles, and runs straight along their tangents between them (docs/model.md). A
chromosome is the permutation and the labels; the fitness looks paths up in the
scenario's turn table (:mod:`hga_jax.model.turns`) for the collision test of the run;
the exact optimum is the shortest walk in the tangent graph (:mod:`hga_jax.model.exact`).
Host code; metres.
"""
from __future__ import annotations

from typing import Any

from hga_jax.model import car_model


class TightRope(car_model.CarModel):
    """The paper's model (module doc): no genes beyond the permutation and labels, both
    collision tests."""

    name = car_model.DEFAULT
    describe = "the paper's: turns on the model circles only"
    adjective = "tight-rope"

    def search_arrays(self, scenario: Any, dtype: Any, collision: str,
                      with_legs: bool = False) -> Any:
        return scenario.search_arrays(dtype, collision, with_legs)

    def graph(self, scenario: Any, collision: str) -> Any:
        from hga_jax.model.exact import tight_rope_graph

        return tight_rope_graph(scenario, collision)

    def solve(self, scenario: Any, collision: str) -> Any:
        from hga_jax.model.exact import solve_tight_rope

        return solve_tight_rope(scenario, collision)

    def notes(self, optimum: Any, searched: car_model.CarModel | None = None) -> list[str]:
        if optimum.expressible:
            if searched is not None:
                return []
            return [f"chromosome: upper {_ints(optimum.upper)}, lower {_ints(optimum.lower)}"]
        alt = optimum.best_expressible
        return ["the optimal walk touches an obstacle twice, which no chromosome expresses; "
                + (f"best chromosome path {alt.length:.6f} m" if alt is not None else
                   "no chromosome path is known")]


def _ints(values: list[int]) -> str:
    return "[" + " ".join(str(int(v)) for v in values) + "]"


TIGHT_ROPE = car_model.register(TightRope())
