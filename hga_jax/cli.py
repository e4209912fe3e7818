"""The ``hga-jax`` command: ``run`` (many seeded GA runs), ``exact`` (the optimum), ``check``,
``study`` (a grid of settings over scenes; :mod:`hga_jax.study.cli`).

Settings are layered: the paper's defaults, the scenario's ``[ga]`` table, a
``--ga`` TOML file (top-level keys are settings), then command-line flags.
Bad input ends with one line ``hga-jax: error: <file>: <key>: <problem>`` and
exit status 2, before anything is written; existing results are never
overwritten without ``--force``.
"""
from __future__ import annotations

import argparse
import os
import sys
import tomllib
from typing import Sequence

from . import __version__
from .config import load_scenario
from .errors import ConfigError
from .settings import (COLLISIONS, PERM_CROSSOVERS, PERM_MUTATIONS, PRECISIONS, SELECTIONS,
                       GASettings)
from .study import cli as study_cli

DEFAULT_SCENARIO = os.path.join("configs", "scenarios", "robocup_paper.toml")


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="hga-jax", description=(
        "Shortest Dubins-car paths among circular obstacles: hierarchical GA in JAX, "
        "compared with the model's exact optimum."))
    p.add_argument("--version", action="version", version=f"hga-jax {__version__}")
    sub = p.add_subparsers(dest="command", required=True)

    run = sub.add_parser("run", help="many seeded GA runs on a scenario")
    run.add_argument("scenario", help="scenario TOML file (e.g. %s)" % DEFAULT_SCENARIO)
    run.add_argument("--runs", type=int, default=1, help="number of runs (default 1)")
    run.add_argument("--seed", type=int, default=0, help="seed; run k uses (seed, k)")
    run.add_argument("--first-run", type=int, default=0, help="index of the first run")
    run.add_argument("--ga", help="TOML file of GA settings (top-level keys)")
    g = run.add_argument_group("GA settings (override the scenario and --ga)")
    g.add_argument("--population", type=int)
    g.add_argument("--generations", type=int)
    g.add_argument("--pc-upper", type=float, help="crossover probability per pair, permutation")
    g.add_argument("--pm-upper", type=float, help="mutation probability per individual, permutation")
    g.add_argument("--pc-lower", type=float, help="crossover probability per pair, labels")
    g.add_argument("--pm-lower", type=float, help="mutation probability per gene, labels")
    g.add_argument("--selection", choices=SELECTIONS)
    g.add_argument("--tournament-size", type=int)
    g.add_argument("--perm-crossover", choices=PERM_CROSSOVERS)
    g.add_argument("--perm-mutation", choices=PERM_MUTATIONS)
    g.add_argument("--elites", type=int)
    g.add_argument("--collision", choices=COLLISIONS)
    g.add_argument("--precision", choices=PRECISIONS, help="float precision of the search")
    run.add_argument("--chunk", type=int, help="runs per compiled batch (default ~50,000 "
                     "chromosomes per batch)")
    run.add_argument("--no-exact", action="store_true", help="skip the exact optimum and gaps")
    _output_args(run)

    ex = sub.add_parser("exact", help="the model's exact optimum (tangent-graph shortest path)")
    ex.add_argument("scenario")
    ex.add_argument("--collision", choices=COLLISIONS, default=None)
    _output_args(ex)

    ck = sub.add_parser("check", help="validate scenario (and --ga) files and exit")
    ck.add_argument("scenario", nargs="+")
    ck.add_argument("--ga")

    study_cli.add_parser(sub)  # hga-jax study: see hga_jax/study/cli.py
    return p


def _output_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", help="output folder (default results/<scenario file name>)")
    p.add_argument("--plot", action="store_true", help="also write PNG plots")
    p.add_argument("--force", action="store_true", help="overwrite an existing result.json")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.add_argument("--no-cache", action="store_true", help="do not keep compiled programs on "
                   "disk (default: $HGA_JAX_CACHE_DIR or ~/.cache/hga-jax/xla)")


def _ga_file(path: str | None, base: GASettings) -> GASettings:
    if not path:
        return base
    try:
        with open(path, "rb") as fh:
            table = tomllib.load(fh)
    except OSError as e:
        raise ConfigError(f"{path}: cannot read: {e.strerror or e}") from None
    except tomllib.TOMLDecodeError as e:
        raise ConfigError(f"{path}: TOML syntax error: {e}") from None
    return GASettings.from_mapping(table, path, prefix="", base=base)


def _settings(args, scenario) -> GASettings:
    from .runner import settings_for

    s = _ga_file(args.ga, settings_for(scenario))
    names = ("population", "generations", "pc_upper", "pm_upper", "pc_lower", "pm_lower",
             "selection", "tournament_size", "perm_crossover", "perm_mutation", "elites",
             "collision", "precision")
    return s.replace("command line", **{k: getattr(args, k) for k in names})


def _out_dir(args) -> str:
    out = args.out or os.path.join("results", os.path.splitext(os.path.basename(args.scenario))[0])
    target = os.path.join(out, "result.json")
    if os.path.exists(target) and not args.force:
        raise ConfigError(f"{target}: already exists (use --force to overwrite, or another --out)")
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as e:
        raise ConfigError(f"{out}: cannot create output folder: {e.strerror or e}") from None
    if not os.access(out, os.W_OK):
        raise ConfigError(f"{out}: output folder is not writable")
    return out


def _cache(args) -> None:
    """Keep compiled programs on disk unless ``--no-cache``."""
    if not args.no_cache:
        from .runner import enable_compilation_cache

        enable_compilation_cache()


def _cmd_run(args) -> int:
    scenario = load_scenario(args.scenario)
    settings = _settings(args, scenario)
    for flag, value, low, high in (("--runs", args.runs, 1, 2**31),
                                   ("--first-run", args.first_run, 0, 2**31 - max(args.runs, 1)),
                                   ("--seed", args.seed, 0, 2**32),
                                   ("--chunk", args.chunk or 1, 1, 2**31)):
        if not low <= value < high:
            raise ConfigError(f"command line: {flag}: must be in {low}..{high - 1}, got {value}")
    out = _out_dir(args)
    _cache(args)
    from . import report
    from .runner import run_many

    res = run_many(scenario, settings, seed=args.seed, runs=args.runs, first_run=args.first_run,
                   chunk=args.chunk, exact=not args.no_exact, progress=not args.quiet)
    print(report.run_summary(res))
    written = report.write_run(res, out, plot=args.plot)
    print("wrote " + ", ".join(written))
    return 0


def _cmd_exact(args) -> int:
    scenario = load_scenario(args.scenario)
    from .runner import settings_for

    collision = args.collision or settings_for(scenario).collision
    out = _out_dir(args)
    _cache(args)
    from . import report
    from .exact import solve

    opt = solve(scenario, collision)
    print(report.exact_summary(scenario, opt))
    written = report.write_exact(scenario, opt, out, plot=args.plot)
    print("wrote " + ", ".join(written))
    return 0


def _cmd_check(args) -> int:
    from .runner import settings_for

    for path in args.scenario:
        sc = load_scenario(path)
        _ga_file(args.ga, settings_for(sc))
        print(f"{path}: ok ({sc.name!r}, {sc.n} obstacles)")
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    command = {"run": _cmd_run, "exact": _cmd_exact, "check": _cmd_check,
               "study": study_cli.run}[args.command]
    try:
        return command(args)
    except ConfigError as e:
        print(f"hga-jax: error: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        where = f"{e.filename}: " if e.filename else ""
        print(f"hga-jax: error: {where}{e.strerror or e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("hga-jax: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
