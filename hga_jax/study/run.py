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

import dataclasses
import json
import os
import sys
import time
from typing import Any

import pandas as pd

from hga_jax import compiled
from hga_jax.host.config import load_scenario

from hga_jax.errors import ConfigError
from hga_jax.host.output import write_file, write_json
from hga_jax.model import car_model
from hga_jax.running.results import json_safe
from . import figures, solvers, summary, table
from .config import Study, load_study
from .scenes import Scene, family_scenes
from .store import Store, cell_id


@dataclasses.dataclass
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
    skipped: dict[str, str] = dataclasses.field(default_factory=dict)  # label -> why
    programs: dict[str, dict[str, int]] = dataclasses.field(default_factory=dict)
    """Compiled programs this call asked for, per kind and way found
    (:func:`hga_jax.compiled.tally_since`)."""


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
    for i, fam in enumerate(study.families):
        try:
            out += family_scenes(fam, os.path.join(folder, "scenes"))
        except RuntimeError as e:  # a generator that keeps no scene in its tries
            raise ConfigError(f"{study.source}: families[{i + 1}] ({fam.name!r}): {e}; "
                              "fewer obstacles or another kind may do") from None
    return out


def _bar(total: int, enabled: bool):
    from tqdm.auto import tqdm

    return tqdm(total=total, unit="cell", desc="study", disable=not enabled, leave=False)


def skipped(study: Study) -> dict[str, str]:
    """The configurations that cannot run here (a peer's package is missing), with why."""
    from hga_jax.peers import missing

    out = {}
    for c in study.configs:
        why = missing(c.solver, c.planner)
        if why:
            out[c.label] = why
    return out


def _devices(study: Study) -> str | None:
    """Ask for the study's ``cpu_devices``; a note when the runtime already has others."""
    if study.cpu_devices is None:
        return None
    import jax

    from hga_jax.errors import ConfigError
    from hga_jax.running.devices import use_cpu_cores

    try:
        use_cpu_cores(study.cpu_devices, source=f"{study.source}: cpu_devices")
    except ConfigError:
        pass
    have = jax.local_device_count()
    if have != study.cpu_devices:
        return (f"the study asks for {study.cpu_devices} CPU device(s); JAX had already "
                f"started with {have}, and times are core-seconds over those")
    return None


STUDY_FILE = "study.json"


def check_folder(folder: str, study: Study, force: bool = False) -> None:
    """Refuse (:class:`~hga_jax.errors.ConfigError`, one line) an output folder that is
    not this study's: a file, a folder holding a ``run`` result, or one holding another
    study (another name, or the quick version of the full one) unless ``force``, which
    removes that study's files first. A folder of this study is resumed."""
    from hga_jax.errors import ConfigError
    from hga_jax.host.output import result_files_in, writable_folder

    writable_folder(folder)
    old = result_files_in(folder)
    if old:
        raise ConfigError(f"{folder}: output folder: holds a run's result ({', '.join(old)}), "
                          "not a study's; use another folder")
    manifest = os.path.join(folder, STUDY_FILE)
    if not os.path.exists(manifest):
        if os.path.isdir(os.path.join(folder, "cells")) and not force:
            raise ConfigError(f"{folder}: output folder: holds study cells but no {STUDY_FILE}; "
                              "use --force to replace them, or another folder")
        if force:
            _remove(folder, [])
        return
    try:
        with open(manifest) as fh:
            doc = json.load(fh)
        mine = (doc["study"], doc["quick"]) == (study.name, study.quick)
    except (OSError, ValueError, KeyError, TypeError):
        doc, mine = {}, False
    if mine and not force:
        return
    if not force:
        what = f"study {doc.get('study')!r}" + (" (--quick)" if doc.get("quick") else "")
        raise ConfigError(f"{folder}: output folder: holds another study ({what}); use "
                          "--force to replace it, or another folder")
    _remove(folder, doc.get("files", []) + [manifest])


def _remove(folder: str, files: list[str]) -> None:
    """Delete a study's outputs from ``folder``: its listed files, cells, scenes, figures."""
    import shutil

    for f in files:
        if os.path.isfile(f) and os.path.dirname(os.path.abspath(f)).startswith(
                os.path.abspath(folder)):
            os.unlink(f)
    for sub in ("cells", "scenes", "figures"):
        shutil.rmtree(os.path.join(folder, sub), ignore_errors=True)


