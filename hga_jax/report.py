"""Human-readable summaries and the files of a result folder.

``run``: ``result.json``, ``history.csv`` and, with plots, ``path.png`` and
``convergence.png``. ``exact``: ``result.json`` (same schema, no runs) and
``path.png``. Every file is written atomically (see :mod:`hga_jax.results`).
"""
from __future__ import annotations

import os
from typing import Any

import numpy as np

from .fitness import fitness_of, length_of_fitness
from .results import RunsResult, result_document, write_csv, write_json
from .scenario import Scenario


def _pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.3g}%"


def _touched(touched) -> str:
    return " ".join(f"{i + 1}{'CW' if s > 0 else 'CCW'}" for i, s in touched) or "none"


def run_summary(res: RunsResult) -> str:
    """The short summary ``hga-jax run`` prints."""
    s, st = res.summary(), res.settings
    med = s["median_generation_found_best"]
    lines = [
        f"scenario {res.scenario.name} ({res.scenario.n} obstacles): {s['runs']} run(s) of seed "
        f"{res.seed}, population {st.population}, {st.generations} generations, "
        f"collision {st.collision}",
        f"best length {s['best_length']:.6f} m ({'feasible' if s['best_feasible'] else 'INFEASIBLE'}"
        f", touches {_touched(res.best.touched)}), found in {s['runs_found_best']}/{s['runs']} "
        f"runs, median generation first reached {med if med is not None else 'n/a'}",
    ]
    if "optimum_length" in s:
        lines.append(
            f"optimum {s['optimum_length']:.6f} m: hit rate {_pct(s['hit_rate'])}; gap over "
            f"{s['feasible_runs']} feasible runs median {_pct(s['gap_median'])} mean "
            f"{_pct(s['gap_mean'])} max {_pct(s['gap_max'])} ({s['infeasible_runs']} runs "
            f"ended infeasible); "
            f"median generations to within 1% {s['median_generation_within_1pct']}, "
            f"to hit {s['median_generation_hit']}")
        opt = res.optimum
        if not opt.expressible:
            alt = opt.best_expressible
            lines.append("  (the optimal walk touches an obstacle twice, which no chromosome "
                         "expresses; best chromosome path "
                         + (f"{alt.length:.6f} m)" if alt is not None else "unknown)"))
    elif res.optimum is not None:
        lines.append(f"optimum: none ({getattr(res.optimum, 'message', 'no feasible path')})")
    rate = s["evaluations_per_s"]
    lines.append(f"time: compile {res.compile_s:.2f} s, search {res.search_s:.2f} s "
                 f"({s['evaluations']:,} evaluations, {rate:,.0f}/s), finish {res.finish_s:.2f} s")
    return "\n".join(lines)


def exact_summary(scenario: Scenario, opt: Any) -> str:
    """The summary ``hga-jax exact`` prints."""
    if not opt.feasible:
        return (f"scenario {scenario.name}: no feasible path ({opt.message}); "
                f"solved in {1000 * opt.seconds:.1f} ms")
    text = (f"scenario {scenario.name} ({scenario.n} obstacles), collision {opt.collision}: "
            f"optimum {opt.length:.6f} m touching {_touched(opt.touched)}, "
            f"solved in {1000 * opt.seconds:.1f} ms")
    if opt.expressible:
        text += f"\nchromosome upper {opt.upper} lower {opt.lower}"
    if not opt.expressible:
        alt = opt.best_expressible
        text += ("\nthe optimal walk touches an obstacle twice: no chromosome expresses it; "
                 + (f"best chromosome path {alt.length:.6f} m" if alt else "no chromosome path"))
    return text


def write_run(res: RunsResult, out: str, plot: bool = False) -> list[str]:
    """Write a run's files into ``out``; returns the paths written."""
    paths = [os.path.join(out, "result.json"), os.path.join(out, "history.csv")]
    write_json(paths[0], res.to_dict())
    write_csv(paths[1], res.history_rows())
    if plot:
        from .plots import plot_convergence, plot_path, save_figure

        best = res.best
        title = f"{res.scenario.name}: length {best.length:.4f} m, " + (
            "feasible" if best.feasible else f"{best.violations} violations")
        paths.append(_save(save_figure, plot_path(res.scenario, best.segments,
                                                  touched=best.touched, title=title),
                           out, "path.png"))
        opt = res.optimum_length
        h = res.history
        fig = plot_convergence(
            h["best_fitness"], h["mean_fitness"],
            optimum_fitness=None if opt is None else fitness_of(opt, 0, res.scenario.delta),
            # Best-so-far Dist_m (length plus penalty): the length itself once feasible.
            best_length=length_of_fitness(h["best_so_far_fitness"].astype(np.float64)),
            optimum_length=opt,
            title=f"{res.scenario.name}: {len(res.length)} runs, median and quartiles",
            length_label="best-so-far Dist$_m$ = length + penalty (m)")
        paths.append(_save(save_figure, fig, out, "convergence.png"))
    return paths


def exact_to_dict(scenario: Scenario, opt: Any) -> dict[str, Any]:
    """result.json of ``hga-jax exact``: the run schema with the optimum as best path."""
    path = opt.path.to_dict() if opt.feasible and opt.path is not None else None
    return result_document(scenario, {
        "seed": None, "runs": None, "settings": {"collision": opt.collision},
        "best": path, "optimum": opt.to_dict(),
        "summary": {"optimum_length": opt.length if opt.feasible else None,
                    "seconds": opt.seconds},
        "per_run": [],
    })


def write_exact(scenario: Scenario, opt: Any, out: str, plot: bool = False) -> list[str]:
    paths = [os.path.join(out, "result.json")]
    write_json(paths[0], exact_to_dict(scenario, opt))
    if plot:
        from .plots import plot_path, save_figure

        segs = opt.path.segments if opt.feasible and opt.path is not None else []
        title = (f"{scenario.name}: optimum {opt.length:.4f} m" if opt.feasible
                 else f"{scenario.name}: no feasible path")
        touched = opt.touched if opt.feasible else ()
        paths.append(_save(save_figure, plot_path(scenario, segs, touched=touched, title=title),
                           out, "path.png"))
    return paths


def _save(save_figure, fig, out: str, name: str) -> str:
    path = os.path.join(out, name)
    save_figure(fig, path)
    return path
