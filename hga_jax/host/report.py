"""Human-readable summaries, their JSON form, and the files of a result folder.

``run``: ``result.json``, ``history.csv`` and, with plots, ``path.png`` and
``convergence.png``. ``exact``: ``result.json`` (same schema, no runs) and, with
plots, ``path.png``. Files are written by :mod:`hga_jax.host.output`: atomically, and
one result per folder. Obstacles are numbered from 1; percentages have two
decimals; counts have thousands separators (docs/model.md).
"""
from __future__ import annotations

import dataclasses
import json
import os
from dataclasses import asdict
from typing import Any

import numpy as np

from hga_jax.errors import ConfigError
from hga_jax.model import car_model
from hga_jax.model.fitness import fitness_of, length_of_fitness
from .output import csv_writer, figure_writer, json_writer, write_result
from hga_jax.model.no_path import NO_PATH, verdict
from hga_jax.model.touch import touch_list
from hga_jax.words import count, pct, touches
from hga_jax.running.results import (RunsResult, json_safe, optimum_dict, result_document,
                                     settings_dict)
from hga_jax.model.scenario import Scenario
from hga_jax.search.settings import GASettings

PAPER_NOTE = ("collision \"paper\": segments judged by the paper's Appendix B test, which "
              "misses a segment that starts or ends inside another model circle")


def operators(st: GASettings) -> str:
    """The GA's operators and rates in one phrase."""
    sel = (f"tournament selection (size {st.tournament_size})" if st.selection == "tournament"
           else f"{st.selection} selection")
    binding = "" if st.label_binding == "position" else f" (bound by {st.label_binding})"
    return (f"{sel}; order: {st.perm_crossover} crossover (pc {st.pc_upper:g}), "
            f"{st.perm_mutation} mutation (pm {st.pm_upper:g}); labels{binding}: "
            f"{st.label_crossover} crossover (pc {st.pc_lower:g}), {st.label_mutation} "
            f"mutation (pm {st.pm_lower:g} per gene); {count(st.elites, 'elite')}"
            + (" per island" if st.island_count > 1 and st.elites else "") + _extras(st))


def _extras(st: GASettings) -> str:
    """The settings beyond the paper's, when set."""
    out = []
    for g in st.model.genes:  # what the car model adds to a chromosome
        out.append(f"{st.model.words}: {g.words}, {getattr(st, g.crossover)} crossover "
                   f"(pc {getattr(st, g.pc):g}), {getattr(st, g.mutation)} mutation "
                   f"(pm {getattr(st, g.pm):g} per gene)")
        if g.ends and getattr(st, g.ends) != "none":
            out.append(f"end move {getattr(st, g.ends)} (pm {getattr(st, g.pe):g})")
        if g.ends and st.ends_of_best:
            out.append(f"{count(st.ends_of_best, 'child', 'children')} per generation: the "
                       "best moved at its ends")
        if g.straight and getattr(st, g.straight):
            k = getattr(st, g.straight)
            out.append(f"{count(k, 'child', 'children')} per generation: the best with "
                       "straight legs")
        if g.tight and getattr(st, g.tight):
            k = getattr(st, g.tight)
            moved = ("moved as the tight rope moves it" if st.path_mutation != "none"
                     else "not moved (no path move)")
            out.append(f"{count(k, 'child', 'children')} per generation: the best with "
                       f"straight legs, {moved}")
    if st.path_mutation != "none":
        arcs = (f", arcs at {pct(st.guided_arcs)} of the penalty"
                if st.path_mutation in ("guided", "guided_pairs") and st.guided_arcs > 0 and st.counts_wrap_sides
                else "")
        out.append(f"path move {st.path_mutation} (pm {st.pm_path:g}{arcs})")
    if st.seeding > 0:
        via = (f", {pct(st.seeding_via)} of them from a path via a random obstacle"
               if st.seeding_via > 0 else "")
        if st.restart_via > 0 and st.restarts:
            via += (f"; in a restart of a run whose best collides, {pct(st.restart_via)} of "
                    "them via a random obstacle too")
        if st.restart_arcs > 0 and st.restarts and st.counts_wrap_sides:
            such = ("such a restart" if st.restart_via > 0
                    else "a restart of a run whose best collides")
            via += (f"; in {such} {pct(st.restart_arcs)} of them also wrap the "
                    "overlapping neighbours of their colliding arcs")
        out.append(f"seeded by wrapping blockers ({pct(st.seeding)} of each new population{via})")
    if st.wrap_clearer > 0 and st.uses_legs and st.counts_wrap_sides:
        out.append(f"{pct(st.wrap_clearer)} of wraps round the side with fewer blockers")
    if st.restart_after:
        out.append(f"restart after {count(st.restart_after, 'stalled generation')}")
    if st.island_count > 1:
        ring = (f", the best of each to the next every "
                f"{count(st.migrate_every, 'generation')}" if st.migrate_every else "")
        k = st.island_count
        out.append(f"{k} islands of {st.population // k}{ring}")
    if st.penalty_weight != 1.0:
        out.append(f"penalty {st.penalty_weight:g} x 2 pi R per violation in the search")
    return "".join("; " + o for o in out)


