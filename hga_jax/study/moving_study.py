"""Studies among robots that move: the columns in time, the frozen-snapshot planner, and
the analysis ``moving``.

Among robots that move (docs/model.md, "Moving robots") a run is *feasible in time* when
its path keeps every standing robot's rules and every moving robot's model radius at the
moment the car is there: a cell's ``feasible`` column, as everywhere (the float64
decoder's count, which is the check in time on such scenes). Gaps are to the yardstick of
:attr:`hga_jax.running.results.RunsResult.optimum_length`: the optimum where the exact
module certifies one, else the standing robots' optimum, a lower bound that no path
feasible in time may reach. So a cell on a scene with robots that move also keeps, per
run (:func:`columns`):

- ``certified``: whether the scene's optimum is certified (the standing robots' optimum
  keeps clear in time); a hit counts only there;
- ``best_known``: the length of the shortest path feasible in time that the exact module
  knows (the optimum where certified), m;
- ``at_best_known``: the run's path is feasible in time and no longer than that path
  (to a relative 1e-6, the hit's tolerance);
- ``best_known_expressible``: whether the exact module gives that path as a chromosome of
  the scenario (one found by freezing a moving robot where it gets in the way wraps a
  copy it does not map to one; with ``wrap_moving = "at-pass"`` a chromosome that wraps
  the robot where the car passes it may still match it, with ``"never"`` none can).

The solver ``"frozen"`` (:func:`frozen_cell`) is what a planner without time returns: the
exact optimum of the scene with every robot standing where it is at time 0, judged in
time by :func:`hga_jax.model.in_time.clearance.segment_hits` (float64). Its cell adds
``frozen_found`` (a path among the frozen robots exists), ``frozen_collides`` (it does,
and meets a moving robot in time; missing without a path) and ``frozen_hits`` (the
(segment, moving robot) pairs that meet). Its time is the static solve's.

The analysis ``moving`` (``moving.csv``, ``moving.md``) gives, per configuration, family
and robot count: runs feasible in time, the hit rate on the scenes with a certified
optimum, on the others the share of runs no longer than the best known path (each with
its 95 % Wilson interval), the scenes of each kind, how often the frozen plan collides in
time (from the study's frozen cells, over the group's scenes), and the time per run.
A scene where nothing moves counts as certified (its optimum is the optimum). Host code.
"""
from __future__ import annotations

import dataclasses
import math
import os
from typing import Any

import numpy as np
import pandas as pd

from hga_jax.host.output import write_file
from hga_jax.running.results import HIT_GAP
from . import stats
from .table import markdown, numeric, write_csv


def yardstick(optimum: Any) -> float | None:
    """The length a cell's gaps are taken to (m): the optimum, or among robots that move
    where none is certified the standing robots' optimum (a lower bound); None without
    one. As :attr:`hga_jax.running.results.RunsResult.optimum_length`."""
    if optimum is None:
        return None
    if not optimum.optimal:
        return optimum.lower_bound
    return float(optimum.length) if optimum.feasible else None


def columns(scenario: Any, optimum: Any, length, feasible) -> dict[str, list]:
    """The per-run columns in time of a cell (module doc); {} where nothing moves."""
    if not scenario.has_motion:
        return {}
    n = len(length)
    certified = bool(optimum is not None and optimum.feasible and optimum.optimal)
    best = float(optimum.length) if optimum is not None and optimum.feasible else None
    at_best = [bool(f) and best is not None and float(x) <= best * (1.0 + HIT_GAP)
               for x, f in zip(length, feasible)]
    expressible = bool(optimum is not None and optimum.feasible and optimum.expressible)
    return {"certified": [certified] * n, "best_known": [best] * n,
            "at_best_known": [bool(v) for v in at_best],
            "best_known_expressible": [expressible] * n}


def frozen_plan(scenario: Any, turns: str | None = None):
    """``(plan, hits)``: the exact optimum of ``scenario`` with every robot standing where
    it is at time 0 (:class:`~hga_jax.model.exact.ExactResult`), and its (segment, moving
    robot) pairs that meet in time (empty without a path, or where nothing moves)."""
    from hga_jax.model.exact import solve
    from hga_jax.model.in_time import clearance

    snapshot = dataclasses.replace(scenario, velocities=None) if scenario.has_motion else scenario
    plan = solve(snapshot) if turns is None else solve(snapshot, turns=turns)
    hits = clearance.segment_hits(scenario, plan.segments) if plan.feasible else []
    return plan, hits


