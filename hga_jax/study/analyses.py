"""Extra reports that a study file asks for with ``analyses = [...]``.

- ``paper``: on the study's first scene with the reference configuration, the
  analogues of the paper's Fig. 4 (best path found) and Fig. 5 (best fitness over
  generations: one run, and median with quartile band over all runs, the optimum
  as a line), and a table of our measurements beside the paper's claims.
- ``penalty``: how often a run's best path, feasible under the run's collision
  test, collides under the full test (the paper's Appendix B criterion misses
  segments that start inside a model circle).
- ``scaling``: per obstacle count, hit rate, gap, GA time per run and exact solver
  time.
- ``reversing``: per family and obstacle count, what backing up saves (the
  Reeds–Shepp optimum against the forward car's) and the GA's hit rate, worst scene
  too (:mod:`hga_jax.study.reversing`).
- ``per_scene``: per configuration, family and obstacle count, the distribution of
  the scenes' hit rates (worst, 10th percentile), feasible share, and each scene
  paired against the first configuration (:mod:`hga_jax.study.per_scene`).
- ``moving``: among robots that move, per configuration, family and robot count: runs
  feasible in time, hits where the optimum is certified, runs no longer than the best
  known path elsewhere, how often the frozen-snapshot plan collides in time
  (:mod:`hga_jax.study.moving_study`).
"""
from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
import pandas as pd

from hga_jax.host.config import load_scenario
from hga_jax.model.fitness import fitness_of
from hga_jax.model.path import evaluate_path, from_chromosome, gene_values, legs_from_list
from hga_jax.host.plots import headroom, plot_path
from hga_jax.host.output import write_file
from . import stats
from .figures import save, subplots
from .table import markdown, numeric, write_csv

PAPER_CLAIMS = {  # the paper's section 4 (one run on its Fig. 4 scene, MATLAB)
    "generation_optimum": 27, "generation_near_optimal": 11, "seconds_per_run": 5.0,
    "generations": 50,
}


def _pct(x: float) -> str:
    return f"{100 * x:.1f}%"


def _median_int(values) -> str:
    v = [x for x in values if x is not None and x >= 0]
    return f"{np.median(v):g} (quartiles {np.percentile(v, 25):g}-{np.percentile(v, 75):g})" \
        if v else "never"


def _paper_figures(doc, ref: str, folder: str) -> list[str]:
    """The analogues of the paper's Fig. 4 and Fig. 5 (module doc)."""
    sc = load_scenario(doc["scenario_file"])
    files = []
    best = doc["best"]
    path = evaluate_path(sc, *from_chromosome(best["upper"], best["lower"], sc.n),
                         legs=legs_from_list(best.get("legs"), sc.n, values=gene_values(sc)))
    fig = plot_path(sc, path.segments, touched=path.touched, title=(
        f"{sc.name}: best of {doc['runs']} runs, {path.length:.4f} m "
        f"(optimum {doc['optimum']:.4f} m)"))
    files.append(save(fig, os.path.join(folder, "figures", "paper_fig4_best_path.png")))

    cur = doc["curves"]
    gens = np.arange(len(cur["run0_best_fitness"]))
    opt_fit = fitness_of(doc["optimum"], 0, sc.delta)
    fig, (a1, a2) = subplots(1, 2, figsize=(10, 4), sharey=True)
    a1.plot(gens, cur["run0_best_fitness"], color="tab:blue", label="best of generation")
    a1.plot(gens, cur["run0_best_so_far_fitness"], color="tab:orange", ls="--",
            label="best so far")
    a1.set_title(f"one run (run 0 of seed {doc['seed']})", fontsize=9)
    q = np.asarray(cur["best_fitness"])
    a2.fill_between(gens, q[0], q[2], color="tab:blue", alpha=0.25, label="quartiles")
    a2.plot(gens, q[1], color="tab:blue", label="median best of generation")
    a2.plot(gens, np.asarray(cur["best_so_far_fitness"])[1], color="tab:orange", ls="--",
            label="median best so far")
    a2.set_title(f"{doc['runs']} runs", fontsize=9)
    for ax in (a1, a2):
        ax.axhline(opt_fit, color="k", lw=0.8, label="exact optimum")
        headroom(ax, opt_fit)
        ax.set_xlabel("generation")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="lower right")
    a1.set_ylabel("fitness 10000 / (Dist_m + 1)")
    fig.suptitle(f"{sc.name}: fitness over generations ({ref})", fontsize=10)
    files.append(save(fig, os.path.join(folder, "figures", "paper_fig5_fitness.png")))

    return files