def gap_pct(gap: float | None) -> str:
    """A gap as a percentage with two decimals; one that rounds to zero is ``0.00%``, never
    ``-0.00%`` (a path shorter than the optimum by less than 0.005 %: float rounding)."""
    text = pct(gap)
    return text[1:] if text.startswith("-") and float(text[1:-1]) == 0.0 else text


def _generations(value: float | None, runs: int, what: str) -> str:
    if value is None:
        return f"to {what}: no run got there"
    return f"to {what} {value:g} (median over the {count(runs, 'run')} that got there)"


def _full_test_note(scenario: Scenario, path: Any) -> str:
    """For a path judged with collision "paper": what the full test says of it."""
    from hga_jax.model.path import evaluate_path, from_chromosome

    if path is None:
        return PAPER_NOTE
    full = evaluate_path(scenario, *from_chromosome(path.upper, path.lower, scenario.n), "full")
    said = ("is feasible under the full test too" if full.feasible else
            f"has {count(full.violations, 'violation')} under the full test (collision "
            "\"full\")")
    return f"{PAPER_NOTE}; this path {said}"


def run_summary(res: RunsResult) -> str:
    """The summary ``hga-jax run`` prints."""
    s, st, sc = res.summary(), res.settings, res.scenario
    runs = s["runs"]
    med = s["median_generation_found_best"]
    lines = [
        f"scenario {sc.name} ({count(sc.n, 'obstacle')}), collision {st.collision}: "
        f"{count(runs, 'run')} of seed {res.seed}, population {st.population}, "
        f"{count(st.generations, 'generation')}"
        + (f" ({res.budget['rule']})" if res.budget else "") + f", precision {st.precision}",
        f"operators{f' (preset {res.preset})' if res.preset else ''}: {operators(st)}",
        f"best length {s['best_length']:.6f} m ({'feasible' if s['best_feasible'] else 'INFEASIBLE'}"
        f", touches {touches(res.best.touched)}"
        + (f", {count(res.best.cusps, 'cusp')}" if st.model.reverses else "")
        + f"), found in {s['runs_found_best']:,} of "
        f"{count(runs, 'run')}, median generation first reached {med:g}",
    ]
    if "optimum_length" in s:
        model = car_model.get(res.optimum.turns)
        name = model.optimum_name
        if res.yardstick == "lower bound":
            name = "lower bound (the standing robots' optimum, which meets a moving robot in time)"
        elif sc.has_motion:
            name += " (certified in time)"
        lines.append(
            f"{name} {s['optimum_length']:.6f} m: hit rate {pct(s['hit_rate'])} "
            f"({s['runs_hit']:,} of {count(runs, 'run')}); gap over the "
            f"{count(s['feasible_runs'], 'feasible run')}: "
            + (f"median {gap_pct(s['gap_median'])}, mean {gap_pct(s['gap_mean'])}, "
               f"max {gap_pct(s['gap_max'])}" if s["feasible_runs"] else "none")
            + f"; {count(s['infeasible_runs'], 'run')} ended infeasible")
        lines.append("median generations: "
                     + _generations(s["median_generation_within_1pct"], s["runs_within_1pct"],
                                    "within 1%") + "; "
                     + _generations(s["median_generation_hit"], s["runs_hit"], "the hit"))
        if res.yardstick == "lower bound":
            lines.append(moving_line(res.optimum))
        else:
            lines += model.notes(res.optimum, st.model)
    elif res.optimum is not None:
        lines.append("optimum: " + no_path_line(res.optimum))
    if st.collision == "paper":
        lines.append("note: " + _full_test_note(sc, res.best))
    rate = s["evaluations_per_s"]
    on = f" on {count(res.devices, 'device')}" if res.devices > 1 else ""
    lines.append(f"time: compile {res.compile_s:.2f} s, search {res.search_s:.2f} s{on} "
                 f"({count(s['evaluations'], 'evaluation')}"
                 + (f", {rate:,.0f}/s" if rate else "") + f"), finish {res.finish_s:.2f} s"
                 + _resumed_note(res))
    return "\n".join(lines)


