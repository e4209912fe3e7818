"""Extra reports that a study file asks for with ``analyses = [...]``.

- ``paper``: on the study's first scene with the reference configuration, the
  analogues of the paper's Fig. 4 (the best path found, above the typical run's: the
  median run, run again from its seed) and Fig. 5 (best fitness over generations: one
  run, and median with quartile band over all runs, the optimum as a line), and a
  table of our measurements beside the paper's claims.
- ``penalty``: how often a run's best path, feasible under the run's collision
  test, collides under the full test (the paper's Appendix B criterion misses
  segments that start inside a model circle).
- ``scaling``: per obstacle count, hit rate, gap, time per run and the exact solver's
  time (one per scene); where every scene has one size, the figure is per
  configuration.
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
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from hga_jax.host.config import load_scenario
from hga_jax.model.fitness import fitness_of
from hga_jax.model.path import evaluate_path, from_chromosome, gene_values, legs_from_list
from hga_jax.host.plots import headroom, plot_path
from hga_jax.host.output import write_file
from hga_jax.running.runner import run_many
from . import stats
from .figure_page import DPI, wrap
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


def typical_run(doc) -> int:
    """The index (in the cell's columns) of its typical run: the median of its runs
    ranked as the best run is chosen (:func:`~hga_jax.running.results.best_run`:
    feasible first, then fewer violations, then shorter; the lower median of an even
    count)."""
    c = doc["columns"]
    length = np.asarray(c["length"], np.float64)
    order = np.lexsort((np.arange(length.size), length, np.asarray(c["violations"])))
    return int(order[(length.size - 1) // 2])


def _outcome(length: float, violations: int, optimum: float) -> str:
    """How a run ended, for a panel's title: against the optimum, or its violations."""
    if violations:
        return f"infeasible ({violations} violation{'s' if violations > 1 else ''})"
    gap = length / optimum - 1.0
    return "the optimum" if gap < 1e-6 else f"{100 * gap:.2f} % over the optimum"


def paper_path_figure(sc, doc, best, typical, k: int) -> Figure:
    """The best run's path beside the typical run's (``best``, ``typical``: their
    :class:`~hga_jax.model.path.Path`; ``k``: the typical run's index in the cell's
    columns), one above the other, each titled with its run, length and gap; the
    figure's title says how many runs reached the optimum."""
    c, n, opt = doc["columns"], doc["runs"], doc["optimum"]
    hits = int(sum(bool(h) for h in c["hit"]))
    j = doc["best"]["run"]
    fig = Figure(figsize=(8.0, 11.0), layout="constrained", dpi=DPI)
    top, bottom = fig.subfigures(2, 1)
    panels = ((top, best, f"best of {n} runs (run {j})"),
              (bottom, typical, f"typical run (run {c['run'][k]}, the median of {n})"))
    for sub, path, what in panels:
        plot_path(sc, path.segments, touched=path.touched, violations_at=path.violations_at,
                  ax=sub.add_subplot(), title=(f"{what}: {path.length:.4f} m, "
                                               f"{_outcome(path.length, path.violations, opt)}"))
    fig.suptitle(f"{sc.name}: optimum {opt:.4f} m, reached by {hits} of {n} runs",
                 fontsize=13)
    return fig


def _paper_figures(doc, config, folder: str) -> list[str]:
    """The analogues of the paper's Fig. 4 (the best run's path, and the typical run's:
    :func:`typical_run`, run again from its seed, which gives the same run) and Fig. 5
    (module doc)."""
    ref = config.label
    sc = load_scenario(doc["scenario_file"])
    files = []
    best = doc["best"]
    values = gene_values(sc)
    path = evaluate_path(sc, *from_chromosome(best["upper"], best["lower"], sc.n),
                         legs=legs_from_list(best.get("legs"), sc.n, values=values))
    k = typical_run(doc)
    res = run_many(sc, config.settings, seed=doc["seed"], runs=1,
                   first_run=int(doc["columns"]["run"][k]), exact=False)
    typical = evaluate_path(sc, res.perm[0], res.labels[0],
                            legs=None if res.legs is None else res.legs[0])
    fig = paper_path_figure(sc, doc, path, typical, k)
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
    files = _paper_figures(doc, study.configs[0], folder) if draw else []
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
    99% of runs had hit, ms per run against the exact solver's ms per scene
    (:func:`exact_seconds`: one time per scene, the same in every row of a group)
    (``scaling.csv``, ``scaling.md``, ``figures/scaling.png``)."""
    out = []
    gap, hit = numeric(tab, "gap"), tab["hit"].to_numpy(bool)
    config, obstacles = tab["config"].to_numpy(), tab["obstacles"].to_numpy()
    family = tab["family"].to_numpy()
    time_s, evals = numeric(tab, "time_s"), numeric(tab, "evaluations")
    to_hit = numeric(tab, "evaluations_hit")
    exact = exact_seconds(docs)
    for c in study.configs:
        for fam in dict.fromkeys(family.tolist()):
            for n in sorted(set(obstacles[family == fam].tolist())):
                m = (config == c.label) & (obstacles == n) & (family == fam)
                if not m.any():
                    continue
                ds = [d for d in docs if d["config"] == c.label and d["obstacles"] == n
                      and d["family"] == fam]
                scenes = {d["scenario"] for d in docs if d["obstacles"] == n
                          and d["family"] == fam and d["scenario"] in exact}
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
                    "exact_ms_median": (1000 * float(np.median([exact[s] for s in scenes]))
                                        if scenes else math.nan)})
    write_csv(os.path.join(folder, "scaling.csv"), pd.DataFrame(out), missing="nan")
    text = _scaling_markdown(out)
    write_file(os.path.join(folder, "scaling.md"), lambda fh: fh.write(text))
    files = [os.path.join(folder, "scaling.csv"), os.path.join(folder, "scaling.md")]
    if not draw:
        return files
    fig = scaling_figure(study.configs, out)
    return [save(fig, os.path.join(folder, "figures", "scaling.png"))] + files


def exact_seconds(docs) -> dict[str, float]:
    """The exact solver's seconds on each scene, one number per scene: its own cell's
    where the study runs the exact solver (solver ``"exact"``), else the median of the
    solves the study's cells made of the scene (each cell solves its scene's optimum
    once, for the gaps). Scenes without a solve are left out."""
    own: dict[str, list[float]] = {}
    solves: dict[str, list[float]] = {}
    for d in docs:
        if d.get("exact_s") is not None:
            into = own if d.get("solver") == "exact" else solves
            into.setdefault(d["scenario"], []).append(float(d["exact_s"]))
    return {s: float(np.median(own.get(s) or solves[s])) for s in {**solves, **own}}


def _config_name(c) -> str:
    """A configuration's name in a figure: the GA's with "GA: " before it, a peer's its own."""
    return f"GA: {c.label}" if getattr(c, "solver", "hga") == "hga" else c.label


