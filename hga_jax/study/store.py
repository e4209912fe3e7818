"""The resumable store of a study: one JSON file per finished cell.

A *cell* is one configuration run ``runs`` times on one scene. Its identity is a
hash of everything that determines its result (the settings, the scene file's
text, the seed, the run count and the package version), so a finished cell is
never run again, and a changed study never reuses a stale cell. A cell file is
written once, atomically (temporary file, then rename): after a crash a cell is
either complete or absent, and the tables, always rebuilt from the cell files,
hold every finished run exactly once.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from typing import Any

import numpy as np

from hga_jax import __version__
from hga_jax.model import car_model
from hga_jax.model.fitness import length_of_fitness
from hga_jax.host.output import write_json
from hga_jax.running.results import NEAR_GAP, RunsResult, gap_of, json_safe
from . import anytime
from .config import Config
from .scenes import Scene

TARGETS = (0.0, 0.01, 0.05)  # gaps for "evaluations to target" (0: the hit, gap < 1e-6)
QUANTILES = (25, 50, 75)


def cell_id(config: Config, scene: Scene, seed: int, runs: int,
            yardstick: str = car_model.DEFAULT) -> str:
    """The cell's file name: a hash of what determines its runs and its gaps (the
    yardstick only when it is not the tight-rope optimum, and the solver only when it
    is not the batched HGA, so such ids stay as they were)."""
    key = {"settings": _identity(config.settings), "scene": scene.text,
           "seed": seed, "runs": runs, "version": __version__}
    if yardstick != car_model.DEFAULT:
        key["yardstick"] = yardstick
    if config.solver != "hga" or not config.batch:
        key["solver"] = {"solver": config.solver, "planner": config.planner,
                         "time_limit": config.time_limit, "batch": config.batch}
    key = json.dumps(key, sort_keys=True)
    return hashlib.sha256(key.encode()).hexdigest()[:20]


def _identity(settings) -> dict[str, Any]:
    """The settings that make a cell: a car model's name and the settings of the genes
    it adds only where they are read (a cell of the paper's model keeps the id it had
    before other models came)."""
    values = dataclasses.asdict(settings)
    unread = {k for name in car_model.names() for g in car_model.get(name).genes
              for k in (g.crossover, g.mutation, g.pc, g.pm)}
    unread -= {k for g in settings.model.genes for k in (g.crossover, g.mutation, g.pc, g.pm)}
    if settings.turns == car_model.DEFAULT:
        unread.add("turns")
    return {k: v for k, v in values.items() if k not in unread}


def optimum_details(optimum: Any) -> dict[str, Any]:
    """What a model's optimum records beside its length (the optima of the models it
    holds, its cusps: :meth:`~hga_jax.model.car_model.CarModel.extras`); {} without one."""
    if optimum is None or not optimum.feasible:
        return {}
    return car_model.get(optimum.turns).extras(optimum)


def tight_rope_optimum(optimum: Any, length: float | None) -> float | None:
    """What a cell records as the tight-rope optimum: the one a model's optimum reports
    beside its own (free turns), else the optimum's ``length`` itself."""
    if optimum is None:
        return length
    return car_model.get(optimum.turns).summary(optimum).get("tight_rope_length", length)


class Store:
    """Cell files ``<folder>/cells/<id>.json``."""

    def __init__(self, folder: str):
        self.folder = os.path.join(folder, "cells")
        os.makedirs(self.folder, exist_ok=True)
        for name in os.listdir(self.folder):  # left by a study killed while writing
            if name.startswith(".tmp-"):
                os.unlink(os.path.join(self.folder, name))

    def path(self, cid: str) -> str:
        return os.path.join(self.folder, cid + ".json")

    def done(self, cid: str) -> bool:
        return os.path.exists(self.path(cid))

    def load(self, cid: str) -> dict[str, Any]:
        with open(self.path(cid)) as fh:
            return json.load(fh)

    def save(self, cid: str, doc: dict[str, Any]) -> None:
        write_json(self.path(cid), json_safe(doc))


def _evals(gen: np.ndarray, population: int) -> list[int | None]:
    """Evaluations spent up to and including generation ``gen`` (None: never)."""
    return [population * (int(g) + 1) if g >= 0 else None for g in gen]


