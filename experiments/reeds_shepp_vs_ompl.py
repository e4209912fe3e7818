"""Does any OMPL path of the Reeds–Shepp car beat the model's Reeds–Shepp optimum?

On held-out scenes (the parking-like families of :mod:`hga_jax.study.parking` and the
studies' generators with the robot made a Reeds–Shepp car), one of OMPL's planners in
its ``ReedsSheppStateSpace`` plans for a few seconds, its path is judged by the model
(:func:`hga_jax.peers.judge.judge_poses`, waypoints joined by Reeds–Shepp paths, cusps
understood), and its length is compared with the exact Reeds–Shepp optimum of the model
(:func:`hga_jax.model.exact.solve`). A feasible OMPL path shorter than the optimum
would show a path the model does not hold. Prints one line per scene and a summary;
writes the rows as JSON.

Usage (needs the ``compare`` extra)::

    python3 experiments/reeds_shepp_vs_ompl.py [--scenes 5] [--seconds 2] [--runs 2]
        [--planner BITstar] [--obstacles 9] [--out results/reeds_shepp_vs_ompl.json]
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys

from hga_jax import scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.peers.judge import judge_poses
from hga_jax.peers.ompl_planner import plan
from hga_jax.study import parking, scenes

FAMILIES = parking.KINDS + ("clutter", "obstructed", "clusters")


def scene(kind: str, n: int, i: int) -> dict:
    """Scene ``i`` of a family with ``n`` obstacles, the robot a Reeds–Shepp car."""
    if kind in parking.KINDS:
        return parking.generate(kind, n, 77, i, f"{kind}_n{n:03d}_{i:03d}")
    d = scenes.generate("uniform" if kind == "clutter" else kind, n, 77, i,
                        f"{kind}_n{n:03d}_{i:03d}")
    d["robot"]["car"] = "reeds-shepp"
    return d


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", type=int, default=5, help="scenes per family")
    p.add_argument("--seconds", type=float, default=2.0, help="OMPL time per run")
    p.add_argument("--runs", type=int, default=2, help="OMPL runs per scene")
    p.add_argument("--planner", default="BITstar")
    p.add_argument("--obstacles", type=int, default=9)
    p.add_argument("--out", default=os.path.join("results", "reeds_shepp_vs_ompl.json"))
    args = p.parse_args(argv)
    rows = []
    for kind in FAMILIES:
        for i in range(args.scenes):
            d = scene(kind, args.obstacles, i)
            sc = scenario_from_dict(d, d["name"])
            opt = solve(sc)
            best = None
            for run in range(args.runs):
                poses = plan(sc, args.planner, args.seconds, seed=run)["checkpoints"][-1][1]
                if poses is None:
                    continue
                j = judge_poses(sc, poses)
                if j.feasible and (best is None or j.length < best):
                    best = j.length
            ratio = None if best is None or not opt.feasible else best / opt.length
            rows.append({"scene": d["name"], "family": kind, "optimum": opt.length,
                         "free_turn_optimum": opt.details.get("free_turn_length"),
                         "cusps": opt.details.get("cusps"), "ompl_best_feasible": best,
                         "ompl_over_optimum": ratio, "optimum_seconds": opt.seconds})
            print(f"{d['name']}: optimum {opt.length:.4f} m ({opt.details.get('cusps')} cusps, "
                  f"{1000 * opt.seconds:.1f} ms), OMPL {args.planner} best feasible "
                  + ("none" if best is None else f"{best:.4f} m (x{ratio:.4f})"), flush=True)
    ratios = [r["ompl_over_optimum"] for r in rows if r["ompl_over_optimum"] is not None]
    shorter = sum(1 for x in ratios if x < 1 - 1e-9)
    print(f"\n{len(rows)} scenes, {len(ratios)} with a feasible OMPL path; OMPL shorter than "
          f"the model's optimum on {shorter}; OMPL / optimum: median "
          f"{statistics.median(ratios) if ratios else float('nan'):.4f}, min "
          f"{min(ratios) if ratios else float('nan'):.4f}")
    os.makedirs(os.path.dirname(args.out) or ".", exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(rows, fh, indent=1)
    print(f"wrote {args.out}")
    return 1 if shorter else 0


if __name__ == "__main__":
    sys.exit(main())
