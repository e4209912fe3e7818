"""One cell of a study with any solver: the HGA (batched or one run at a time), random
search, the exact solver, the DEAP GA, an OMPL planner or, among robots that move, the
frozen-snapshot planner (:data:`~hga_jax.study.config.SOLVERS`).

Every solver's cell document has the same columns (:func:`hga_jax.study.store.cell_document`
for the HGA and random search, :func:`peer_document` for the others), so one store,
table, summary and set of figures serves them all. Every length is the project's
float64 model's: the DEAP GA's best chromosome is decoded again by
:func:`~hga_jax.model.path.evaluate_path`, an OMPL path is rebuilt from its waypoints and
judged by :mod:`hga_jax.peers.judge` under the full collision rule (a path OMPL
accepted that clips an obstacle is infeasible), the exact solver's optimum is what
it is. Gaps are to the study's yardstick optimum; a peer may find a path shorter
than the tight-rope optimum (it turns in free space): its gap is negative. Among robots
that move, gaps are to the optimum where the exact module certifies one, else to the
standing robots' optimum (a lower bound), and every cell keeps the columns in time of
:func:`hga_jax.study.moving_study.columns`.

Times are seconds of one run on one core, compile excluded (:mod:`~hga_jax.study.anytime`).
"""
from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from hga_jax.model.exact import solve
from hga_jax.model.path import decode64, evaluate_path
from hga_jax.running.results import HIT_GAP, best_run, gap_of
from hga_jax.running.runner import joined, run_many
from . import anytime, moving_study
from .config import Config, Study
from .scenes import Scene
from .store import TARGETS, cell_document, optimum_details, tight_rope_optimum


def run_cell(study: Study, config: Config, scene: Scene) -> dict[str, Any]:
    """Run ``config`` on ``scene`` for the study's runs and describe the cell."""
    runs = study.runs_of(config)
    if config.solver in ("hga", "random"):
        return _ga_cell(study, config, scene, runs)
    optimum = solve(scene.scenario, turns=study.yardstick)
    if config.solver == "exact":
        return _exact_cell(study, config, scene, optimum)
    if config.solver == "frozen":
        return moving_study.frozen_cell(study, config, scene, optimum)
    if config.solver == "deap":
        return _deap_cell(study, config, scene, runs, optimum)
    return _ompl_cell(study, config, scene, runs, optimum)


def _ga_cell(study: Study, config: Config, scene: Scene, runs: int) -> dict[str, Any]:
    sc = scene.scenario
    if config.batch:
        res = run_many(sc, config.settings, seed=study.seed, runs=runs, turns=study.yardstick)
        times = None
    else:  # each run alone: one compiled shape, called once per run
        parts = [run_many(sc, config.settings, seed=study.seed, runs=1, first_run=k,
                          turns=study.yardstick, exact=k == 0) for k in range(runs)]
        res = joined(parts)
        times = [p.search_s * p.devices for p in parts]
    full = res.violations
    if config.settings.collision != "full":
        full = decode64(sc, res.perm, res.labels, "full").violations
    doc = cell_document(res, config, scene, full, times)
    doc["columns"].update(moving_study.columns(sc, res.optimum, res.length, res.feasible))
    return doc


def _gap(length: float, feasible: bool, opt: float | None) -> float:
    return np.inf if opt is None else float(gap_of(length, feasible, opt))