def _resumed_note(res: RunsResult) -> str:
    """For a resumed job: how the times split between this command and the interrupted one."""
    e = res.earlier
    if not e:
        return ""
    return (f"; compile and search include the {count(e['runs'], 'run')} kept from the "
            f"interrupted command ({e['compile_s']:.2f} s and {e['search_s']:.2f} s there; "
            f"{res.compile_s - e['compile_s']:.2f} s and {res.search_s - e['search_s']:.2f} s "
            "in this one)")


def run_json(res: RunsResult, written: list[str]) -> dict[str, Any]:
    """What ``hga-jax run --json`` prints: the summary and the files written."""
    return json_safe({
        "command": "run", "scenario": res.scenario.name, "source": res.scenario.source,
        "seed": res.seed, "settings": settings_dict(res.settings), "summary": res.summary(),
        "best": {"run": res.best_run, "length": res.best.length,
                 "feasible": res.best.feasible, "violations": res.best.violations,
                 "touched": touch_list(res.best.touched)},
        "written": written,
    })


def moving_line(opt: Any) -> str:
    """Among robots that move with no optimum certified: the best path known in time."""
    if not opt.feasible:
        return "no path feasible in time is known (the lower bound's path meets a moving robot)"
    how = opt.message.rsplit("(", 1)[-1].rstrip(")") if "(" in opt.message else ""
    return (f"best known path feasible in time {opt.length:.6f} m"
            + (f" (found by {how})" if how else "")
            + f", {100.0 * (opt.length / opt.lower_bound - 1.0):.2f}% over the lower bound")


def exact_summary(scenario: Scenario, opt: Any) -> str:
    """The summary ``hga-jax exact`` prints."""
    took = f"solved in {1000 * opt.seconds:.1f} ms"
    if scenario.has_motion and not opt.optimal:
        return (f"scenario {scenario.name} ({count(scenario.n, 'obstacle')}, "
                f"{int(scenario.moving.sum())} moving), collision {opt.collision}: "
                f"lower bound {opt.lower_bound:.6f} m (the standing robots' optimum, which "
                f"meets a moving robot in time), not certified; {moving_line(opt)}; {took}")
    if not opt.feasible:
        return (f"scenario {scenario.name} ({count(scenario.n, 'obstacle')}): "
                f"{no_path_line(opt)}; {took}")
    head = (f"scenario {scenario.name} ({count(scenario.n, 'obstacle')}), collision "
            f"{opt.collision}: ")
    model = car_model.get(opt.turns)
    certified = " (certified: it keeps clear of every moving robot in time)" if (
        scenario.has_motion) else ""
    text = head + (f"{model.optimum_name} {opt.length:.6f} m{certified} touching "
                   f"{touches(opt.touched)}{model.head(opt)}, {took}")
    text += "".join("\n" + line for line in model.notes(opt))
    if opt.collision == "paper":
        text += "\nnote: " + _full_test_note(scenario, opt.path or opt.best_expressible)
    return text


def no_path_line(opt: Any) -> str:
    """The one line of every model for an optimum that does not exist, with why."""
    return verdict(opt.collision, opt.turns, opt.message)




def exact_json(scenario: Scenario, opt: Any, written: list[str]) -> dict[str, Any]:
    """What ``hga-jax exact --json`` prints."""
    return json_safe({"command": "exact", "scenario": scenario.name, "source": scenario.source,
                      "optimum": optimum_dict(opt), "written": written})


