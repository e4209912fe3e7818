"""What a robotics user would run instead: OMPL's sampling planners in its Dubins state
space, against the exact optimum and the GA on the same scenes.

OMPL (the ``ompl`` wheel, the ``compare`` extra): ``DubinsStateSpace`` with the
scene's turning radius, forward only; states are valid when the point lies outside
every model circle and inside the field shrunk by the robot radius; default
validity-checking resolution, as a user would leave it. Planners BIT* and RRT* at
budgets of 0.25, 1 and 5 s, several seeds. Every returned path is interpolated into
densely sampled states and checked with the model's own clearance test (distance
to each obstacle centre at least its model radius, field kept); paths that fail it
are counted as invalid. OMPL's Dubins curves may turn in free space, so a valid
OMPL path can be shorter than the tight-rope optimum of hga-jax's model.

Scenes: the bundled RoboCup scene and the first obstructed scenes of
reproduce_paper (the same generator and seed). Writes ``results/baselines/ompl.csv``
and ``results/baselines/ompl_length_vs_time.png`` (gap to the exact optimum
against planning time for OMPL, the GA and the exact solver).

Usage: ``python3 experiments/baselines/ompl_dubins.py [--scenes 3] [--seeds 5]
[--budgets 0.25 1 5] [--out results/baselines]``
"""
from __future__ import annotations

import argparse
import csv
import math
import os
import statistics
import time

import numpy as np

from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.running.runner import run_many
from hga_jax.study.scenes import generate

SAMPLES = 4000  # states per checked path
TOL = 1e-7  # metres


def dense_violations(sc, xy: np.ndarray) -> int:
    """Sampled points closer than a model radius to an obstacle or off the kept field."""
    bad = np.zeros(len(xy), bool)
    if sc.n:
        d = np.hypot(xy[:, None, 0] - sc.centres[None, :, 0], xy[:, None, 1] - sc.centres[None, :, 1])
        bad |= np.any(d < sc.model_radii[None] - TOL, axis=1)
    f, r = sc.field, sc.robot_radius
    if f is not None and f.keep_inside:
        bad |= ((xy[:, 0] < f.xmin + r - TOL) | (xy[:, 0] > f.xmax - r + TOL)
                | (xy[:, 1] < f.ymin + r - TOL) | (xy[:, 1] > f.ymax - r + TOL))
    return int(bad.sum())


def plan(sc, planner: str, budget: float, seed: int) -> dict:
    from ompl import base as ob, geometric as og, util as ou

    ou.setLogLevel(ou.LOG_NONE)
    ou.RNG.setSeed(seed + 1)  # OMPL refuses seed 0
    space = ob.DubinsStateSpace(sc.min_turn_radius, False)
    f, r = sc.field, sc.robot_radius
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(0, f.xmin + r)
    bounds.setHigh(0, f.xmax - r)
    bounds.setLow(1, f.ymin + r)
    bounds.setHigh(1, f.ymax - r)
    space.setBounds(bounds)
    setup = og.SimpleSetup(space)
    cx, cy, big = sc.centres[:, 0].tolist(), sc.centres[:, 1].tolist(), sc.model_radii.tolist()

    def valid(s):
        x, y = s.getX(), s.getY()
        return space.satisfiesBounds(s) and all(
            (x - a) ** 2 + (y - b) ** 2 >= rr * rr for a, b, rr in zip(cx, cy, big))

    setup.setStateValidityChecker(valid)
    start, goal = space.allocState(), space.allocState()
    for st, (x, y, h) in ((start, sc.start), (goal, sc.goal)):
        st.setX(x)
        st.setY(y)
        st.setYaw(h)
    setup.setStartAndGoalStates(start, goal)
    si = setup.getSpaceInformation()
    setup.setPlanner({"BITstar": og.BITstar, "RRTstar": og.RRTstar}[planner](si))
    t0 = time.perf_counter()
    status = setup.solve(budget)
    seconds = time.perf_counter() - t0
    exact = str(status) == "Exact solution"
    if not exact:
        return {"solved": False, "length": math.nan, "invalid_samples": -1, "seconds": seconds}
    path = setup.getSolutionPath()
    length = path.length()
    path.interpolate(SAMPLES)
    xy = np.array([[path.getState(i).getX(), path.getState(i).getY()]
                   for i in range(path.getStateCount())])
    return {"solved": True, "length": length, "invalid_samples": dense_violations(sc, xy),
            "seconds": seconds}


