"""Summary tables of a study (CSV, Parquet and Markdown), per group of scenes and configuration.

A group is a scene family (``files`` for the study's scene files), and an obstacle
count where the family has several (:func:`hga_jax.study.table.group_labels`). Every
configuration is compared with the reference (the first configuration) on the
same runs of the same scenes; the tests and the interval methods are named in
the column headers (see :mod:`hga_jax.study.stats`). The tables here are lists of
row dicts (rates as fractions, gaps as fractions of the optimum, times in ms or
s as named); :func:`markdown` lays them out with ``DataFrame.to_markdown``.
"""
from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from hga_jax.model import car_model
from . import stats
from hga_jax.running.results import HIT_GAP

from .store import TARGETS
from .table import markdown as markdown_table, numeric

MWU = "Mann-Whitney U (gap), Holm"
FISHER = "Fisher exact (hits), Holm"


def _tag(t: float) -> str:
    return f"{round(100 * t)}pct"


def target_column(t: float) -> str:
    return "evaluations_hit" if t == 0 else f"evaluations_{_tag(t)}"


def summarize(table: pd.DataFrame, configs: list[str]) -> list[dict[str, Any]]:
    """One row per (group, configuration) with intervals, ERTs and Holm-corrected tests."""
    rows = []
    gap, hit = numeric(table, "gap"), table["hit"].to_numpy(bool)
    family, config = table["group"].to_numpy(), table["config"].to_numpy()
    scenario = table["scenario"].to_numpy()
    evaluations, time_s = numeric(table, "evaluations"), numeric(table, "time_s")
    solver = (table["solver"].to_numpy() if "solver" in table
              else np.full(len(table), "hga", object))
    compile_s = numeric(table, "compile_s") if "compile_s" in table else np.zeros(len(table))
    no_path = (table["solved"].to_numpy(object) == False) if "solved" in table else (  # noqa: E712
        np.zeros(len(table), bool))  # a planner that returned no path (OMPL)
    for group in dict.fromkeys(family.tolist()):
        in_group = family == group
        ref = in_group & (config == configs[0])
        for label in configs:
            m = in_group & (config == label)
            if not m.any():
                continue
            n, k = int(m.sum()), int(hit[m].sum())
            lo, hi = stats.wilson(k, n)
            med, mlo, mhi = stats.median_ci(gap[m])
            feas = gap[m][np.isfinite(gap[m])]
            evals = evaluations[m]
            counted = bool(np.all(np.isfinite(evals)))
            row: dict[str, Any] = {
                "group": group, "config": label, "solver": str(solver[m][0]),
                "scenes": len(set(scenario[m].tolist())), "runs": n,
                "feasible_rate": float(np.mean(np.isfinite(gap[m]))),
                "infeasible_runs": int(np.sum(~np.isfinite(gap[m]))),
                "no_path_runs": int(np.sum(no_path[m])),
                "shorter_runs": int(np.sum(feas < -HIT_GAP)),
                "gap_min": float(feas.min()) if len(feas) else math.nan,
                "hit_rate": k / n, "hit_rate_ci_low": lo, "hit_rate_ci_high": hi,
                "gap_median": med, "gap_median_ci_low": mlo, "gap_median_ci_high": mhi,
                "gap_mean_feasible": float(feas.mean()) if len(feas) else math.nan,
                "evaluations_per_run": float(evals.mean()) if counted else math.nan,
                "time_per_run_ms": 1000 * float(np.mean(time_s[m])),
                "time_per_run_median_ms": 1000 * float(np.median(time_s[m])),
                "compile_s": float(np.max(compile_s[m])),
            }
            for t in TARGETS:
                row[f"ert_evaluations_{_tag(t)}"] = (
                    stats.ert(numeric(table, target_column(t))[m], evals) if counted else math.nan)
                row[f"ert_seconds_{_tag(t)}"] = stats.ert(_seconds_to(table, t)[m], time_s[m])
            same = label != configs[0] and ref.any()
            row["reference"] = configs[0]
            row["p_gap_mwu"] = stats.mann_whitney(gap[m], gap[ref]) if same else math.nan
            row["p_hit_fisher"] = (stats.fisher(k, n, int(hit[ref].sum()), int(ref.sum()))
                                   if same else math.nan)
            rows.append(row)
    for name in ("p_gap_mwu", "p_hit_fisher"):
        for r, p in zip(rows, stats.holm([r[name] for r in rows])):
            r[name + "_holm"] = float(p)
    return rows


