"""The ways a chromosome may treat a robot that moves, compared on held-out scenes.

``Scenario.wrap_moving`` (docs/model.md, "Moving robots"): ``"at-best"`` (the default)
places a wrapped moving robot's circle where the robot is when the shortest path known
to be feasible in time passes it; ``"at-pass"`` where the standing robots' shortest
path passes it closest; ``"never"`` makes a moving robot a point that a chromosome
wraps only at the cost of a violation. This script runs the recommended preset under each on
the moving-robot families of :mod:`hga_jax.study.moving_scenes` (``leaving``,
``crossing``, ``random_moving``), on seeds no study uses, and prints per family and way:

- the hit rate against the certified optimum (runs on scenes whose standing robots'
  optimum keeps clear in time), with its 95 % Wilson interval;
- the share of runs feasible in time (every scene, Wilson interval);
- on the scenes with no certified optimum, the share of runs feasible in time and no
  longer than the shortest path feasible in time the exact module knows (relative 1e-6);
- the median excess length of the feasible runs over the best known path;
- the worst scene (the lowest of those two rates, whichever applies to it);
- ms per run (one run's share of its batch, compile excluded) and the compile seconds.

Every run of a scene uses the same seed under every way (run k is run k of ``--seed``),
and each run's yardstick is the exact module's answer for that way's scenario (the
same scene, so the same optimum, bound and best known path; the script says so where
not). Usage (from the repository root)::

    python experiments/moving_wraps.py       # 5, 9, 15 robots, 5 scenes each, 30 runs
    python experiments/moving_wraps.py --sizes 5 9 --scenes 2 --runs 20  # a quick look

``--csv FILE`` also writes one row per (scene, way).
"""
from __future__ import annotations

import argparse
import dataclasses
import math
import sys
import time

import numpy as np

FAMILIES = {"leaving": 501, "crossing": 502, "random_moving": 503}
"""The families and their held-out seeds (the study configs/studies/moving.toml uses 301-303)."""
WAYS = ("at-best", "at-pass", "never")


def scene_of(kind: str, n: int, seed: int, index: int):
    """Scene ``index`` with ``n`` robots of ``kind`` seeded ``seed``, as a Scenario."""
    from hga_jax.host.config import scenario_from_dict
    from hga_jax.study.moving_scenes import generate

    name = f"{kind}_n{n:03d}_{index:03d}"
    return scenario_from_dict(generate(kind, n, seed, index, name), name)


def run_scene(sc, way: str, runs: int, seed: int) -> dict:
    """The recommended preset's ``runs`` runs on ``sc`` under ``wrap_moving = way``."""
    import hga_jax
    from hga_jax.study.moving_study import columns

    scenario = dataclasses.replace(sc, wrap_moving=way)
    t0 = time.perf_counter()
    res = hga_jax.run_many(scenario, "recommended", runs=runs, seed=seed)
    wall = time.perf_counter() - t0
    opt = res.optimum
    cols = columns(scenario, opt, res.length, res.feasible)
    certified = bool(opt.feasible and opt.optimal)
    return {
        "scenario": sc.name, "robots": sc.n, "moving": int(sc.moving.sum()), "way": way,
        "runs": runs, "certified": certified,
        "best_known": float(opt.length) if opt.feasible else math.nan,
        "lower_bound": opt.lower_bound if opt.lower_bound is not None else math.nan,
        "best_known_expressible": bool(opt.feasible and opt.expressible),
        "feasible": int(res.feasible.sum()), "hits": int(res.hit.sum()),
        "excess": [float(x) / float(opt.length) - 1.0 for x, f in zip(res.length, res.feasible)
                   if f and opt.feasible],
        "at_best_known": int(sum(cols["at_best_known"])) if cols else int(res.hit.sum()),
        "ms_per_run": 1000 * res.search_s * res.devices / runs,
        "compile_s": res.compile_s, "wall_s": wall,
    }


def _wilson(k: int, n: int) -> str:
    if n == 0:
        return "-"
    from hga_jax.study.stats import wilson

    lo, hi = wilson(k, n)
    return f"{100 * k / n:.1f}% [{100 * lo:.1f}, {100 * hi:.1f}] of {n}"


def _excess(rows: list[dict]) -> str:
    """The median of ``length / best known - 1`` over the feasible runs of ``rows``."""
    values = [v for r in rows for v in r["excess"]]
    return f"{100 * np.median(values):.2f}%" if values else "-"


def success(r: dict) -> float:
    """A scene's rate: hits where certified, else runs no longer than the best known."""
    return (r["hits"] if r["certified"] else r["at_best_known"]) / r["runs"]