FAMILY_STYLES = (("-", "o"), ("--", "^"), ("-.", "s"), (":", "D"), ("-", "v"), ("--", "P"))


def scaling_figure(configs, out: list[dict]):
    """Hit rate (95% Wilson) and ms per run against the obstacle count: colour the
    configuration, line and marker the family, the exact solver's time per scene as
    black open markers where the study does not run it as a configuration of its own.
    Where every scene has one size, the x axis is the configurations instead (each
    family's point beside the others'), and the axis label gives the size."""
    fams = list(dict.fromkeys(r["family"] for r in out))
    style = {f: FAMILY_STYLES[i % len(FAMILY_STYLES)] for i, f in enumerate(fams)}
    sizes = sorted({r["obstacles"] for r in out})
    drawn = [c for c in configs if any(r["config"] == c.label for r in out)]
    own_exact = any(getattr(c, "solver", "hga") == "exact" for c in drawn)
    first = [r for r in out if drawn and r["config"] == drawn[0].label]
    reference = [] if own_exact else [r for r in first if math.isfinite(r["exact_ms_median"])]
    fig, (a1, a2) = subplots(1, 2, figsize=(10, 4.6), layout="constrained")
    handles: dict[str, Any] = {}
    if len(sizes) == 1:  # one size: a strip per configuration, families side by side
        names = [_config_name(c) for c in drawn] + (["exact solver"] if reference else [])
        step = min(0.14, 0.7 / max(len(fams), 1))
        for i, c in enumerate(drawn):
            for j, fam in enumerate(fams):
                rs = [r for r in out if r["config"] == c.label and r["family"] == fam]
                if not rs:
                    continue
                x = [i + (j - (len(fams) - 1) / 2) * step]
                r, mk = rs[0], style[fam][1]
                a1.errorbar(x, [100 * r["hit_rate"]],
                            yerr=[[100 * (r["hit_rate"] - r["hit_rate_ci_low"])],
                                  [100 * (r["hit_rate_ci_high"] - r["hit_rate"])]],
                            marker=mk, ls="none", capsize=3, color=f"C{i}", gid=c.label)
                a2.plot(x, [r["ga_ms_per_run"]], marker=mk, ls="none", color=f"C{i}",
                        gid=c.label)
        for j, fam in enumerate(fams):
            r = [r for r in reference if r["family"] == fam]
            if r:
                a2.plot([len(drawn) + (j - (len(fams) - 1) / 2) * step],
                        [r[0]["exact_ms_median"]], marker=style[fam][1], ls="none", color="k",
                        mfc="white", gid="exact solver")
        for fam in fams:
            handles[fam] = Line2D([], [], marker=style[fam][1], ls="none", color="0.3")
        if reference:
            handles["exact solver (its time per scene)"] = Line2D(
                [], [], marker="o", ls="none", color="k", mfc="white")
        for ax, shown in ((a1, names[:len(drawn)]), (a2, names)):  # no hit rate: the reference
            ax.set_xticks(range(len(shown)), [wrap(n, 1.3, 8) for n in shown], fontsize=8)
            ax.set_xlim(-0.6, len(names) - 0.4)
            ax.set_xlabel(f"configuration (every scene has {sizes[0]} obstacles)")
        title = "family (marker)"
    else:
        for i, c in enumerate(drawn):
            for fam in fams:
                rs = [r for r in out if r["config"] == c.label and r["family"] == fam]
                if not rs:
                    continue
                n = [r["obstacles"] for r in rs]
                rate = np.array([r["hit_rate"] for r in rs])
                err = np.array([[r["hit_rate"] - r["hit_rate_ci_low"] for r in rs],
                                [r["hit_rate_ci_high"] - r["hit_rate"] for r in rs]])
                ls, mk = style[fam]
                label = f"{_config_name(c)}, {fam}"
                handles[label] = a1.errorbar(n, 100 * rate, yerr=100 * err, marker=mk, ls=ls,
                                             capsize=3, color=f"C{i}", gid=c.label)
                a2.plot(n, [r["ga_ms_per_run"] for r in rs], marker=mk, ls=ls, color=f"C{i}",
                        gid=c.label)
        for fam in fams:
            rs = [r for r in reference if r["family"] == fam]
            if rs:
                ls, mk = style[fam]
                handles[f"exact solver (its time per scene), {fam}"], = a2.plot(
                    [r["obstacles"] for r in rs], [r["exact_ms_median"] for r in rs],
                    marker=mk, ls=ls, color="k", mfc="white", gid="exact solver")
        for ax in (a1, a2):
            ax.set_xlabel("obstacles")
            ax.set_xticks(sizes)
        title = None
    a1.set_ylabel("hit rate (%), 95% Wilson")
    a1.set_ylim(-5, 105)
    a2.set_ylabel("ms per run (GA: share of a batched search)")
    a2.set_yscale("log")
    for ax in (a1, a2):
        ax.grid(alpha=0.3)
    fig.legend(list(handles.values()), list(handles), loc="outside lower center",
               ncol=min(3, max(len(handles), 1)), fontsize=7, frameon=False, title=title,
               title_fontsize=7)
    return fig