def _seconds_to(table: pd.DataFrame, t: float) -> np.ndarray:
    """Per run the seconds to target ``t`` (inf: never); from the evaluations to it and
    the run's seconds per evaluation in tables written before times to targets."""
    name = "time_hit" if t == 0 else f"time_{_tag(t)}"
    if name in table:
        return numeric(table, name)
    return numeric(table, target_column(t)) * numeric(table, "time_s") / numeric(
        table, "evaluations")


def by_scene(table: pd.DataFrame, configs: list[str]) -> list[dict[str, Any]]:
    """Hit rate and median gap per (scene, configuration), with the optimum."""
    rows = []
    gap, hit = numeric(table, "gap"), table["hit"].to_numpy(bool)
    scenario, config = table["scenario"].to_numpy(), table["config"].to_numpy()
    for scene in dict.fromkeys(scenario.tolist()):
        for label in configs:
            m = (scenario == scene) & (config == label)
            if m.any():
                first = table[m].iloc[0]
                rows.append({"scenario": scene, "family": first["family"],
                             "obstacles": int(first["obstacles"]), "config": label,
                             "optimum": float(first["optimum"]), "runs": int(m.sum()),
                             "hit_rate": float(hit[m].mean()),
                             "gap_median": float(np.median(gap[m])),
                             "feasible_rate": float(np.mean(np.isfinite(gap[m])))})
    return rows


def _fmt(v: Any, pct: bool = False) -> str:
    if isinstance(v, float):
        if math.isnan(v):
            return "-"
        if math.isinf(v):
            return "inf"
        return f"{100 * v:.2f}%" if pct else f"{v:.3g}"
    return str(v)


def _p(v: float) -> str:
    return "-" if math.isnan(v) else ("<1e-4" if v < 1e-4 else f"{v:.3g}")


COLUMNS = ("configuration", "solver", "runs", "hit rate [95% Wilson]",
           "median gap [95% bootstrap]", "feasible", "shorter than optimum", "ERT evals to hit",
           "ERT s to hit", "ERT s to 1%", "s/run (median)", "compile s",
           f"p gap ({MWU})", f"p hits ({FISHER})")


def _cells(r: dict[str, Any]) -> list[str]:
    """One summary row as the Markdown table's cells (rates and gaps in percent)."""
    pct = lambda name: _fmt(r[name], True)  # noqa: E731
    shorter = (f"{r['shorter_runs']} (down to {_fmt(r['gap_min'], True)})"
               if r.get("shorter_runs") else "0")
    return [str(r["config"]), str(r.get("solver", "hga")), str(r["runs"]),
            f"{pct('hit_rate')} [{pct('hit_rate_ci_low')}, {pct('hit_rate_ci_high')}]",
            f"{pct('gap_median')} [{pct('gap_median_ci_low')}, {pct('gap_median_ci_high')}]",
            f"{pct('feasible_rate')} ({r.get('infeasible_runs', 0)} infeasible"
            + (f"; {r['no_path_runs']} found no path)" if r.get("no_path_runs") else ")"),
            shorter, _fmt(r["ert_evaluations_0pct"]), _fmt(r["ert_seconds_0pct"]),
            _fmt(r["ert_seconds_1pct"]), _fmt(r.get("time_per_run_median_ms", math.nan) / 1000),
            _fmt(r.get("compile_s", math.nan)),
            _p(r["p_gap_mwu_holm"]), _p(r["p_hit_fisher_holm"])]


NOTES = (
    "Every length is the project's float64 model's; a peer's path is judged again under "
    "the full collision rule, and one that clips an obstacle counts as infeasible. "
    "A hit is a gap below 1e-6. An infeasible run is one whose path violates the model, "
    "or a planner's run that found no path (said apart). \"shorter than optimum\": feasible runs whose path is "
    "shorter than the optimum the gaps are taken to (a negative gap: the path turns in "
    "free space, which the tight-rope model does not allow). Times: seconds of one run "
    "on one core, compile excluded (a batched run: its share of the batch's "
    "core-seconds); ERT: expected running time to the target (restarts counted), "
    "evaluations or seconds; solvers that count no evaluations show \"-\".")