def peer_document(study: Study, config: Config, scene: Scene, optimum, rows: list[dict],
                  extra: dict[str, Any] | None = None) -> dict[str, Any]:
    """The cell document of a solver outside the batched GA, from one dict per run:
    ``length`` (m, float64 model), ``violations`` (the configuration's collision rule),
    ``violations_full``, ``time_s``, ``evaluations`` (None: not counted),
    ``generation_best`` (None: no generations), ``trace_t``/``trace_gap`` (anytime trace)
    and, for a GA, ``trace_gen``/``trace_eval`` (its generation and evaluations so far at
    each trace point: the first of each within a target is that run's, DEAP's
    evaluations counted as made, only changed individuals evaluated again). An OMPL cell also keeps ``paths``: per
    run the waypoint poses ``[x, y, heading]`` of its final path (None: none found)."""
    opt = moving_study.yardstick(optimum)  # among robots that move: maybe a lower bound
    gap = [_gap(r["length"], r["violations"] == 0, opt) for r in rows]
    n = len(rows)
    k = max(1, max(len(r["trace_t"]) for r in rows))

    def trace(name: str) -> np.ndarray:  # (K, R): a run's trace, its last entry repeated
        return np.array([list(v) + [v[-1] if v else np.inf] * (k - len(v))
                         for v in (r[name] for r in rows)], np.float64).T

    times, gaps = trace("trace_t"), trace("trace_gap")
    columns: dict[str, list] = {
        "run": list(range(n)), "length": [r["length"] for r in rows],
        "feasible": [r["violations"] == 0 for r in rows],
        "violations": [r["violations"] for r in rows],
        "violations_full": [r["violations_full"] for r in rows],
        "gap": [None if not np.isfinite(g) else float(g) for g in gap],
        "hit": [bool(g < HIT_GAP) for g in gap],
        "generation_best": [r["generation_best"] for r in rows],
        **moving_study.columns(scene.scenario, optimum, [r["length"] for r in rows],
                               [r["violations"] == 0 for r in rows]),
    }
    counted = all("trace_gen" in r for r in rows)  # a GA's trace: generations, evaluations
    for t in TARGETS:
        tag = "hit" if t == 0 else f"{round(100 * t)}pct"
        for clock, name in (("generation", "trace_gen"), ("evaluations", "trace_eval")):
            first = anytime.first_time(trace(name), gaps, t) if counted else [None] * n
            columns[f"{clock}_{tag}"] = [None if v is None else int(v) for v in first]
    columns["evaluations_run"] = [r["evaluations"] for r in rows]
    columns["time_s"] = [r["time_s"] for r in rows]
    columns.update({("time_hit" if t == 0 else f"time_{round(100 * t)}pct"):
                    anytime.first_time(times, gaps, t) for t in TARGETS})
    evaluations = [r["evaluations"] for r in rows]
    return {
        "solver": config.solver, "batch": True, "config": config.label,
        "settings": dataclasses.asdict(config.settings), "scenario": scene.name,
        "family": scene.family, "scenario_file": scene.path, "obstacles": scene.scenario.n,
        "seed": study.seed, "runs": n, "optimum": opt,
        "yardstick": optimum.turns if optimum is not None else None,
        "tight_rope_optimum": tight_rope_optimum(optimum, opt),
        "optimum_details": optimum_details(optimum),
        "optimum_touched": len(optimum.touched) if optimum is not None else None,
        "exact_s": optimum.seconds if optimum is not None else None,
        "compile_s": 0.0, "search_s": float(sum(r["time_s"] for r in rows)), "finish_s": 0.0,
        "devices": 1,
        "evaluations_per_run": (float(np.mean(evaluations))
                                if all(e is not None for e in evaluations) else None),
        "best": _best(rows, gap),
        "columns": columns, "curves": {"anytime_gap": anytime.quartiles(times, gaps)},
        **(extra or {}),
    }


def _best(rows: list[dict], gap: list[float]) -> dict[str, Any]:
    """The cell's best run: the shortest feasible path, else the fewest violations."""
    i = best_run([r["length"] for r in rows], [r["violations"] for r in rows])
    return {"run": i, "length": rows[i]["length"], "feasible": rows[i]["violations"] == 0,
            "violations": rows[i]["violations"]}