def path_title(name: str, what: str, length: float, violations: int, collision: str,
               st: GASettings | None = None) -> str:
    """A path plot's title: length, feasibility, collision mode and (for GA paths) operators."""
    state = "feasible" if violations == 0 else count(violations, "violation")
    text = f"{name}: {what}, length {length:.4f} m, {state}, collision {collision}"
    if st is not None:
        text += (f"\n{st.selection}, {st.perm_crossover}/{st.perm_mutation}, "
                 f"population {st.population}, {count(st.generations, 'generation')}")
    return text


def run_figures(res: RunsResult) -> dict[str, Any]:
    """The run's figures: ``path.png`` (best path, violations marked) and ``convergence.png``."""
    from .plots import plot_convergence, plot_path

    best, st = res.best, res.settings
    path = plot_path(res.scenario, best.segments, touched=best.touched,
                     violations_at=best.violations_at,
                     title=path_title(res.scenario.name, f"best (run {res.best_run})",
                                      best.length, best.violations, st.collision, st))
    opt = res.optimum_length
    h = res.history
    conv = plot_convergence(
        h["best_fitness"], h["mean_fitness"],
        optimum_fitness=None if opt is None else fitness_of(opt, 0, res.scenario.delta),
        # Best-so-far Dist_m (length plus penalty): the length itself once feasible.
        best_length=length_of_fitness(h["best_so_far_fitness"].astype(np.float64)),
        optimum_length=opt,
        title=(f"{res.scenario.name}: {count(len(res.length), 'run')}, median and quartiles; "
               f"collision {st.collision}; {st.selection}, {st.perm_crossover}/"
               f"{st.perm_mutation}"),
        length_label="best-so-far Dist$_m$ = length + penalty (m)",
        reached=None if opt is None else {"within 1%": res.first_generation_within(0.01),
                                          "optimum": res.generation_hit},
        population=st.population, restart_after=st.restart_after)
    return {"path.png": path, "convergence.png": conv}


def write_run(res: RunsResult, out: str, plot: bool = False, force: bool = False) -> list[str]:
    """Write a run's files into the folder ``out``; returns the paths written.

    A folder holds one result: if ``out`` already holds result files, this raises
    :class:`~hga_jax.errors.ConfigError` unless ``force``, which replaces them
    (and removes the earlier result's files this one does not write, e.g. its
    PNGs when ``plot`` is False).
    """
    files = {"result.json": (json_writer(res.to_dict()), False),
             "history.csv": (csv_writer(res.history_rows()), False)}
    if plot:
        files.update({k: (figure_writer(f), True) for k, f in run_figures(res).items()})
    return write_result(out, files, force)


PARTIAL = "partial.npz"
"""The finished runs of an interrupted ``run``, beside its partial result.json."""
_ARRAYS = ("perm", "labels", "legs", "generation", "length", "violations")


def write_partial(res: RunsResult, out: str, requested: int, force: bool = False) -> list[str]:
    """Write the finished runs of an interrupted job: a result.json that says it is
    partial (``partial``: runs done and requested, first run, seed) and ``partial.npz``
    with every finished run's arrays, which ``hga-jax run ... --resume`` continues from."""
    import io

    doc = res.to_dict()
    doc["partial"] = {"runs_done": int(len(res.length)), "runs_requested": int(requested),
                      "first_run": int(res.run_ids[0]), "seed": res.seed}
    arrays = {k: getattr(res, k) for k in _ARRAYS if getattr(res, k) is not None}
    arrays.update({f"history.{k}": v for k, v in res.history.items()})
    arrays.update(compile_s=np.float64(res.compile_s), search_s=np.float64(res.search_s))

    def npz(fh):
        buf = io.BytesIO()
        np.savez(buf, **arrays)
        fh.write(buf.getvalue())

    return write_result(out, {"result.json": (json_writer(doc), False), PARTIAL: (npz, True)},
                        force)


def partial_in(out: str) -> dict[str, Any] | None:
    """The ``partial`` entry of the result in ``out`` if that result is partial, else None."""
    if not os.path.exists(os.path.join(out, PARTIAL)):
        return None
    try:
        return load_result(os.path.join(out, "result.json")).get("partial")
    except ConfigError:
        return None