def family_rows(rows: list[dict]) -> list[dict]:
    """Per way, the family's measures (module doc) over ``rows`` (one family's)."""
    out = []
    for way in WAYS:
        mine = [r for r in rows if r["way"] == way]
        if not mine:
            continue
        cert = [r for r in mine if r["certified"]]
        other = [r for r in mine if not r["certified"]]
        worst = min(mine, key=lambda r: (success(r), r["feasible"] / r["runs"], r["scenario"]))
        out.append({
            "way": way, "scenes": len(mine),
            "certified scenes": len(cert),
            "hit rate, certified [95% Wilson]": _wilson(sum(r["hits"] for r in cert),
                                                        sum(r["runs"] for r in cert)),
            "feasible in time [95% Wilson]": _wilson(sum(r["feasible"] for r in mine),
                                                     sum(r["runs"] for r in mine)),
            "no longer than best known, other scenes [95% Wilson]": _wilson(
                sum(r["at_best_known"] for r in other), sum(r["runs"] for r in other)),
            "worst scene": f"{worst['scenario']} ({100 * success(worst):.0f}% "
                           f"{'hits' if worst['certified'] else 'at best known'}, "
                           f"{100 * worst['feasible'] / worst['runs']:.0f}% feasible)",
            "median excess over best known (feasible runs)": _excess(mine),
            "ms/run (median)": f"{np.median([r['ms_per_run'] for r in mine]):.3g}",
            "compile s": f"{sum(r['compile_s'] for r in mine):.0f}",
        })
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--families", nargs="+", default=list(FAMILIES), choices=list(FAMILIES))
    p.add_argument("--sizes", nargs="+", type=int, default=[5, 9, 15],
                   help="robots per scene, standing and moving (default 5 9 15)")
    p.add_argument("--scenes", type=int, default=5, help="scenes per family and size (default 5)")
    p.add_argument("--runs", type=int, default=30, help="runs per scene and way (default 30)")
    p.add_argument("--seed", type=int, default=7, help="the runs' seed (default 7)")
    p.add_argument("--ways", nargs="+", default=list(WAYS), choices=list(WAYS),
                   help="the ways to compare (default all three)")
    p.add_argument("--csv", help="also write one row per (scene, way) to this CSV file")
    args = p.parse_args(argv)
    if args.scenes < 1 or args.runs < 1 or min(args.sizes) < 2:
        p.error("--scenes and --runs must be >= 1, --sizes >= 2")
    import pandas as pd

    from hga_jax.model.scenario import Scenario
    from hga_jax.study.table import markdown

    if not any(f.name == "wrap_moving" for f in dataclasses.fields(Scenario)):
        print("this hga_jax has no Scenario.wrap_moving", file=sys.stderr)
        return 2
    from hga_jax.compiled import enable_compilation_cache

    enable_compilation_cache()  # as the command line does: compiled programs kept on disk
    t0 = time.perf_counter()
    rows, notes = [], []
    for kind in args.families:
        for n in args.sizes:
            for i in range(args.scenes):
                sc = scene_of(kind, n, FAMILIES[kind], i)
                pair = [run_scene(sc, way, args.runs, args.seed) for way in args.ways]
                answers = {(r["certified"], round(r["best_known"], 9)) for r in pair}
                if len(answers) > 1:
                    notes.append(f"{sc.name}: the exact module's answer differs between the "
                                 "ways (" + ", ".join(f"{r['way']} {r['best_known']:.6f} m"
                                                      for r in pair) + ")")
                for r in pair:
                    r["family"] = kind
                rows += pair
                print(f"{sc.name}: " + "; ".join(
                    f"{r['way']} {r['feasible']}/{r['runs']} feasible, "
                    f"{r['hits'] if r['certified'] else r['at_best_known']}/{r['runs']} "
                    f"{'hits' if r['certified'] else 'at best known'}" for r in pair),
                    file=sys.stderr, flush=True)
    if args.csv:
        pd.DataFrame([{k: v for k, v in r.items() if k != "excess"} for r in rows]).to_csv(
            args.csv, index=False)
    print(f"wrap_moving {' vs '.join(args.ways)}: recommended preset, {args.runs} runs per scene "
          f"(seed {args.seed}), sizes {', '.join(map(str, args.sizes))}, {args.scenes} "
          f"scenes per family and size, held-out family seeds "
          f"{', '.join(f'{k} {FAMILIES[k]}' for k in args.families)}\n")
    for kind in args.families:
        mine = [r for r in rows if r["family"] == kind]
        print(f"## {kind}\n")
        print(markdown(pd.DataFrame(family_rows(mine))))
        print()
    for note in notes:
        print(f"note: {note}")
    print(f"{time.perf_counter() - t0:.0f} s in all")
    return 0


if __name__ == "__main__":
    sys.exit(main())