def paper(study, tab: pd.DataFrame, docs, rows, folder: str, draw: bool = True) -> list[str]:
    ref = study.configs[0].label
    doc = next(d for d in docs if d["config"] == ref)
    files = _paper_figures(doc, ref, folder) if draw else []
    out = []
    family, config = tab["family"].to_numpy(), tab["config"].to_numpy()
    for group in dict.fromkeys(family.tolist()):
        m = (family == group) & (config == ref)
        n, k = int(m.sum()), int(tab["hit"].to_numpy(bool)[m].sum())
        lo, hi = stats.wilson(k, n)
        g_hit, g_near = (tab[name].to_numpy()[m] for name in ("generation_hit", "generation_1pct"))
        out.append({
            "group": group, "scenes": len(set(tab["scenario"].to_numpy()[m].tolist())), "runs": n,
            "hit_rate": k / n, "hit_rate_ci_low": lo, "hit_rate_ci_high": hi,
            "generation_hit": _median_int(g_hit), "generation_1pct": _median_int(g_near),
            "within_1pct_by_gen_11": float(np.mean((g_near >= 0) & (g_near <= 11))),
            "hit_by_gen_27": float(np.mean((g_hit >= 0) & (g_hit <= 27))),
            "ms_per_run": 1000 * float(np.mean(numeric(tab, "time_s")[m])),
        })
    write_csv(os.path.join(folder, "paper_claims.csv"), pd.DataFrame(out), missing="nan")
    run0 = [i for i, r in enumerate(doc["columns"]["run"]) if r == 0][0]
    c, first = doc["columns"], out[0]
    claims = pd.DataFrame([
        ["optimum reached by generation", PAPER_CLAIMS["generation_optimum"],
         c["generation_hit"][run0] if c["hit"][run0] else "not reached",
         f"{first['generation_hit']} among hits; {_pct(first['hit_by_gen_27'])} of runs "
         f"by generation 27"],
        ["near-optimal (within 1%) by generation", PAPER_CLAIMS["generation_near_optimal"],
         c["generation_1pct"][run0] if c["generation_1pct"][run0] >= 0 else "never",
         f"{first['generation_1pct']}; {_pct(first['within_1pct_by_gen_11'])} of runs by "
         f"generation 11"],
        ["time per run", f"about {PAPER_CLAIMS['seconds_per_run']:g} s", "-",
         f"{first['ms_per_run']:.2f} ms (batched search, compile {doc['compile_s']:.1f} s once)"],
    ], columns=["claim", "paper (one run, MATLAB)", "run 0 here", "all runs here"])
    lines = [f"# {study.name}: the paper's claims beside our measurements", "",
             f"Reference configuration `{ref}`; first scene `{doc['scenario']}` "
             f"(optimum {doc['optimum']:.4f} m).", "", markdown(claims), "",
             "Hit rate within the run's generations (95% Wilson interval):", ""]
    lines += [f"- {r['group']} ({r['scenes']} scenes, {r['runs']} runs): {_pct(r['hit_rate'])} "
              f"[{_pct(r['hit_rate_ci_low'])}, {_pct(r['hit_rate_ci_high'])}]" for r in out]
    text = "\n".join(lines) + "\n"
    write_file(os.path.join(folder, "paper_claims.md"), lambda fh: fh.write(text))
    return files + [os.path.join(folder, n) for n in ("paper_claims.csv", "paper_claims.md")]