def cell_document(res: RunsResult, config: Config, scene: Scene, violations_full,
                  time_s=None) -> dict:
    """Everything the tables and figures need from one cell, JSON-ready and columnar.

    ``time_s``: per run its seconds of search on one core (default: the batch's search
    time times its devices, shared evenly by its runs)."""
    s = res.settings
    opt = res.optimum_length
    gen_hit = res.generation_hit
    runs = len(res.length)
    if time_s is None:
        time_s = np.full(runs, res.search_s * res.devices / max(runs, 1))
    time_s = np.asarray(time_s, np.float64)
    columns: dict[str, list] = {
        "run": res.run_ids.tolist(), "length": res.length.tolist(),
        "feasible": res.feasible.tolist(), "violations": res.violations.tolist(),
        "violations_full": np.asarray(violations_full).tolist(),
        "gap": [None if not np.isfinite(g) else float(g) for g in res.gap],
        "hit": res.hit.tolist(), "generation_best": res.generation.tolist(),
    }
    generations = res.history["best_fitness"].shape[0]
    per_gen = time_s / generations  # generation g ends at (g + 1) / (G + 1) of the run
    for t in TARGETS:
        gen = gen_hit if t == 0 else res.first_generation_within(t)
        tag = "hit" if t == 0 else f"{round(100 * t)}pct"
        columns[f"generation_{tag}"] = gen.tolist()
        columns[f"evaluations_{tag}"] = _evals(gen, s.population)
        columns[f"time_{tag}"] = [None if g < 0 else float((g + 1) * p)
                                  for g, p in zip(gen, per_gen)]
    h = res.history
    dist_m = length_of_fitness(h["best_so_far_fitness"].astype(np.float64))
    curves = {name: np.percentile(h[name].astype(np.float64), QUANTILES, axis=1).tolist()
              for name in ("best_fitness", "mean_fitness", "best_so_far_fitness")}
    if opt is not None:
        # Best-so-far Dist_m (length plus penalty) relative to the optimum: finite always.
        curves["best_so_far_gap_m"] = np.percentile(dist_m / opt - 1.0, QUANTILES, axis=1).tolist()
        near = res.first_generation_within(NEAR_GAP)
        gens = np.arange(h["best_fitness"].shape[0])[:, None]
        curves["within_1pct_fraction"] = np.mean((near >= 0) & (near <= gens), axis=1).tolist()
    curves["run0_best_fitness"] = h["best_fitness"][:, 0].astype(float).tolist()
    curves["run0_best_so_far_fitness"] = h["best_so_far_fitness"][:, 0].astype(float).tolist()
    columns["time_s"] = time_s.tolist()
    if opt is not None:
        ends = (np.arange(generations)[:, None] + 1) * per_gen[None, :]
        gaps = gap_of(h["best_so_far_length"], h["best_so_far_violations"] == 0, opt)
        curves["anytime_gap"] = anytime.quartiles(ends, gaps)
    o = res.optimum
    return {
        "solver": config.solver, "batch": config.batch,
        "config": config.label, "settings": dataclasses.asdict(s), "scenario": scene.name,
        "family": scene.family, "scenario_file": scene.path, "obstacles": scene.scenario.n,
        "seed": res.seed, "runs": len(res.length), "optimum": opt,
        "yardstick": o.turns if o is not None else None,
        "tight_rope_optimum": tight_rope_optimum(o, opt),
        "optimum_details": optimum_details(o),
        "optimum_touched": len(o.touched) if o is not None else None,
        "exact_s": o.seconds if o is not None else None,
        "compile_s": res.compile_s, "search_s": res.search_s, "finish_s": res.finish_s,
        "devices": res.devices, "evaluations_per_run": s.population * (s.generations + 1),
        **({"budget": res.budget} if res.budget else {}),
        "best": {"run": res.best_run, **{k: v for k, v in res.best.to_dict().items()
                                         if k in ("length", "feasible", "violations", "upper",
                                                  "lower", "legs")}},
        "columns": columns, "curves": curves,
    }