def load_partial(out: str, scenario: Scenario, settings: Any, seed: int, first_run: int,
                 runs: int) -> tuple[dict[str, Any], dict[str, np.ndarray]]:
    """The partial result in ``out`` and its arrays, checked to be the same job (scenario,
    settings, seed, runs); a ConfigError naming what differs otherwise."""
    where = os.path.join(out, "result.json")
    part = partial_in(out)
    if part is None:
        raise ConfigError(f"{out}: --resume: no partial result there to resume (an interrupted "
                          "run leaves result.json and partial.npz)")
    doc = load_result(where)
    fresh = json.loads(json.dumps(result_document(scenario, {
        "settings": settings_dict(settings.for_car(scenario.car).for_obstacles(scenario.n))})))
    mine = {"scenario": (doc["scenario"]["definition"], fresh["scenario"]["definition"]),
            "settings": (doc["settings"], fresh["settings"]), "seed": (part["seed"], seed),
            "first run": (part["first_run"], first_run),
            "runs": (part["runs_requested"], runs)}
    for what, (there, here) in mine.items():
        diff = _differences(there, here, "" if what in ("seed", "first run", "runs") else what)
        if diff:
            key, was, now = diff[0]
            more = f" (and {count(len(diff) - 1, 'other difference')})" if len(diff) > 1 else ""
            raise ConfigError(f"{where}: --resume: the partial result was not made by this "
                              f"command: its {key or what} is {_shown(was)}, this command's "
                              f"is {_shown(now)}{more}; use the interrupted command with "
                              "--resume, or --force to start over")
    with np.load(os.path.join(out, PARTIAL)) as z:
        arrays = {k: z[k] for k in z.files}
    return doc, arrays


def _differences(a: Any, b: Any, key: str) -> list[tuple[str, Any, Any]]:
    """``(dotted key, value in a, value in b)`` wherever two JSON values differ."""
    if isinstance(a, dict) and isinstance(b, dict):
        return [d for k in dict.fromkeys([*a, *b])
                for d in _differences(a.get(k, _MISSING), b.get(k, _MISSING),
                                      f"{key}.{k}" if key else k)]
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [d for i, (x, y) in enumerate(zip(a, b))
                for d in _differences(x, y, f"{key}[{i + 1}]")]
    return [] if a == b else [(key, a, b)]


_MISSING = object()


def _shown(value: Any) -> str:
    """A value of a result file as a message shows it."""
    if value is _MISSING:
        return "not set"
    if isinstance(value, bool) or value is None:
        return json.dumps(value)
    if isinstance(value, int):
        return f"{value:,}"
    return repr(value) if isinstance(value, str) else json.dumps(value)


def exact_to_dict(scenario: Scenario, opt: Any) -> dict[str, Any]:
    """result.json of ``hga-jax exact``: the run schema with the optimum as best path."""
    path = opt.path.to_dict() if opt.feasible and opt.path is not None else None
    if path is None and opt.feasible:  # a path no chromosome expresses (free arcs)
        path = {"length": opt.length, "feasible": True, "violations": 0, "upper": None,
                "lower": None, "touched": touch_list(opt.touched), "segments": opt.segments,
                "violations_at": []}
    return result_document(scenario, {
        "seed": None, "runs": None, "settings": {"collision": opt.collision, "turns": opt.turns,
                                                 "car": car_model.get(opt.turns).car},
        "best": path, "optimum": optimum_dict(opt),
        "summary": {"optimum_length": opt.length if opt.feasible else None,
                    "seconds": opt.seconds,
                    **(car_model.get(opt.turns).summary(opt) if opt.feasible else {})},
        "per_run": [],
    })


def write_exact(scenario: Scenario, opt: Any, out: str, plot: bool = False,
                force: bool = False) -> list[str]:
    """Write ``exact``'s files into ``out`` (one result per folder, as :func:`write_run`)."""
    files = {"result.json": (json_writer(exact_to_dict(scenario, opt)), False)}
    if plot:
        from .plots import plot_path

        if opt.feasible:
            what = car_model.get(opt.turns).optimum_name
            fig = plot_path(scenario, opt.segments, touched=opt.touched,
                            title=path_title(scenario.name, what, opt.length, 0,
                                             opt.collision))
        else:
            fig = plot_path(scenario, [], title=f"{scenario.name}: "
                            + verdict(opt.collision, opt.turns))
        files["path.png"] = (figure_writer(fig), True)
    return write_result(out, files, force)


