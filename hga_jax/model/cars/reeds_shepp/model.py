"""The Reeds–Shepp car (``car = "reeds-shepp"``): the car that also drives backward.

Reeds and Shepp (1990) gave the shortest path of a car that turns with radius rho and
drives forward or backward, changing gear at cusps (:mod:`hga_jax.model.cars.reeds_shepp.closed_form`).
Among obstacles its paths are those of free turns driven in either gear
(:mod:`hga_jax.model.cars.reeds_shepp.graph`): every free-turn path is one, so its optimum
is never longer than the free-turn optimum, which is never longer than the tight
rope's; the result reports all three. Its arcs on free circles are judged against
every obstacle, so the model needs the full collision test. A piece driven backward
carries ``"reverse": true`` in the segments of the result files; summaries count the
cusps. The GA searches its paths with leg genes of five values and the start's gear
(:mod:`hga_jax.model.cars.reeds_shepp.legs`, :mod:`hga_jax.model.cars.reeds_shepp.reversing`). Host code;
metres.
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

LEGS = car_model.GeneModule(name="legs", weights=(6, 1, 1, 1, 1, 1, 1),
                            crossover="leg_crossover", mutation="leg_mutation", pc="pc_legs",
                            pm="pm_legs", words="leg genes (with gears)", ends="end_mutation",
                            pe="pm_ends", straight="straight_of_best", tight="tight_of_best")
"""One gene per leg, seven values (:mod:`hga_jax.model.cars.reeds_shepp.reversing`): 0 a tangent, 1-2 a
free circle against the leg's first circle, 3-4 with it (a cusp), 5-6 the quarter
turns leaving the start and reaching the goal; the goal's gene, 3 or more, starts the
path backward. Fresh genes are straight half the time (so most fresh paths start
forward: on development scenes 76-77 % of runs hit on obstructed ones driven by this
car, 94-95 % on parking-like ones, against 67 % and 94 % with weights 2, 1, ...); the ends of
the path are also moved whole (``end_mutation``); ``straight_of_best`` children per
generation are the parents' best with every gene 0 (every leg a tangent driven forward),
``tight_of_best`` more such copies moved as the tight rope would move them."""


class ReedsShepp(car_model.CarModel):
    """The Reeds–Shepp car (module doc)."""

    name = "reeds-shepp"
    car = "reeds-shepp"
    reverses = True
    genes = (LEGS,)
    describe = ("the car that also drives backward, with cusps, and turns in free space "
                "too; the full collision test only")
    words = "Reeds-Shepp car"
    adjective = "Reeds-Shepp"
    optimum_name = "Reeds-Shepp optimum"
    segment_flags = {"reverse": "path {type}, driven backward"}
    includes = (car_model.DEFAULT, "free")
    yardstick_note = ("Gaps and hits are measured against the Reeds-Shepp optimum (a car "
                      "that also drives backward, turning in free space too).")

    def problem(self, collision: str) -> str | None:
        if collision != "full":
            return ("the Reeds-Shepp car needs the full collision test (the paper's judges "
                    f"no arc against an obstacle), got collision {collision!r}")
        return None

    def search_arrays(self, scenario: Any, dtype: Any, collision: str,
                      with_legs: bool = False) -> Any:
        from hga_jax.model.cars.reeds_shepp.legs import search_arrays

        return search_arrays(scenario, dtype, with_legs)

    def decode_arrays(self, scenario: Any) -> Any:
        from hga_jax.model.cars.reeds_shepp import legs

        return scenario.arrays(np.float64)._replace(tangents=legs.tangent_table(scenario),
                                                    free_legs=legs.leg_table(scenario))

    def connect(self, p: Any, q: Any, rho: float) -> list[dict[str, Any]]:
        from hga_jax.model.cars.reeds_shepp import closed_form

        return closed_form.segments(p, closed_form.shortest(p, q, rho).pieces, rho)

    def graph(self, scenario: Any, collision: str) -> Any:
        from hga_jax.model.cars.reeds_shepp.graph import build

        return build(scenario)[0]

    def solve(self, scenario: Any, collision: str) -> Any:
        return solve_reeds_shepp(scenario)

    def extras(self, optimum: Any) -> dict[str, Any]:
        tight, free = optimum.tight_rope_length, optimum.details.get("free_turn_length")
        return {"tight_rope_length": car_model.finite(tight),
                "free_turn_length": car_model.finite(free),
                "cusps": optimum.details.get("cusps", 0)}

    def summary(self, optimum: Any) -> dict[str, Any]:
        out = {"optimum_turns": self.name, **self.extras(optimum)}
        free = out["free_turn_length"]
        out["reeds_shepp_to_free_turns"] = optimum.length / free if free else None
        return out

    def head(self, optimum: Any) -> str:
        return ", " + count(optimum.details.get("cusps", 0), "cusp")

    def notes(self, optimum: Any, searched: car_model.CarModel | None = None) -> list[str]:
        free = self.extras(optimum)["free_turn_length"]
        if free is None:
            line = "free-turn optimum (forward only): no feasible path exists"
        elif optimum.length >= free - 1e-9 * max(1.0, free):
            line = f"free-turn optimum {free:.6f} m: the same (reversing does not shorten it)"
        else:
            line = (f"free-turn optimum {free:.6f} m (forward only); reversing saves "
                    f"{100 * (1 - optimum.length / free):.2f}% (ratio {optimum.length / free:.6f})")
        tight = self.extras(optimum)["tight_rope_length"]
        from hga_jax.model.no_path import NO_PATH

        if tight is None:
            return [line, f"tight-rope optimum: {NO_PATH}"]
        ratio = f" (ratio {optimum.length / tight:.6f})" if tight > 0 else ""
        return [line, f"tight-rope optimum {tight:.6f} m{ratio}"]


def solve_reeds_shepp(scenario: Any) -> Any:
    """The Reeds–Shepp optimum (:func:`hga_jax.model.cars.reeds_shepp.graph.shortest`), with the
    free-turn and tight-rope optima beside it; ``seconds``: its own search. Raises
    :class:`ModelMismatchError` if it were longer than the free-turn optimum (every
    free-turn path is a Reeds–Shepp path: a bug)."""
    from hga_jax.model.cars.free_turns.model import solve_free
    from hga_jax.model.cars.reeds_shepp import graph
    from hga_jax.model.exact import ExactResult, no_path

    free = solve_free(scenario)
    t0 = time.perf_counter()
    bound = free.length * (1.0 + 1e-9) + 1e-12
    length, segs, touched, cusps = graph.shortest(scenario, bound)
    spent = time.perf_counter() - t0
    details = {"free_turn_length": free.length if free.feasible else math.inf, "cusps": cusps}
    if not math.isfinite(length):
        return dataclasses.replace(no_path(scenario, "full", REEDS_SHEPP.name, spent),
                                   tight_rope_length=math.inf, details=details)
    if free.feasible and not length <= free.length + 1e-9 * max(1.0, free.length):
        raise ModelMismatchError(
            f"{scenario.source}: the Reeds-Shepp optimum ({length!r} m) is longer than the "
            f"free-turn optimum ({free.length!r} m)")
    backward = any(s.get("reverse") for s in segs)
    if not backward and free.feasible and length >= free.length - 1e-9 * max(1.0, free.length):
        return dataclasses.replace(free, turns=REEDS_SHEPP.name, seconds=spent,
                                   details=dict(details, cusps=0))
    message = (f"Reeds-Shepp: {cusps} cusp(s), "
               + (f"{100 * (1 - length / free.length):.2f}% shorter than the free-turn optimum"
                  if free.feasible else "no forward-only path exists"))
    return ExactResult(length, True, "full", length, False, None, None, touched, None,
                       free.best_expressible, segs, spent, message, turns=REEDS_SHEPP.name,
                       tight_rope_length=free.tight_rope_length, details=details)


REEDS_SHEPP = car_model.register(ReedsShepp())
