"""Hit rate against evaluations (and seconds) on chosen scenes, far past the preset's budget.

Answers "would a larger budget get there?" for the scenes a study fails: each scene is
searched with ``--times`` the preset's generations (the same preset otherwise), and
the hit rate, the feasible share and the search time are read off at every budget
up to that: a run that first reached the optimum in generation ``g`` is a hit from
``population x (g + 1)`` evaluations on. A run of ``T`` times the generations draws
other generation keys than the preset's run (:mod:`hga_jax.search.run_keys`), so the
curve at 1x is another sample of the preset's hit rate, not its runs; nothing else in a
generation depends on the run's length.

Scenes are scenario files or ``kind:n:seed:index[:car]`` (a study family's generator, e.g.
the held-out ``corridors:25:201:0`` or ``behind:9:171:0:dubins``). Writes ``budget_curve.csv`` (one row per scene and budget
multiple) and ``budget_curve.png`` to ``--out``::

    python experiments/budget_curve.py corridors:25:201:0 obstructed:40:133:8 --times 8
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import sys

import numpy as np
import pandas as pd

import hga_jax as hg
from hga_jax import ConfigError, scenario_from_dict
from hga_jax.host.config import load_scenario
from hga_jax.host.output import write_file
from hga_jax.model.fitness import length_of_fitness
from hga_jax.search.settings import preset as presets
from hga_jax.study import stats
from hga_jax.study.figure_page import save
from hga_jax.study.config import KINDS
from hga_jax.study.scenes import generate

MULTIPLES = (0.25, 0.5, 1, 1.5, 2, 3, 4, 6, 8, 12, 16, 24, 32)


def scene(spec: str):
    """A scenario file, or ``kind:n:seed:index[:car]`` -> the scenario a study family's
    generator makes (``car``: the family's, as the parking-like kinds need)."""
    if spec.endswith(".toml"):
        return load_scenario(spec)
    try:
        kind, n, seed, index, *car = spec.split(":")
        if len(car) > 1:
            raise ValueError("too many fields")
        if kind not in KINDS:
            raise ValueError(f"kind must be one of {', '.join(KINDS)}, got {kind!r}")
        name = f"{kind}_n{int(n):03d}_{int(index):03d}"
        d = generate(kind, int(n), int(seed), int(index), name, car=car[0] if car else None)
        if car:
            d["robot"]["car"] = car[0]
        return scenario_from_dict(d, name)
    except ValueError as e:
        raise ConfigError(f"scene {spec!r}: expected kind:n:seed:index[:car] ({e})") from None


def curve(sc, preset: str, times: float, runs: int, seed: int, progress: bool = False
          ) -> list[dict]:
    """Rows of hit rate, feasible share and seconds per run at each budget multiple."""
    base = hg.settings_for(sc, presets(preset, "budget_curve")).for_car(sc.car).for_obstacles(sc.n)
    long = dataclasses.replace(base, generations=int(round(times * base.generations)),
                               generations_per_obstacle=0)
    res = hg.run_many(sc, long, seed=seed, runs=runs, progress=progress)
    budget = base.population * (base.generations + 1)  # the preset's evaluations
    first_hit = np.where(res.hit, base.population * (res.generation + 1), np.inf)
    fit, length = res.history["best_so_far_fitness"], res.history["best_so_far_length"]
    # feasible at generation g: the best so far carries no penalty (its fitness is its length's)
    feasible_at = np.isclose(length_of_fitness(fit), length, rtol=1e-4, atol=1e-6)
    per_eval_s = res.search_s / (runs * long.population * (long.generations + 1))
    rows = []
    for m in MULTIPLES:
        if m > times:
            break
        g = min(int(m * budget) // base.population - 1, long.generations)  # the last generation
        evals = base.population * (g + 1)
        hits = int(np.sum(first_hit <= evals))
        lo, hi = stats.wilson(hits, runs)
        rows.append({"scene": sc.name, "n": sc.n, "multiple": m, "evaluations": evals,
                     "hit_rate": hits / runs, "wilson_low": lo, "wilson_high": hi,
                     "feasible": float(np.mean(feasible_at[g])),
                     "ms_per_run": 1e3 * per_eval_s * evals, "runs": runs,
                     "optimum_m": res.optimum_length})
    return rows


def figure(table: pd.DataFrame):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.4, 3.2))
    ax = fig.add_subplot()
    for name, rows in table.groupby("scene", sort=False):
        ax.plot(rows["multiple"], 100 * rows["hit_rate"], marker="o", label=name)
        ax.fill_between(rows["multiple"], 100 * rows["wilson_low"], 100 * rows["wilson_high"],
                        alpha=0.15)
    ax.axvline(1, color="grey", lw=0.8, ls="--")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("evaluations, in multiples of the preset's budget (1 = the preset)")
    ax.set_ylabel("runs at the optimum (%)")
    ax.set_ylim(0, 101)
    ax.grid(alpha=0.3)
    # beside the axes, not over them: a curve that ends low on the right stays in view
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    fig.tight_layout()
    return fig


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("scenes", nargs="+", help="scenario files or kind:n:seed:index[:car] (a "
                   "study family's scene, e.g. corridors:25:201:0)")
    p.add_argument("--preset", default="recommended")
    p.add_argument("--times", type=float, default=8, help="generations, in multiples of the "
                   "preset's (default 8)")
    p.add_argument("--runs", type=int, default=100)
    p.add_argument("--seed", type=int, default=11)
    p.add_argument("--out", default=os.path.join("results", "budget_curve"))
    args = p.parse_args(argv)
    if not args.times >= 1 or args.runs < 1:  # NaN too
        p.error(f"--times must be >= 1 and --runs >= 1, got {args.times} and {args.runs}")
    hg.use_cpu_cores()
    rows = []
    try:
        for spec in args.scenes:
            sc = scene(spec)
            rows += curve(sc, args.preset, args.times, args.runs, args.seed, progress=True)
            at = {r["multiple"]: r for r in rows if r["scene"] == sc.name}
            print(f"{spec} ({sc.name}): " + ", ".join(
                f"{m}x {100 * r['hit_rate']:.0f} % ({r['ms_per_run']:.0f} ms)"
                for m, r in at.items() if m in (1, 2, 4, 8, 16, 32)), flush=True)
    except ConfigError as e:
        print(f"budget_curve: {e}", file=sys.stderr)
        return 2
    table = pd.DataFrame(rows)
    os.makedirs(args.out, exist_ok=True)
    write_file(os.path.join(args.out, "budget_curve.csv"), lambda fh: table.to_csv(fh, index=False))
    print(f"wrote {save(figure(table), os.path.join(args.out, 'budget_curve.png'))}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
