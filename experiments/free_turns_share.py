"""How often free turns beat the tight rope, by how much, and what a leg gene could express.

For each scene the exact tight-rope optimum and the exact free-turn optimum
(``solve(scene, turns="free")``) are compared, and so is the best path of a chromosome
with one gene per leg (straight, or a free circle of radius rho touching both
neighbouring circles: :func:`hga_jax.model.cars.free_turns.leg_space.shortest`, exact). "Expressed"
counts the scenes where that chromosome space reaches the free-turn optimum.

Scenes: the studies' generators (random, obstructed, clusters) at 9, 15 and 25
obstacles, and ``near``: the RoboCup field with uniform obstacles and a goal pose
within 5 rho of the start (the distances where turn-turn-turn Dubins words win), drawn
as the ``loops`` family draws them but not filtered by its keep rule.

Usage: ``python experiments/free_turns_share.py [--scenes 20] [--seed 7]``.
"""
from __future__ import annotations

import argparse
import math
import statistics
import time

import numpy as np

from hga_jax import ConfigError, scenario_from_dict
from hga_jax.model.cars.free_turns import leg_space
from hga_jax.model.exact import solve
from hga_jax.study import loops
from hga_jax.study.scenes import generate

def near_scene(rng: np.random.Generator, n: int, name: str) -> dict:
    """A ``loops`` candidate (:func:`hga_jax.study.loops.draw`) that is a valid scenario,
    before the family's keep rule: how often free turns win is measured here."""
    while True:
        d = loops.draw("loops", rng, n, name)
        if d is None:
            continue
        try:
            scenario_from_dict(d, name)
        except ConfigError:  # a pose too close to an obstacle: draw again
            continue
        return d


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=20)
    ap.add_argument("--seed", type=int, default=7)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    print("family       n  scenes  shorter  median saving    expressed  free ms  tight ms")
    for kind in ("near", "random", "obstructed", "clusters"):
        for n in (9, 15, 25):
            shorter, saving, expressible, tf, tt = 0, [], 0, [], []
            for i in range(args.scenes):
                d = (near_scene(rng, n, f"near{n}_{i}") if kind == "near"
                     else generate(kind, n, args.seed, i, f"{kind}{n}_{i}"))
                sc = scenario_from_dict(d, d["name"])
                t0 = time.perf_counter()
                free = solve(sc, turns="free")
                tf.append(free.seconds)
                tt.append(time.perf_counter() - t0 - free.seconds)
                tight = free.tight_rope_length
                if free.free_arcs and math.isfinite(tight):
                    shorter += 1
                    saving.append(1.0 - free.length / tight)
                    legs = leg_space.shortest(sc)[0]
                    expressible += legs <= free.length * (1 + 1e-9)
            med = f"{100 * statistics.median(saving):5.1f}%" if saving else "    -"
            print(f"{kind:11s} {n:3d} {args.scenes:7d} {shorter:8d} {med:>14s} "
                  f"{expressible:>8d}/{shorter:<3d} {1e3 * statistics.median(tf):8.1f} "
                  f"{1e3 * statistics.median(tt):8.1f}", flush=True)


if __name__ == "__main__":
    main()
