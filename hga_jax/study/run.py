"""Running a study: scenes, the cells of the grid (resumable), tables, statistics, figures.

Outputs in the study folder (default ``results/<name>``, ``results/<name>_quick``
with ``quick``): ``scenes/`` (every scene as a scenario TOML file), ``cells/``
(one JSON file per finished cell), ``runs.csv``, ``runs.parquet`` and
``runs.jsonl`` (one row per run), ``summary.csv``, ``summary.parquet`` and
``summary.md`` (per group and configuration), ``by_scene.csv``, ``figures/*.png``,
the analyses' files, and ``study.json`` (what was run, with versions). Tables are
pandas DataFrames (:mod:`hga_jax.study.table` for their files). Everything is
written atomically.
"""
from __future__ import annotations

import os
import sys
import time
from dataclasses import dataclass
from typing import Any

from hga_jax.host.config import load_scenario
from hga_jax.model.path import decode64
import pandas as pd

from hga_jax.host.output import write_file, write_json
from hga_jax.running.results import json_safe
from hga_jax.running.runner import run_many
from . import figures, summary, table
from .config import Config, Study, load_study
from .scenes import Scene, family_scenes
from .store import Store, cell_document, cell_id


@dataclass
class Outcome:
    """What ``run_study`` did: the folder, the tables, and how many cells it ran."""

    folder: str
    study: Study
    table: Any  # a pandas DataFrame, one row per run
    summary: list[dict[str, Any]]
    docs: list[dict[str, Any]]
    cells_run: int
    cells_reused: int
    files: list[str]


def versions() -> dict[str, str]:
    import platform

    import jax
    import numpy
    import pyarrow
    import scipy

    from hga_jax import __version__

    return {"hga_jax": __version__, "jax": jax.__version__, "numpy": numpy.__version__,
            "scipy": scipy.__version__, "pandas": pd.__version__,
            "pyarrow": pyarrow.__version__, "python": platform.python_version()}


def default_folder(study: Study) -> str:
    return os.path.join("results", study.name + ("_quick" if study.quick else ""))


def scenes_of(study: Study, folder: str) -> list[Scene]:
    out = []
    for path in study.scenarios:
        sc = load_scenario(path)
        with open(path) as fh:
            out.append(Scene(sc.name, "files", path, sc, fh.read()))
    for fam in study.families:
        out += family_scenes(fam, os.path.join(folder, "scenes"))
    return out


def _bar(total: int, enabled: bool):
    from tqdm.auto import tqdm

    return tqdm(total=total, unit="cell", desc="study", disable=not enabled, leave=False)


def run_cell(study: Study, config: Config, scene: Scene) -> dict[str, Any]:
    """Run one configuration on one scene and describe it (see ``store.cell_document``)."""
    res = run_many(scene.scenario, config.settings, seed=study.seed, runs=study.runs,
                   turns=study.yardstick)
    full = res.violations
    if config.settings.collision != "full":
        full = decode64(scene.scenario, res.perm, res.labels, "full").violations
    return cell_document(res, config, scene, full)


def run_study(path: str | Study, *, quick: bool = False, out: str | None = None,
              progress: bool | None = None, max_cells: int | None = None,
              scenes: int | None = None) -> Outcome:
    """Run (or resume) the study file ``path``; ``max_cells`` stops after that many new
    cells (the tables then cover the finished ones); ``scenes`` runs only the first
    scenes of each family (see :func:`load_study`)."""
    study = path if isinstance(path, Study) else load_study(path, quick, scenes)
    folder = out or default_folder(study)
    os.makedirs(folder, exist_ok=True)
    scenes = scenes_of(study, folder)
    store = Store(folder)
    plan = [(c, s, cell_id(c, s, study.seed, study.runs, study.yardstick))
            for c in study.configs for s in scenes]
    if progress is None:
        progress = sys.stderr.isatty()
    todo = [p for p in plan if not store.done(p[2])]
    ran = 0
    bar = _bar(len(plan), progress)
    bar.update(len(plan) - len(todo))
    t0 = time.perf_counter()
    for config, scene, cid in todo:
        if max_cells is not None and ran >= max_cells:
            break
        bar.set_postfix_str(f"{config.label[:30]} | {scene.name}")
        store.save(cid, run_cell(study, config, scene))
        ran += 1
        bar.update(1)
    bar.close()
    docs = [store.load(cid) for _, _, cid in plan if store.done(cid)]
    return _report(study, folder, scenes, plan, docs, ran, time.perf_counter() - t0)


def _report(study: Study, folder: str, scenes: list[Scene], plan, docs, ran: int,
            seconds: float) -> Outcome:
    labels = [c.label for c in study.configs]
    files: list[str] = []
    tab = table.build(study.name, docs)
    rows: list[dict[str, Any]] = []
    if docs:
        j = lambda name: os.path.join(folder, name)  # noqa: E731
        table.write_csv(j("runs.csv"), tab)
        table.write_parquet(j("runs.parquet"), tab)
        table.write_jsonl(j("runs.jsonl"), tab)
        rows = summary.summarize(tab, labels)
        table.write_csv(j("summary.csv"), pd.DataFrame(rows), missing="nan")
        table.write_parquet(j("summary.parquet"), pd.DataFrame(rows))
        md = summary.markdown(rows, f"Study {study.name}: {len(tab)} runs")
        if study.yardstick == "free":
            md = md.replace("\n", "\n\nGaps and hits are measured against the free-turn "
                            "optimum (turns in free space too), not the tight-rope one. "
                            "Configurations with turns = \"free\" search free-turn chromosomes "
                            "(leg genes); the others search tight-rope paths.\n", 1)
        write_file(j("summary.md"), lambda fh: fh.write(md))
        table.write_csv(j("by_scene.csv"), pd.DataFrame(summary.by_scene(tab, labels)),
                        missing="nan")
        files += [j(n) for n in ("runs.csv", "runs.parquet", "runs.jsonl", "summary.csv",
                                 "summary.parquet", "summary.md", "by_scene.csv")]
        files += figures.all_figures(tab, docs, rows, labels, j("figures"))
        from . import analyses

        for name in study.analyses:
            files += analyses.ANALYSES[name](study, tab, docs, rows, folder)
    manifest = os.path.join(folder, "study.json")
    write_json(manifest, json_safe({
        "versions": versions(),
        "study": study.name, "source": study.source, "quick": study.quick, "seed": study.seed,
        "runs_per_cell": study.runs, "configs": [c.label for c in study.configs],
        "scenes": [{"name": s.name, "family": s.family, "file": s.path} for s in scenes],
        "cells": len(plan), "cells_finished": len(docs), "cells_run_now": ran,
        "seconds_now": seconds, "files": files,
    }))
    return Outcome(folder, study, tab, rows, docs, ran, len(docs) - ran, files + [manifest])