def setup(study, scenes, docs: list[dict[str, Any]]) -> str:
    """What was run, in words: seeds, runs, scenes per family, each configuration's budget."""
    fams: dict[str, dict[int, int]] = {}
    files = [f"{sc.name} ({sc.scenario.n} obstacles)" for sc in scenes if sc.family == "files"]
    for sc in scenes:
        if sc.family != "files":
            fams.setdefault(sc.family, {}).setdefault(sc.scenario.n, 0)
            fams[sc.family][sc.scenario.n] += 1
    fam = "; ".join(([f"scene files: {', '.join(files)}"] if files else []) + [
        f"family {f}: " + ", ".join(f"{k} with {n} obstacles" for n, k in sorted(c.items()))
        for f, c in fams.items()])
    lines = [f"Seed {study.seed}: run k of every cell is run k of this seed. Scenes "
             f"({len(scenes)}): {fam}. Gaps are to the "
             f"{car_model.get(study.yardstick).adjective} optimum.", "",
             "Budget per run of each configuration:", ""]
    for c in study.configs:
        mine = [d for d in docs if d["config"] == c.label]
        runs = study.runs_of(c)
        if c.solver == "ompl":
            what = f"OMPL {c.planner}, {c.time_limit:g} s"
        elif c.solver == "exact":
            what = "the exact solver, once per scene"
        elif c.solver == "frozen":
            what = ("the frozen-snapshot planner (the exact optimum with every robot standing "
                    "where it is at time 0, judged in time), once per scene")
        else:
            evals = sorted({d["evaluations_per_run"] for d in mine if d.get(
                "evaluations_per_run") is not None})
            span = (f"{evals[0]:,.0f}" if len(evals) == 1 else
                    f"{evals[0]:,.0f} to {evals[-1]:,.0f} (growing with the obstacle count)"
                    if evals else "not run yet")
            s = c.settings
            what = (f"{'DEAP, ' if c.solver == 'deap' else ''}population {s.population}, "
                    f"{'0 generations (random search)' if c.solver == 'random' else f'{s.generations} generations'}"
                    f"{f' + {s.generations_per_obstacle} per obstacle beyond 9' if s.generations_per_obstacle and c.solver == 'hga' else ''}"
                    f"{f' (times {s.reversing_budget} for a car that reverses)' if s.reversing_budget != 1 and c.solver == 'hga' else ''}: "
                    f"{'about ' if c.solver == 'deap' else ''}{span} evaluations"
                    f"{' (only changed individuals are evaluated again)' if c.solver == 'deap' else ''}")
        lines.append(f"- `{c.label}`: {what}; {runs} run{'s' if runs != 1 else ''} per scene"
                     + ("" if c.batch else ", each run alone"))
    return "\n".join(lines)


def brief(rows: list[dict[str, Any]], width: int = 100) -> str:
    """The terminal's view of a summary: per group, each configuration's hit rate with
    its interval, median gap and feasible share, in lines of at most ``width``
    characters (configuration names shortened with "..."); the tables with every
    column are summary.md's."""
    out = []
    for group in dict.fromkeys(r["group"] for r in rows):
        mine = [r for r in rows if r["group"] == group]
        cells = [(f"{_fmt(r['hit_rate'], True)} [{_fmt(r['hit_rate_ci_low'], True)}, "
                  f"{_fmt(r['hit_rate_ci_high'], True)}]", _fmt(r["gap_median"], True),
                  _fmt(r["feasible_rate"], True)) for r in mine]
        head = ("hit rate [95%]", "median gap", "feasible")
        cols = [max(len(h), *(len(c[i]) for c in cells)) for i, h in enumerate(head)]
        room = max(8, width - sum(cols) - 2 * len(cols) - 2)
        name = min(room, max(len("configuration"), *(len(r["config"]) for r in mine)))
        line = lambda first, rest: "  " + "  ".join(  # noqa: E731
            [first.ljust(name)] + [v.rjust(w) for v, w in zip(rest, cols)])
        out += [f"{group}:", line(_short("configuration", name), head)]
        out += [line(_short(r["config"], name), c) for r, c in zip(mine, cells)]
    return "\n".join(out)


def _short(text: str, width: int) -> str:
    return text if len(text) <= width else text[:width - 3] + "..."


def markdown(rows: list[dict[str, Any]], title: str, skipped: dict[str, str] | None = None,
             note: str | None = None, preamble: str = "") -> str:
    """Markdown text: the title, what was run (``preamble``), notes (skipped configurations
    too), one table per group."""
    out = [f"# {title}", ""] + ([preamble, ""] if preamble else []) + [NOTES, ""]
    for label, why in (skipped or {}).items():
        out += [f"Skipped `{label}`: {why}.", ""]
    if note:
        out += [f"Note: {note}.", ""]
    for group in dict.fromkeys(r["group"] for r in rows):
        mine = [r for r in rows if r["group"] == group]
        frame = pd.DataFrame([_cells(r) for r in mine], columns=list(COLUMNS))
        out += [f"## {group} (tests against `{mine[0]['reference']}`)", "",
                markdown_table(frame), ""]
    return "\n".join(out)