def penalty(study, tab: pd.DataFrame, docs, rows, folder: str, draw: bool = True) -> list[str]:
    out = []
    feasible = tab["feasible"].to_numpy(bool)
    colliding = tab["violations_full"].to_numpy(int) > 0
    family, config = tab["family"].to_numpy(), tab["config"].to_numpy()
    for group in dict.fromkeys(family.tolist()):
        for c in study.configs:
            m = (family == group) & (config == c.label)
            if not m.any():
                continue
            acc = int((m & feasible).sum())
            bad = int((m & feasible & colliding).sum())
            lo, hi = stats.wilson(bad, acc) if acc else (math.nan, math.nan)
            out.append({"group": group, "config": c.label, "collision": c.settings.collision,
                        "penalty_weight": c.settings.penalty_weight, "runs": int(m.sum()),
                        "accepted": acc, "accepted_but_colliding": bad,
                        "rate": bad / acc if acc else math.nan,
                        "rate_ci_low": lo, "rate_ci_high": hi})
    write_csv(os.path.join(folder, "penalty.csv"), pd.DataFrame(out), missing="nan")
    cells = pd.DataFrame([
        [r["group"], r["config"], r["collision"], f"{r['penalty_weight']:g}", r["runs"],
         r["accepted"], f"{r['accepted_but_colliding']} ("
         + (f"{_pct(r['rate'])} [{_pct(r['rate_ci_low'])}, {_pct(r['rate_ci_high'])}]"
            if r["accepted"] else "-") + ")"] for r in out],
        columns=["group", "configuration", "collision", "penalty weight", "runs", "accepted",
                 "colliding among accepted [95% Wilson]"])
    title = "# Best paths accepted by the run's collision test but colliding under the full test"
    text = f"{title}\n\n{markdown(cells)}\n"
    write_file(os.path.join(folder, "penalty.md"), lambda fh: fh.write(text))
    return [os.path.join(folder, "penalty.csv"), os.path.join(folder, "penalty.md")]


def scaling(study, tab: pd.DataFrame, docs, rows, folder: str, draw: bool = True) -> list[str]:
    """Per configuration, scene family and obstacle count: hit rate (95% Wilson),
    feasible share, median and 90th-percentile gap (infeasible runs count as an
    infinite gap), evaluations per run, to the hit (median over hits) and by which
    99% of runs had hit, GA ms per run against the exact solver's ms per scene
    (``scaling.csv``, ``scaling.md``, ``figures/scaling.png``)."""
    out = []
    gap, hit = numeric(tab, "gap"), tab["hit"].to_numpy(bool)
    config, obstacles = tab["config"].to_numpy(), tab["obstacles"].to_numpy()
    family = tab["family"].to_numpy()
    time_s, evals = numeric(tab, "time_s"), numeric(tab, "evaluations")
    to_hit = numeric(tab, "evaluations_hit")
    for c in study.configs:
        for fam in dict.fromkeys(family.tolist()):
            for n in sorted(set(obstacles[family == fam].tolist())):
                m = (config == c.label) & (obstacles == n) & (family == fam)
                if not m.any():
                    continue
                ds = [d for d in docs if d["config"] == c.label and d["obstacles"] == n
                      and d["family"] == fam]
                k, runs = int(hit[m].sum()), int(m.sum())
                lo, hi = stats.wilson(k, runs)
                hits_at = to_hit[m][hit[m]]
                out.append({
                    "config": c.label, "family": fam, "obstacles": n, "scenes": len(ds),
                    "runs": runs, "hit_rate": k / runs, "hit_rate_ci_low": lo,
                    "hit_rate_ci_high": hi,
                    "feasible_rate": float(np.mean(np.isfinite(gap[m]))),
                    "gap_median": float(np.median(gap[m])),
                    "gap_p90": float(np.quantile(gap[m], 0.9, method="higher")),
                    "evaluations_per_run": float(np.mean(evals[m])),
                    "evaluations_to_hit_median": (float(np.median(hits_at)) if len(hits_at)
                                                  else math.nan),
                    # evaluations by which 99% of runs had hit (inf: fewer than 99% did)
                    "evaluations_to_hit_p99": float(np.quantile(
                        np.where(hit[m], to_hit[m], np.inf), 0.99, method="higher")),
                    "ga_ms_per_run": 1000 * float(np.mean(time_s[m])),
                    "ga_evaluations_per_s": float(np.sum(evals[m]) / np.sum(time_s[m])),
                    "exact_ms_median": 1000 * float(np.median([d["exact_s"] for d in ds]))})
    write_csv(os.path.join(folder, "scaling.csv"), pd.DataFrame(out), missing="nan")
    text = _scaling_markdown(out)
    write_file(os.path.join(folder, "scaling.md"), lambda fh: fh.write(text))
    files = [os.path.join(folder, "scaling.csv"), os.path.join(folder, "scaling.md")]
    if not draw:
        return files
    # Colour: the configuration; line and marker: the family; one legend below both panels.
    fams = list(dict.fromkeys(r["family"] for r in out))
    style = {f: (("-", "o"), ("--", "^"), ("-.", "s"), (":", "D"))[i % 4] for i, f in enumerate(fams)}
    fig, (a1, a2) = subplots(1, 2, figsize=(10, 4.6), layout="constrained")
    for i, c in enumerate(study.configs):
        for fam in fams:
            rs = [r for r in out if r["config"] == c.label and r["family"] == fam]
            if not rs:
                continue
            n = [r["obstacles"] for r in rs]
            rate = np.array([r["hit_rate"] for r in rs])
            err = np.array([[r["hit_rate"] - r["hit_rate_ci_low"] for r in rs],
                            [r["hit_rate_ci_high"] - r["hit_rate"] for r in rs]])
            ls, mk = style[fam]
            a1.errorbar(n, 100 * rate, yerr=100 * err, marker=mk, ls=ls, capsize=3,
                        color=f"C{i}", label=f"GA: {c.label}, {fam}")
            a2.plot(n, [r["ga_ms_per_run"] for r in rs], marker=mk, ls=ls, color=f"C{i}")
    first = [r for r in out if r["config"] == study.configs[0].label]
    for fam in dict.fromkeys(r["family"] for r in first):
        rs = [r for r in first if r["family"] == fam]
        ls, mk = style[fam]
        a2.plot([r["obstacles"] for r in rs], [r["exact_ms_median"] for r in rs], marker=mk,
                ls=ls, color="k", mfc="white", label=f"exact solver, {fam}")
    a1.set_ylabel("hit rate (%), 95% Wilson")
    a2.set_ylabel("ms per run (GA: share of a batched search)")
    a2.set_yscale("log")
    for ax in (a1, a2):
        ax.set_xlabel("obstacles")
        ax.grid(alpha=0.3)
    handles = a1.get_legend_handles_labels()
    extra = a2.get_legend_handles_labels()
    fig.legend(handles[0] + extra[0], handles[1] + extra[1], loc="outside lower center",
               ncol=3, fontsize=7, frameon=False)
    return [save(fig, os.path.join(folder, "figures", "scaling.png"))] + files