def _exact_cell(study: Study, config: Config, scene: Scene, optimum) -> dict[str, Any]:
    feasible = optimum.feasible
    length = float(optimum.length) if feasible else np.inf
    # 0 but among robots that move where no optimum is certified: the gap to the bound
    gap = 0.0 if feasible and optimum.optimal else _gap(length, feasible,
                                                       moving_study.yardstick(optimum))
    row = {"length": length, "violations": 0 if feasible else 1,
           "violations_full": 0 if feasible else 1, "time_s": optimum.seconds,
           "evaluations": None, "generation_best": None,
           "trace_t": [optimum.seconds], "trace_gap": [gap]}
    return peer_document(study, config, scene, optimum, [row])


def _deap_cell(study, config, scene, runs, optimum) -> dict[str, Any]:
    from hga_jax.peers.deap_ga import run
    from hga_jax.peers.python_decoder import PythonDecoder

    sc, s = scene.scenario, config.settings
    opt = optimum.length if optimum.feasible else None
    decoder = PythonDecoder.from_scenario(sc, s.collision)
    rows = []
    for k in range(runs):
        r = run(sc, s, study.seed, k, decoder)
        path = evaluate_path(sc, r["perm"], r["labels"], s.collision)
        full = path if s.collision == "full" else evaluate_path(sc, r["perm"], r["labels"])
        rows.append({"length": path.length, "violations": path.violations,
                     "violations_full": full.violations, "time_s": r["seconds"],
                     "evaluations": r["evaluations"], "generation_best": r["generation"],
                     "trace_t": [t for t, *_ in r["trace"]],
                     "trace_gap": [_gap(length, v == 0, opt) for _, _, length, v in r["trace"]],
                     "trace_gen": list(range(len(r["trace"]))),
                     "trace_eval": [e for _, e, *_ in r["trace"]]})
    return peer_document(study, config, scene, optimum, rows)


def ompl_runs(sc, planner: str, time_limit: float, seed: int, runs: int) -> list[dict]:
    """``runs`` runs of OMPL's ``planner`` on ``sc`` (:func:`hga_jax.peers.ompl_planner.plan`),
    one after another: what a study's OMPL cell asks of its worker process."""
    from hga_jax.peers.ompl_planner import plan

    return [plan(sc, planner, time_limit, seed) for _ in range(runs)]


def _ompl_cell(study, config, scene, runs, optimum) -> dict[str, Any]:
    from hga_jax.peers import isolated
    from hga_jax.peers.judge import judge_poses

    sc = scene.scenario
    opt = optimum.length if optimum.feasible else None
    rows, checks, ompl_lengths, paths = [], [], [], []
    # in a worker process: OMPL's BIT* crashes its process now and then (hga_jax.peers.isolated)
    results = isolated.call(ompl_runs, sc, config.planner, config.time_limit, study.seed, runs,
                            what=f"OMPL's {config.planner} on scene {scene.name}")
    for r in results:
        trace_t, trace_gap, last, final = [], [], None, None
        for t, poses in r["checkpoints"]:
            if poses is None:
                continue
            last, final = judge_poses(sc, poses), poses
            trace_t.append(t)
            trace_gap.append(_gap(last.length, last.feasible, opt))
        paths.append(final)
        solved = last is not None
        rows.append({"length": last.length if solved else np.inf,
                     "violations": last.violations if solved else 1,
                     "violations_full": last.violations if solved else 1,
                     "time_s": r["seconds"], "evaluations": None, "generation_best": None,
                     "trace_t": trace_t, "trace_gap": trace_gap})
        checks.append(r["checks"])
        ompl_lengths.append(r["ompl_length"])
    doc = peer_document(study, config, scene, optimum, rows,
                        {"planner": config.planner, "time_limit": config.time_limit,
                         "paths": [None if p is None else [list(q) for q in p] for p in paths]})
    doc["columns"]["state_checks"] = checks
    doc["columns"]["ompl_length"] = [None if not np.isfinite(v) else float(v)
                                     for v in ompl_lengths]
    doc["columns"]["solved"] = [bool(np.isfinite(r["length"])) for r in rows]
    return doc