def load_result(path: str) -> dict[str, Any]:
    """A result.json, read and checked for the keys :func:`redraw` needs."""
    import json

    try:
        with open(path, encoding="utf-8") as fh:
            data = json.load(fh)
    except OSError as e:
        raise ConfigError(f"{path}: file: cannot read: {e.strerror or e}") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as e:
        raise ConfigError(f"{path}: json: not a result file ({e})") from None
    for key in ("scenario", "settings", "best", "optimum", "per_run"):
        if not isinstance(data, dict) or key not in data:
            raise ConfigError(f"{path}: {key}: missing key (not a result.json of hga-jax)")
    if not isinstance(data["scenario"], dict) or "definition" not in data["scenario"]:
        raise ConfigError(f"{path}: scenario.definition: missing key (written by an older "
                          "hga-jax? run it again)")
    return data


def result_scenario(path: str, data: dict[str, Any]) -> Scenario:
    """The scenario a result file (read by :func:`load_result`) was written for."""
    from .config import scenario_from_dict

    return scenario_from_dict(data["scenario"]["definition"], f"{path}: scenario.definition")


def result_path(path: str, data: dict[str, Any], sc: Scenario,
                run: int | None = None) -> dict[str, Any] | None:
    """The path a result file holds, in the result files' form (``length``,
    ``feasible``, ``violations``, ``touched``, ``segments``, ``violations_at``, ...).

    ``run`` None: the file's ``best`` (None if it has none). Else run ``run``'s best
    path, re-evaluated from its chromosome in ``per_run`` with the file's collision
    test (a ConfigError naming ``per_run`` if the file has no such run).
    """
    if run is None:
        return data["best"]
    from hga_jax.model.path import evaluate_path, from_chromosome, gene_values, legs_from_list

    rows = [r for r in data["per_run"] if r.get("run") == run]
    if not rows:
        ids = [r["run"] for r in data["per_run"]]
        span = f"runs {min(ids)}..{max(ids)}" if ids else "no runs"
        raise ConfigError(f"{path}: per_run: no run {run} in this file ({span})")
    collision = data["settings"].get("collision", "full")
    p = evaluate_path(sc, *from_chromosome(rows[0]["upper"], rows[0]["lower"], sc.n,
                                           f"{path}: per_run"), collision,
                      legs_from_list(rows[0].get("legs"), sc.n, f"{path}: per_run",
                                     gene_values(sc)))
    return {**p.to_dict(), "run": run}


def redraw(path: str, run: int | None = None, with_optimum: bool = False) -> Any:
    """The figure ``hga-jax plot`` draws from the result file ``path``.

    ``run``: draw run ``run``'s best path (re-evaluated from its chromosome) instead
    of the result's best. ``with_optimum``: overlay the exact optimum (the file's,
    or solved now if the file has none). Violations are marked.
    """
    from .plots import plot_path

    data = load_result(path)
    sc = result_scenario(path, data)
    st_keys = data["settings"]
    collision = st_keys.get("collision", "full")
    turns = st_keys.get("turns", car_model.DEFAULT)
    st = (GASettings(**{k: v for k, v in st_keys.items() if k != "car"})
          if "population" in st_keys else None)
    chosen = result_path(path, data, sc, run)
    if run is None:
        what = (car_model.get(turns).optimum_name if st is None or chosen is None
                else f"best (run {chosen.get('run')})")
    else:
        what = f"run {run}"
    if chosen is None:
        segs, touched, where, length, viol = [], [], [], None, None
    else:
        segs, touched, where = chosen["segments"], chosen["touched"], chosen["violations_at"]
        length, viol = chosen["length"], chosen["violations"]
    overlay, note = None, ""
    if with_optimum:
        opt = data["optimum"]
        if opt is None:
            from hga_jax.model.exact import solve

            solved = solve(sc, collision, turns)
            opt = {"feasible": solved.feasible, "length": solved.length,
                   "segments": solved.segments}
        itself = st is None and run is None  # an exact result: its path is the optimum
        if opt["feasible"]:
            overlay = opt["segments"]
            note = ("; dashed: the same optimum" if itself
                    else f"; optimum {opt['length']:.4f} m (dashed)")
        elif not itself:  # else the title already says there is none
            note = f"; optimum: {NO_PATH}"
    title = (path_title(sc.name, what, length, viol, collision, st) if length is not None
             else f"{sc.name}: " + verdict(collision, turns))
    return plot_path(sc, segs, touched=touched, violations_at=where, optimum=overlay,
                     title=title + note)
