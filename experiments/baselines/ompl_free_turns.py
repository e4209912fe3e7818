"""Where a Dubins curve beats the tight-rope optimum: turns in free space.

The model's paths turn only on the start and goal turning circles and on the
obstacles' model circles; between them they run straight. A Dubins car may also
turn in free space: the shortest Dubins path between two poses is the shortest of
six words, four "curve-straight-curve" (CSC) words, which are exactly the
tight-rope paths of an empty scene, and two "curve-curve-curve" (CCC) words, which
are not. So wherever a CCC word is the shortest, OMPL's Dubins state space (and
any planner built on it) can beat the model's optimum.

This script measures where that happens, on an empty field: start at the origin
heading east, goal at a random distance (up to 8 turning radii), bearing and
heading; the model's exact optimum (hga-jax) against OMPL's exact Dubins distance
(``DubinsStateSpace.distance``, no planner involved). It then plans with BIT* on a
scene where it happens, with the bundled scene's obstacles around, and checks the
path with the model's own collision rules (:mod:`hga_jax.peers.judge`).

Usage: ``python3 experiments/baselines/ompl_free_turns.py [--pairs 2000]
[--out results/baselines]`` (needs the ``compare`` extra for OMPL).
"""
from __future__ import annotations

import argparse
import csv
import math
import os

import numpy as np

from hga_jax.host.config import load_scenario, scenario_from_dict, scenario_to_dict
from hga_jax.model.exact import solve

RHO = 0.15  # the bundled scene's turning radius (m)


def scene(goal, obstacles=(), field=None) -> dict:
    d = {"name": "free turns", "robot": {"radius": 0.09, "min_turn_radius": RHO},
         "start": {"x": 0.0, "y": 0.0, "heading_deg": 0.0},
         "goal": {"x": goal[0], "y": goal[1], "heading_deg": math.degrees(goal[2])},
         "obstacles": [dict(o) for o in obstacles]}
    if field:
        d["field"] = field
    return d


def dubins_distance(start, goal) -> float:
    from ompl import base as ob

    space = ob.DubinsStateSpace(RHO, False)
    a, b = space.allocState(), space.allocState()
    for st, (x, y, h) in ((a, start), (b, goal)):
        st.setX(x)
        st.setY(y)
        st.setYaw(h)
    return space.distance(a, b)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pairs", type=int, default=2000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", default=os.path.join("results", "baselines"))
    args = p.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    rows = []
    for i in range(args.pairs):
        d = RHO * 8 * math.sqrt(rng.random())  # uniform over a disc of radius 8 rho
        bearing, heading = rng.uniform(-math.pi, math.pi, 2)
        goal = (d * math.cos(bearing), d * math.sin(bearing), heading)
        opt = solve(scenario_from_dict(scene(goal))).length
        dub = dubins_distance((0.0, 0.0, 0.0), goal)
        rows.append({"pair": i, "distance_m": d, "bearing": bearing, "heading": heading,
                     "tight_rope_m": opt, "dubins_m": dub, "saving": 1 - dub / opt})
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "free_turns.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    saving = np.array([r["saving"] for r in rows])
    dist = np.array([r["distance_m"] for r in rows]) / RHO
    shorter = saving > 1e-9
    print(f"{args.pairs} random pose pairs on an empty field (rho = {RHO} m, distance up to 8 rho)")
    print(f"Dubins shorter than the tight-rope optimum: {shorter.sum()} pairs "
          f"({100 * shorter.mean():.1f} %); never longer: {bool((saving > -1e-9).all())}")
    for lo, hi in ((0, 2), (2, 4), (4, 8)):
        sel = (dist >= lo) & (dist < hi)
        s = saving[sel & shorter]
        print(f"  distance {lo}-{hi} rho: {sel.sum()} pairs, {100 * (sel & shorter).sum() / max(1, sel.sum()):.1f} % "
              f"shorter" + (f", saving median {100 * np.median(s):.1f} %, max {100 * s.max():.1f} %"
                            if len(s) else ""))

    # A scene where it matters: the pair with the largest saving, placed on the bundled
    # field among its robots where no model circle gets in the way.
    base = scenario_to_dict(load_scenario("configs/scenarios/robocup_paper.toml"))
    best = rows[int(np.argmax(saving))]
    ox, oy = 1.4, 0.35  # a free spot of the bundled field
    goal = (ox + best["distance_m"] * math.cos(best["bearing"]),
            oy + best["distance_m"] * math.sin(best["bearing"]), best["heading"])
    d = scene(goal, base["obstacles"], base.get("field"))
    d["start"] = {"x": ox, "y": oy, "heading_deg": 0.0}
    sc = scenario_from_dict(d)
    opt = solve(sc)
    from hga_jax.peers.judge import judge_poses
    from hga_jax.peers.ompl_planner import plan  # the study's planner set-up

    print(f"on the bundled field at ({ox}, {oy}): tight-rope optimum {opt.length:.4f} m, "
          f"Dubins distance {dubins_distance(sc.start, sc.goal):.4f} m")
    for run in range(3):
        r = plan(sc, "BITstar", 1.0)
        poses = r["checkpoints"][-1][1]
        if poses is None:
            print(f"  BIT* 1 s, run {run}: no path")
            continue
        j = judge_poses(sc, poses)
        print(f"  BIT* 1 s, run {run}: length {j.length:.4f} m (the model's), "
              f"violations under the model's full rule: {j.violations}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