def _scaling_markdown(out: list[dict]) -> str:
    """The scaling table in Markdown (rates and gaps in %), "-" where a value is
    missing, and a note on what the columns hold."""
    def pct(v):
        return "inf" if math.isinf(v) else ("-" if math.isnan(v) else f"{100 * v:.2f} %")

    def num(v):
        return f"{v:,.0f}" if math.isfinite(v) else "-"

    def num99(v, counted):
        if not counted:
            return "-"
        return "not within the budget" if math.isinf(v) else num(v)

    def ms(v):
        return f"{v:.2f}" if math.isfinite(v) else "-"

    rows = [{
        "config": r["config"], "family": r["family"], "n": r["obstacles"],
        "runs": f"{r['runs']:,}",
        "hit rate [95% Wilson]": f"{pct(r['hit_rate'])} [{100 * r['hit_rate_ci_low']:.1f}, "
                                 f"{100 * r['hit_rate_ci_high']:.1f}]",
        "feasible": pct(r["feasible_rate"]), "median gap": pct(r["gap_median"]),
        "p90 gap": pct(r["gap_p90"]), "evaluations per run": num(r["evaluations_per_run"]),
        "median evaluations to the hit": num(r["evaluations_to_hit_median"]),
        "evaluations for 99% of runs to hit": num99(
            r["evaluations_to_hit_p99"], math.isfinite(r["evaluations_per_run"])),
        "ms/run": ms(r["ga_ms_per_run"]), "exact ms/scene": ms(r["exact_ms_median"]),
    } for r in out]
    note = ("\n\"-\": none (the evaluation columns of a solver that counts no "
            "evaluations, such as OMPL's planners and the exact solver; the median to the hit "
            "where no run hit). \"inf\": an infinite gap (most runs infeasible). ms/run: a "
            "run's share of its batch's search (a GA) or its own time (a peer). exact "
            "ms/scene: the exact solver's time on each scene (its own runs where the study "
            "runs it, else the median of the solves the cells made of the scene), median over "
            "the group's scenes: the same in every row of a group.\n")
    return markdown(pd.DataFrame(rows)) + "\n" + note


from .moving_study import moving  # noqa: E402  (its own module: robots that move)
from .per_scene import per_scene  # noqa: E402  (its own module)
from .reversing import reversing  # noqa: E402  (its own module: the Reeds-Shepp car's)

ANALYSES: dict[str, Any] = {"paper": paper, "penalty": penalty, "scaling": scaling,
                            "reversing": reversing, "per_scene": per_scene, "moving": moving}