def frozen_cell(study, config, scene, optimum) -> dict[str, Any]:
    """The cell of the solver ``"frozen"`` on ``scene`` (module doc): one run."""
    from .solvers import peer_document

    plan, hits = frozen_plan(scene.scenario, study.yardstick)
    found = bool(plan.feasible)
    length = float(plan.length) if found else math.inf
    violations = len(hits) if found else 1
    opt = yardstick(optimum)
    ok = found and not hits
    gap = math.inf if opt is None or not ok else length / opt - 1.0
    row = {"length": length, "violations": violations, "violations_full": violations,
           "time_s": plan.seconds, "evaluations": None, "generation_best": None,
           "trace_t": [plan.seconds], "trace_gap": [gap]}
    doc = peer_document(study, config, scene, optimum, [row])
    doc["columns"]["solved"] = [found]
    doc["columns"]["frozen_found"] = [found]
    doc["columns"]["frozen_collides"] = [bool(hits)] if found else [None]
    doc["columns"]["frozen_hits"] = [len(hits)]
    return doc


# ---------------------------------------------------------------------------
# The analysis.

def _bools(tab: pd.DataFrame, name: str, default: bool | None) -> np.ndarray:
    """A column of booleans with missing values as ``default`` (object array)."""
    if name not in tab:
        return np.full(len(tab), default, object)
    return np.array([default if v is None or v is pd.NA or (isinstance(v, float) and
                                                          math.isnan(v)) else bool(v)
                     for v in tab[name].tolist()], object)


def _rate(k: int, n: int) -> tuple[float, float, float]:
    if n == 0:
        return math.nan, math.nan, math.nan
    lo, hi = stats.wilson(k, n)
    return k / n, lo, hi


def rows(study, tab: pd.DataFrame) -> list[dict[str, Any]]:
    """One row per (configuration, family, robot count): the module doc's measures."""
    out = []
    family, config = tab["family"].to_numpy(), tab["config"].to_numpy()
    obstacles, scenario = tab["obstacles"].to_numpy(), tab["scenario"].to_numpy()
    solver = tab["solver"].to_numpy(object)
    feasible = tab["feasible"].to_numpy(bool)
    hit = tab["hit"].to_numpy(bool)
    certified = _bools(tab, "certified", True).astype(bool)
    at_best = _bools(tab, "at_best_known", False).astype(bool)
    expressible = _bools(tab, "best_known_expressible", True).astype(bool)
    collides = _bools(tab, "frozen_collides", None)
    found = _bools(tab, "frozen_found", None)
    time_s = numeric(tab, "time_s")
    for fam in dict.fromkeys(family.tolist()):
        for n in sorted(set(obstacles[family == fam].tolist())):
            for c in study.configs:
                m = (config == c.label) & (family == fam) & (obstacles == n)
                if not m.any():
                    continue
                group = (family == fam) & (obstacles == n)
                frozen = group & (solver == "frozen")
                frozen_scenes = {s: (f, k) for s, f, k in zip(
                    scenario[frozen], found[frozen], collides[frozen])}
                fz_n = len(frozen_scenes)
                fz_col = sum(1 for f, k in frozen_scenes.values() if f and k)
                fz_none = sum(1 for f, _ in frozen_scenes.values() if not f)
                cert, unc = m & certified, m & ~certified
                feas = _rate(int(feasible[m].sum()), int(m.sum()))
                hits = _rate(int(hit[cert].sum()), int(cert.sum()))
                best = _rate(int(at_best[unc].sum()), int(unc.sum()))
                col = _rate(fz_col, fz_n)
                out.append({
                    "config": c.label, "solver": c.solver, "family": fam, "obstacles": int(n),
                    "scenes": len(set(scenario[m].tolist())),
                    "scenes_certified": len(set(scenario[cert].tolist())),
                    "runs": int(m.sum()),
                    "feasible_rate": feas[0], "feasible_ci_low": feas[1],
                    "feasible_ci_high": feas[2],
                    "runs_certified": int(cert.sum()), "hit_rate_certified": hits[0],
                    "hit_certified_ci_low": hits[1], "hit_certified_ci_high": hits[2],
                    "scenes_uncertified_expressible": len(set(scenario[unc & expressible]
                                                              .tolist())),
                    "runs_uncertified": int(unc.sum()), "at_best_known_rate": best[0],
                    "at_best_known_ci_low": best[1], "at_best_known_ci_high": best[2],
                    "frozen_scenes": fz_n, "frozen_collides": fz_col, "frozen_no_path": fz_none,
                    "frozen_collides_rate": col[0], "frozen_collides_ci_low": col[1],
                    "frozen_collides_ci_high": col[2],
                    "time_per_run_ms": 1000 * float(np.mean(time_s[m])),
                    "time_per_run_median_ms": 1000 * float(np.median(time_s[m])),
                })
    return out