def _scaling_markdown(out: list[dict]) -> str:
    """The scaling table in Markdown (rates and gaps in %)."""
    def pct(v):
        return "inf" if math.isinf(v) else ("-" if math.isnan(v) else f"{100 * v:.2f} %")

    def num(v):
        return "-" if math.isnan(v) else f"{v:,.0f}"

    def num99(v):
        return "not within the budget" if math.isinf(v) else num(v)

    rows = [{
        "config": r["config"], "family": r["family"], "n": r["obstacles"],
        "runs": f"{r['runs']:,}",
        "hit rate [95% Wilson]": f"{pct(r['hit_rate'])} [{100 * r['hit_rate_ci_low']:.1f}, "
                                 f"{100 * r['hit_rate_ci_high']:.1f}]",
        "feasible": pct(r["feasible_rate"]), "median gap": pct(r["gap_median"]),
        "p90 gap": pct(r["gap_p90"]), "evaluations per run": num(r["evaluations_per_run"]),
        "median evaluations to the hit": num(r["evaluations_to_hit_median"]),
        "evaluations for 99% of runs to hit": num99(r["evaluations_to_hit_p99"]),
        "GA ms/run": f"{r['ga_ms_per_run']:.2f}", "exact ms/scene": f"{r['exact_ms_median']:.2f}",
    } for r in out]
    return markdown(pd.DataFrame(rows)) + "\n"


from .moving_study import moving  # noqa: E402  (its own module: robots that move)
from .per_scene import per_scene  # noqa: E402  (its own module)
from .reversing import reversing  # noqa: E402  (its own module: the Reeds-Shepp car's)

ANALYSES: dict[str, Any] = {"paper": paper, "penalty": penalty, "scaling": scaling,
                            "reversing": reversing, "per_scene": per_scene, "moving": moving}
