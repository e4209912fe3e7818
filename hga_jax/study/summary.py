"""Summary tables of a study (CSV, Parquet and Markdown), per group of scenes and configuration.

A group is a scene family (``files`` for the study's scene files). Every
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

from . import stats
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
    family, config = table["family"].to_numpy(), table["config"].to_numpy()
    scenario = table["scenario"].to_numpy()
    evaluations, time_s = numeric(table, "evaluations"), numeric(table, "time_s")
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
            time_per_eval = float(np.sum(time_s[m]) / np.sum(evals))
            row: dict[str, Any] = {
                "group": group, "config": label,
                "scenes": len(set(scenario[m].tolist())), "runs": n,
                "feasible_rate": float(np.mean(np.isfinite(gap[m]))),
                "hit_rate": k / n, "hit_rate_ci_low": lo, "hit_rate_ci_high": hi,
                "gap_median": med, "gap_median_ci_low": mlo, "gap_median_ci_high": mhi,
                "gap_mean_feasible": float(feas.mean()) if len(feas) else math.nan,
                "evaluations_per_run": float(evals.mean()),
                "time_per_run_ms": 1000 * float(np.mean(time_s[m])),
            }
            for t in TARGETS:
                e = stats.ert(numeric(table, target_column(t))[m], evals)
                row[f"ert_evaluations_{_tag(t)}"] = e
                row[f"ert_seconds_{_tag(t)}"] = e * time_per_eval
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


COLUMNS = ("configuration", "runs", "hit rate [95% Wilson]", "median gap [95% bootstrap]",
           "feasible", "ERT evals to 1%", "ERT evals to hit", "ERT s to hit", "ms/run",
           f"p gap ({MWU})", f"p hits ({FISHER})")


def _cells(r: dict[str, Any]) -> list[str]:
    """One summary row as the Markdown table's cells (rates and gaps in percent)."""
    pct = lambda name: _fmt(r[name], True)  # noqa: E731
    return [str(r["config"]), str(r["runs"]),
            f"{pct('hit_rate')} [{pct('hit_rate_ci_low')}, {pct('hit_rate_ci_high')}]",
            f"{pct('gap_median')} [{pct('gap_median_ci_low')}, {pct('gap_median_ci_high')}]",
            pct("feasible_rate"), _fmt(r["ert_evaluations_1pct"]),
            _fmt(r["ert_evaluations_0pct"]), _fmt(r["ert_seconds_0pct"]),
            _fmt(r["time_per_run_ms"]), _p(r["p_gap_mwu_holm"]), _p(r["p_hit_fisher_holm"])]


def markdown(rows: list[dict[str, Any]], title: str) -> str:
    """Markdown text: the title, then one table per group."""
    out = [f"# {title}", ""]
    for group in dict.fromkeys(r["group"] for r in rows):
        mine = [r for r in rows if r["group"] == group]
        frame = pd.DataFrame([_cells(r) for r in mine], columns=list(COLUMNS))
        out += [f"## {group} (tests against `{mine[0]['reference']}`)", "",
                markdown_table(frame), ""]
    return "\n".join(out)
