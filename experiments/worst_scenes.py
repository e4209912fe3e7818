"""Pictures of the scenes a study's configuration fails most: its worst scenes by hit
rate, each drawn with the path most of its missing runs ended on (the exact optimum
the study measures against, its ``yardstick``, dashed over it), and a Markdown table
of where those runs ended. Tight-rope and free-turn runs (drawn with their leg genes).

Reads a finished study folder with the ``per_scene`` analysis (``per_scene_rates.csv``),
reruns the worst cells (the same seed and runs, so the same results: run k depends on
the seed and k alone) and writes ``worst_scenes/`` in the folder::

    hga-jax study configs/studies/held_out.toml
    python experiments/worst_scenes.py results/held_out --count 6

``--config`` picks another configuration than the study's first; ``--below`` only
scenes under that hit rate (default 1: any miss).
"""
from __future__ import annotations

import argparse
import collections
import json
import os
import sys

import numpy as np
import pandas as pd

import hga_jax as hg
from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario
from hga_jax.host.output import write_file
from hga_jax.host.plots import plot_path
from hga_jax.model.exact import solve
from hga_jax.model.path import evaluate_path
from hga_jax.study.config import load_study
from hga_jax.study.figures import save
from hga_jax.study.table import markdown


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("folder", help="a finished study folder with per_scene_rates.csv")
    p.add_argument("--count", type=int, default=4, help="how many worst scenes (default 4)")
    p.add_argument("--config", help="the configuration's label (default: the study's first)")
    p.add_argument("--below", type=float, default=1.0, help="only scenes under this hit rate")
    args = p.parse_args(argv)
    if args.count < 1:
        return _fail("--count: must be >= 1, got {}".format(args.count))
    rates_file = os.path.join(args.folder, "per_scene_rates.csv")
    for need in (os.path.join(args.folder, "study.json"), rates_file):
        if not os.path.isfile(need):
            return _fail(f"{need}: not found (a finished study folder whose study file asks "
                         "for analyses = [\"per_scene\"])")
    try:
        manifest = json.load(open(os.path.join(args.folder, "study.json")))
        study = load_study(manifest["source"], manifest.get("quick", False))
    except (ValueError, KeyError, OSError, ConfigError) as e:
        return _fail(f"{os.path.join(args.folder, 'study.json')}: {e}")
    label = args.config or study.configs[0].label
    config = next((c for c in study.configs if c.label == label), None)
    if config is None or config.settings is None:
        return _fail(f"{manifest['source']}: configs: no GA configuration {label!r}")
    if config.settings.turns not in ("tight-rope", "free"):
        return _fail(f"{manifest['source']}: configs: {label!r} searches turns = "
                     f"{config.settings.turns!r}; only tight-rope and free-turn runs are drawn")
    rates = pd.read_csv(rates_file)
    rates = rates[(rates["config"] == label) & (rates["hit_rate"] < args.below)]
    worst = rates.sort_values(["hit_rate", "scenario"]).head(args.count)
    out = os.path.join(args.folder, "worst_scenes")
    os.makedirs(out, exist_ok=True)
    hg.use_cpu_cores()
    rows = []
    for _, r in worst.iterrows():
        sc = load_scenario(os.path.join(args.folder, "scenes", f"{r['scenario']}.toml"))
        res = hg.run_many(sc, config.settings, seed=study.seed, runs=int(r["runs"]),
                          turns=study.yardstick)
        opt = solve(sc, turns=study.yardstick)  # the optimum the study's hits are taken to
        ends = collections.Counter(
            (round(float(length), 4), int(v)) for length, v, h in
            zip(res.length, res.violations, res.hit) if not h)
        (length, violations), count = ends.most_common(1)[0]
        k = next(i for i in range(len(res.length)) if not res.hit[i]
                 and (round(float(res.length[i]), 4), int(res.violations[i])) == (length, violations))
        legs = None if res.legs is None else res.legs[k]  # a free-turn run's leg genes
        path = evaluate_path(sc, res.perm[k], res.labels[k], legs=legs)
        optimum = opt.path
        title = (f"{r['scenario']} ({label}): {100 * float(np.mean(res.hit)):.0f} % hit\n"
                 f"{count} of {len(res.length)} runs end at {length:.4f} m, "
                 f"{violations} violation{'' if violations == 1 else 's'} (optimum {opt.length:.4f} m, dashed)")
        fig = plot_path(sc, path.segments, touched=path.touched, title=title,
                        optimum=opt.segments,
                        violations_at=path.violations_at)
        picture = save(fig, os.path.join(out, f"{r['scenario']}.png"))
        rows.append({
            "scene": r["scenario"], "walls": sc.field.keep_inside,
            "turning radius (m)": f"{sc.min_turn_radius:.3f}",
            "hit rate": f"{100 * float(np.mean(res.hit)):.1f} %",
            "feasible": f"{100 * float(np.mean(res.feasible)):.1f} %",
            "optimum (m), touched": f"{opt.length:.4f}, "
                                    + " ".join(f"{t.obstacle}{'+' if t.label > 0 else '-'}"
                                               for t in opt.touched),
            "most common miss (m), touched": f"{length:.4f} ({count} runs), "
                                             + " ".join(f"{t.obstacle}{'+' if t.label > 0 else '-'}"
                                                        for t in path.touched),
            "ends (start, goal): optimum / miss": f"{_ends(optimum)} / {_ends(path)}",
            "picture": os.path.basename(picture)})
        print(f"{r['scenario']}: {rows[-1]['hit rate']}, picture {picture}", flush=True)
    text = markdown(pd.DataFrame(rows)) + "\n" if rows else "No scene below the hit rate given.\n"
    write_file(os.path.join(out, "worst_scenes.md"), lambda fh: fh.write(text))
    print(f"table: {os.path.join(out, 'worst_scenes.md')}")
    return 0


def _fail(message: str) -> int:
    print(f"worst_scenes: {message}", file=sys.stderr)
    return 2


def _ends(path) -> str:
    if path is None:
        return "-"
    lower = path.lower
    return f"{'+' if lower[0] > 0 else '-'}{'+' if lower[-1] > 0 else '-'}"


if __name__ == "__main__":
    sys.exit(main())