def _pct(v: float) -> str:
    return "-" if math.isnan(v) else f"{100 * v:.1f}%"


def _interval(r: dict, rate: str, low: str, high: str, count: str | None = None) -> str:
    if math.isnan(r[rate]):
        return "-"
    head = f"{_pct(r[rate])} [{_pct(r[low])}, {_pct(r[high])}]"
    return head if count is None else f"{head} of {r[count]}"


def table_text(out: list[dict[str, Any]]) -> str:
    """The Markdown of :func:`rows`: one table, rates with their 95 % Wilson intervals."""
    cells = pd.DataFrame([[
        r["family"], r["obstacles"], r["config"], r["scenes"], r["runs"],
        _interval(r, "feasible_rate", "feasible_ci_low", "feasible_ci_high"),
        f"{r['scenes_certified']} of {r['scenes']}",
        _interval(r, "hit_rate_certified", "hit_certified_ci_low", "hit_certified_ci_high",
                  "runs_certified"),
        _interval(r, "at_best_known_rate", "at_best_known_ci_low", "at_best_known_ci_high",
                  "runs_uncertified"),
        ("-" if not r["frozen_scenes"] else
         f"{r['frozen_collides']} of {r['frozen_scenes']} ({_pct(r['frozen_collides_rate'])})"
         + (f"; {r['frozen_no_path']} no path" if r["frozen_no_path"] else "")),
        f"{r['time_per_run_median_ms']:.3g}",
    ] for r in out], columns=[
        "family", "robots", "configuration", "scenes", "runs", "feasible in time [95% Wilson]",
        "certified scenes", "hit rate, certified scenes [95% Wilson] of runs",
        "no longer than best known, other scenes [95% Wilson] of runs",
        "frozen plan collides in time (scenes)", "ms/run (median)"])
    return markdown(cells)


NOTE = (
    "Feasible in time: the run's path keeps the standing robots' rules and every moving "
    "robot's model radius at the moment the car is there (float64). A hit counts on scenes "
    "whose optimum is certified (the standing robots' optimum keeps clear in time; a scene "
    "where nothing moves counts as certified); elsewhere a run counts when it is feasible "
    "in time and no longer than the shortest path feasible in time that the exact module "
    "knows (relative 1e-6). Frozen plan: the exact optimum with every robot standing where "
    "it is at time 0, judged in time; the count is over the group's scenes, the same in "
    "every row of a group. Times: one run on one core, compile excluded (a batched GA "
    "run: its share of the batch).")


def moving(study, tab: pd.DataFrame, docs, summary_rows, folder: str,
           draw: bool = True) -> list[str]:
    """The analysis ``moving`` (module doc): ``moving.csv`` and ``moving.md``."""
    out = rows(study, tab)
    csv, md = os.path.join(folder, "moving.csv"), os.path.join(folder, "moving.md")
    write_csv(csv, pd.DataFrame(out), missing="nan")
    text = (f"# {study.name}: robots that move\n\n{NOTE}\n\n"
            + (table_text(out) if out else "No runs.") + "\n")
    write_file(md, lambda fh: fh.write(text))
    return [csv, md]
