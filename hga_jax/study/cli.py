"""The ``hga-jax study`` subcommand (kept apart from the other commands).

The study file names its own plugins (``plugins = [...]``, :mod:`hga_jax.study.config`);
options are checked by :mod:`hga_jax.validation` like the other commands'."""
from __future__ import annotations

import argparse

from hga_jax.running import devices


def add_parser(sub, formatter=argparse.HelpFormatter) -> None:
    p = sub.add_parser(
        "study", help="run or resume a study (grid of settings over scenes)",
        formatter_class=formatter, description=(
            "Run or resume a study: a grid of configurations (GA settings, or peers such as "
            "OMPL's planners, DEAP, random search and the exact solver) over scene files "
            "and generated scene families, many seeded runs per cell. Finished cells are "
            "kept in the output folder and never run again; writes runs and summary tables "
            "(CSV, Parquet, Markdown with intervals and tests) and figures. The study file "
            "format: docs/studies.md."))
    p.add_argument("config", help="study TOML file (e.g. configs/studies/reproduce_paper.toml)")
    _options(p)


def _options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--quick", action="store_true", help="the study's small [quick] version")
    p.add_argument("--out", metavar="DIR", help="output folder (default: results/<study name>, "
                   "results/<study name>_quick with --quick); a folder of the same study is "
                   "resumed")
    p.add_argument("--force", action="store_true", help="replace another study's outputs in "
                   "the output folder (its cells too)")
    p.add_argument("--scenes", type=int, help="only the first N scenes of each family "
                   "(a part of the study; the full study reuses its cells)")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no table: one "
                   "line saying what ran and where the summary is")
    p.add_argument("--no-cache", action="store_true", help="do not keep compiled programs "
                   "on disk")
    p.add_argument("--no-figures", action="store_true", help="write the tables, not the "
                   "figures (seconds per report; the same command without it draws them)")
    devices.add_option(p)


def run(args: argparse.Namespace) -> int:
    from .run import run_study

    devices.from_option(args)  # before anything starts JAX's runtime
    if not args.no_cache:
        from hga_jax.compiled import enable_compilation_cache

        enable_compilation_cache()
    if args.scenes is not None:
        from hga_jax import validation

        validation.at_least(args.scenes, "command line", "--scenes", 1)
    from hga_jax.loop import study as replanning

    if replanning.is_replanning(args.config):  # episodes, not runs: hga_jax/loop/study.py
        got = replanning.run(args.config, out=args.out, quick=args.quick, force=args.force,
                             progress=not args.quiet, episodes=args.scenes)
        print(f"replanning study: {len(got['episodes'])} episodes; results in "
              f"{got['folder']} (replanning.md)")
        return 0
    outcome = run_study(args.config, quick=args.quick, out=args.out, scenes=args.scenes,
                        progress=not args.quiet, force=args.force,
                        figures=not args.no_figures)
    import os
    import shutil

    from .summary import brief

    print(f"study {outcome.study.name}: {len(outcome.docs)} cells "
          f"({outcome.cells_run} run now, {outcome.cells_reused} already done), "
          f"{len(outcome.table)} runs; results in {outcome.folder}")
    if outcome.programs:
        print(programs_line(outcome.programs))
    md = os.path.join(outcome.folder, "summary.md")
    if outcome.docs and not args.quiet:
        print(brief(outcome.summary, min(100, shutil.get_terminal_size((100, 24)).columns)))
    if outcome.docs:
        print(f"every column, the tests and the notes: {md}")
    return 0


KINDS = {"ga-block": "GA", "decode64": "float64 decoder"}


def programs_line(programs: dict[str, dict[str, int]]) -> str:
    """One line: how many programs of each kind were compiled now, loaded from the
    program folder, or reused in this process (``Outcome.programs``)."""
    parts = []
    for kind, c in programs.items():
        parts.append(f"{KINDS.get(kind, kind)}: {c['compiled']} compiled, {c['loaded']} "
                     f"loaded from the program folder, {c['reused']} reused")
    return "programs: " + "; ".join(parts)