def run_study(path: str | Study, *, quick: bool = False, out: str | None = None,
              progress: bool | None = None, max_cells: int | None = None,
              scenes: int | None = None, force: bool = False,
              figures: bool = True) -> Outcome:
    """Run (or resume) the study file ``path``; ``max_cells`` stops after that many new
    cells (the tables then cover the finished ones); ``scenes`` runs only the first
    scenes of each family (see :func:`load_study`); ``figures=False`` writes the tables
    without the figures (the study's manifest says so)."""
    study = path if isinstance(path, Study) else load_study(path, quick, scenes)
    skip = skipped(study)
    if skip:
        study = dataclasses.replace(study, configs=[c for c in study.configs
                                                    if c.label not in skip])
    for why in dict.fromkeys(skip.values()):  # one line per reason
        names = ", ".join(repr(k) for k, v in skip.items() if v == why)
        print(f"skipped {names}: {why}", file=sys.stderr)
    note = _devices(study)
    folder = out or default_folder(study)
    check_folder(folder, study, force)
    os.makedirs(folder, exist_ok=True)
    if not os.path.exists(os.path.join(folder, STUDY_FILE)):  # the folder is this study's
        write_json(os.path.join(folder, STUDY_FILE), {"study": study.name, "quick": study.quick,
                                                      "source": study.source, "files": []})
    scenes = scenes_of(study, folder)
    store = Store(folder)
    plan = [(c, s, cell_id(c, s, study.seed, study.runs_of(c), study.yardstick))
            for c in study.configs for s in scenes]
    if progress is None:
        progress = sys.stderr.isatty()
    todo = [p for p in plan if not store.done(p[2])]
    ran = 0
    bar = _bar(len(plan), progress)
    bar.update(len(plan) - len(todo))
    t0, tally0 = time.perf_counter(), compiled.tally()
    try:
        for config, scene, cid in todo:
            if max_cells is not None and ran >= max_cells:
                break
            bar.set_postfix_str(f"{config.label[:30]} | {scene.name}")
            store.save(cid, solvers.run_cell(study, config, scene))
            ran += 1
            bar.update(1)
    except KeyboardInterrupt:
        bar.close()
        from hga_jax.errors import Interrupted

        kept = len(plan) - len(todo) + ran
        raise Interrupted(f"interrupted; {kept} of {len(plan)} cells finished and written in "
                          f"{store.folder} ({ran} this time): the same command resumes "
                          "there") from None
    bar.close()
    docs = [store.load(cid) for _, _, cid in plan if store.done(cid)]
    return _report(study, folder, scenes, plan, docs, ran, time.perf_counter() - t0,
                   skip, note, figures, compiled.tally_since(tally0))


def _report(study: Study, folder: str, scenes: list[Scene], plan, docs, ran: int,
            seconds: float, skip: dict[str, str], note: str | None,
            draw: bool = True, programs: dict | None = None) -> Outcome:
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
        md = summary.markdown(rows, f"Study {study.name}: {len(tab)} runs", skip, note,
                              summary.setup(study, scenes, docs))
        yardstick = car_model.get(study.yardstick).yardstick_note
        if yardstick:
            md = md.replace("\n", f"\n\n{yardstick}\n", 1)
        write_file(j("summary.md"), lambda fh: fh.write(md))
        table.write_csv(j("by_scene.csv"), pd.DataFrame(summary.by_scene(tab, labels)),
                        missing="nan")
        files += [j(n) for n in ("runs.csv", "runs.parquet", "runs.jsonl", "summary.csv",
                                 "summary.parquet", "summary.md", "by_scene.csv")]
        if draw:
            files += figures.all_figures(tab, docs, rows, labels, j("figures"))
        from . import analyses

        for name in study.analyses:
            files += analyses.ANALYSES[name](study, tab, docs, rows, folder, draw)
    manifest = os.path.join(folder, STUDY_FILE)
    write_json(manifest, json_safe({
        "versions": versions(),
        "study": study.name, "source": study.source, "quick": study.quick, "seed": study.seed,
        "runs_per_cell": study.runs, "configs": [c.label for c in study.configs],
        "scenes": [{"name": s.name, "family": s.family, "file": s.path} for s in scenes],
        "cells": len(plan), "cells_finished": len(docs), "cells_run_now": ran,
        "skipped": skip, "note": note,
        "seconds_now": seconds, "programs_now": programs or {},
        "figures": draw and bool(docs), "files": files,
    }))
    return Outcome(folder, study, tab, rows, docs, ran, len(docs) - ran, files + [manifest],
                   skip, programs or {})