def scenes(count: int):
    out = [load_scenario("configs/scenarios/robocup_paper.toml")]
    for i in range(count - 1):  # reproduce_paper's family: obstructed, 9 obstacles, seed 1
        name = f"obstructed9_n009_{i:03d}"
        out.append(scenario_from_dict(generate("obstructed", 9, 1, i, name), name))
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenes", type=int, default=3)
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--budgets", type=float, nargs="+", default=[0.25, 1.0, 5.0])
    p.add_argument("--planners", nargs="+", default=["BITstar", "RRTstar"])
    p.add_argument("--ga-runs", type=int, default=1000)
    p.add_argument("--out", default=os.path.join("results", "baselines"))
    args = p.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for sc in scenes(args.scenes):
        opt = solve(sc)
        ga = run_many(sc, seed=0, runs=args.ga_runs)
        ga_gap = ga.gap[ga.feasible]
        rows.append({"scenario": sc.name, "method": "exact", "budget_s": math.nan, "seed": -1,
                     "solved": True, "length": opt.length, "gap": 0.0, "invalid": False,
                     "seconds": opt.seconds})
        rows.append({"scenario": sc.name, "method": "GA run (paper, median)", "budget_s": math.nan,
                     "seed": 0, "solved": True, "length": float(np.median(ga.length[ga.feasible])),
                     "gap": float(np.median(ga_gap)), "invalid": False,
                     "seconds": ga.search_s / args.ga_runs})
        rows.append({"scenario": sc.name, "method": f"GA best of {args.ga_runs} runs",
                     "budget_s": math.nan, "seed": 0, "solved": True, "length": ga.best.length,
                     "gap": ga.best.length / opt.length - 1, "invalid": False,
                     "seconds": ga.search_s})  # compile (once per shape) excluded
        for planner in args.planners:
            for budget in args.budgets:
                for seed in range(args.seeds):
                    r = plan(sc, planner, budget, seed)
                    rows.append({"scenario": sc.name, "method": planner, "budget_s": budget,
                                 "seed": seed, "solved": r["solved"], "length": r["length"],
                                 "gap": r["length"] / opt.length - 1,
                                 "invalid": r["invalid_samples"] > 0, "seconds": r["seconds"]})
    path = os.path.join(args.out, "ompl.csv")
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    for planner in args.planners:
        for budget in args.budgets:
            rs = [r for r in rows if r["method"] == planner and r["budget_s"] == budget]
            ok = [r for r in rs if r["solved"] and not r["invalid"]]
            shorter = [r for r in ok if r["gap"] < -1e-9]
            print(f"{planner} {budget:g} s: {len(rs)} plans, {sum(r['solved'] for r in rs)} solved, "
                  f"{sum(r['solved'] and r['invalid'] for r in rs)} invalid under the model's test, "
                  f"median gap of valid ones "
                  f"{statistics.median([r['gap'] for r in ok]) if ok else math.nan:.2%}, "
                  f"{len(shorter)} shorter than the tight-rope optimum"
                  + (f" (by up to {-min(r['gap'] for r in shorter):.2%})" if shorter else ""))
    _figure(rows, args, os.path.join(args.out, "ompl_length_vs_time.png"))
    print(f"wrote {path}")
    return 0


def _figure(rows, args, path):
    from hga_jax.study.figures import save, subplots

    fig, ax = subplots(figsize=(7, 4.5))
    for planner, colour in zip(args.planners, ("tab:blue", "tab:green")):
        for budget in args.budgets:
            rs = [r for r in rows if r["method"] == planner and r["budget_s"] == budget
                  and r["solved"] and not r["invalid"]]
            if rs:
                ax.scatter([r["seconds"] for r in rs], [100 * r["gap"] for r in rs], s=12,
                           color=colour, alpha=0.6,
                           label=planner if budget == args.budgets[0] else None)
    for method, marker, colour in (("GA run (paper, median)", "o", "tab:orange"),
                                   (f"GA best of {args.ga_runs} runs", "D", "tab:red"),
                                   ("exact", "*", "k")):
        rs = [r for r in rows if r["method"] == method]
        ax.scatter([r["seconds"] for r in rs], [100 * r["gap"] for r in rs], marker=marker,
                   s=40, color=colour, label=method)
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xscale("log")
    ax.set_xlabel("planning time (s); GA run: its share of a batched search")
    ax.set_ylabel("length / exact tight-rope optimum - 1 (%)")
    ax.set_title("OMPL (valid paths), GA and exact solver on the same scenes", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    save(fig, path)


if __name__ == "__main__":
    raise SystemExit(main())
