"""The ``hga-jax`` command: ``run`` (many seeded GA runs), ``exact`` (the optimum),
``check`` (validate files), ``plot`` (redraw a result file), ``export`` (a result's
path as poses at a chosen spacing, CSV and JSON; :mod:`hga_jax.host.poses`) and
``study`` (a grid of settings over scenes; :mod:`hga_jax.study.cli`).

``--start X,Y,HEADING_DEG`` and ``--goal`` (``run``, ``exact``, ``check``) replace
the scenario file's start or goal and are checked by the scenario's own rules
(:func:`hga_jax.host.config.scenario_from_dict`).

Settings are layered: the preset's, the scenario's ``[ga]`` table, a ``--ga``
TOML file (top-level keys are settings), then command-line flags; an error names
the source of each value it involves (:mod:`hga_jax.validation`). Operators
are named from :mod:`hga_jax.search.registry`: ``--plugin FILE.py`` (or a module
name; repeatable) and a ``--ga`` file's ``plugins = [...]`` (paths relative to
that file) are imported first, so operators they register can be named too, and
``run`` records them in result.json (``plugins``). Bad input ends with one line
``hga-jax: error: <file>: <key>: <problem>`` and exit status 2, before anything
is written. Result files are written before anything is printed, and a folder
holds one result: an earlier result is only replaced with ``--force``.

``run --distributed`` spreads one job over several processes
(:mod:`hga_jax.running.distributed`): every process runs the same command, process 0
writes and prints; bad input found by any process stops all of them with the
same line.

Exit status: 0 done (also when standard output was closed early, e.g. by
``| head``); 1 an input/output error (standard output full, a file that cannot
be written); 2 bad input; 3 an internal error (a bug: please report it); 130
interrupted (Ctrl-C or SIGTERM; a run keeps its finished batches for ``--resume``).
"""
from __future__ import annotations

import argparse
import dataclasses
import contextlib
import errno
import functools
import json
import math
import os
import signal
import sys
from typing import Any, Callable, Iterator, Sequence

from hga_jax import __version__
from hga_jax.errors import ConfigError, Interrupted, ModelMismatchError, PeerCrashed
from hga_jax.running import devices
from hga_jax.search import registry
from hga_jax.model import car_model
from hga_jax.search.settings import COLLISIONS, PAPER, PRECISIONS, PRESETS, RECOMMENDED, GASettings
from hga_jax.loop import cli as episode_cli
from hga_jax.study import cli as study_cli

from hga_jax import validation
from .config import load_scenario

DEFAULT_SCENARIO = os.path.join("configs", "scenarios", "robocup_paper.toml")
OPERATOR_HELP = {  # operator kind (a setting, registry.KINDS) -> help
    "selection": "parent selection",
    "perm_crossover": "crossover of the permutation",
    "perm_mutation": "mutation of the permutation",
    "label_crossover": "crossover of the labels",
    "label_mutation": "mutation of the labels",
    "path_mutation": "move on the touched sequence applied to children (none: off)",
    "leg_crossover": "crossover of the leg genes (with --turns free)",
    "leg_mutation": "mutation of the leg genes (with --turns free)",
    "end_mutation": "move on the ends of the path (the Reeds-Shepp car: start's circle, "
                    "gear and first leg, or goal's circle and last leg)",
}
GA_FLAGS = {  # setting -> (type, choices, help); operator kinds: choices "registry"
    "population": (int, None, "individuals per run"),
    "generations": (int, None, ("generations after the random initial one (on up to 9 "
                                "obstacles, see --generations-per-obstacle)")),
    "generations_per_obstacle": (int, None, ("generations added per obstacle beyond 9 "
                                             "(0: a fixed count)")),
    "reversing_budget": (int, None, ("times the generations for a car that also drives "
                                     "backward (1: as the forward car)")),
    "pairs_from": (int, None, ("fewest obstacles on which the guided_pairs path move turns "
                               "neighbours (fewer: the guided move; 0: always)")),
    "pc_upper": (float, None, "crossover probability per pair of parents, permutation"),
    "pm_upper": (float, None, "mutation probability per individual, permutation"),
    "pc_lower": (float, None, "crossover probability per pair of parents, labels"),
    "pm_lower": (float, None, "mutation probability per gene, labels"),
    "tournament_size": (int, None, "tournament size (with --selection tournament)"),
    "elites": (int, None, "best individuals kept from one generation to the next"),
    "collision": (str, COLLISIONS, "collision test: full, or the paper's Appendix B test"),
    **{kind: (str, "registry", OPERATOR_HELP.get(kind, kind.replace("_", " ")))
       for kind in registry.KINDS},
    "pm_path": (float, None, "probability per child of the path move"),
    "seeding": (float, None, "fraction of generation 0 (and restarts) built by wrapping "
                "obstacles that block the direct path"),
    "seeding_via": (float, None, "share of the seeded individuals that start from a path "
                    "through one random obstacle instead of the direct path"),
    "restart_via": (float, None, "in a restart of a run whose best path collides, that share "
                    "of the seeded individuals starts via a random obstacle too"),
    "restart_arcs": (float, None, "in such a restart, that share of the seeded individuals "
                     "also wraps the overlapping neighbours of its colliding arcs (tight rope)"),
    "wrap_clearer": (float, None, "share of the wraps (seeding, repair) that go round the "
                     "side whose two new legs pass through fewer obstacles (tight rope)"),
    "guided_arcs": (float, None, "share of the penalty the guided move's score adds for the "
                    "moved obstacle's arc where it has a violation of its own (tight rope)"),
    "restart_after": (int, None, "restart a run stalled this many generations (0: never)"),
    "islands": (int, None, "islands the population is split into, each selecting and "
                "keeping elites among its own (1: one population)"),
    "migrate_every": (int, None, "generations between the islands' migrants, the best of "
                      "each to the next (0: never)"),
    "precision": (str, PRECISIONS, "float precision of the search (lengths are reported in "
                  "float64 always)"),
    "turns": (str, "models", "the car model the GA searches and the optimum it is "
              "measured against: " + car_model.help_text()),
    "pc_legs": (float, None, "crossover probability per pair of parents, leg genes"),
    "pm_legs": (float, None, "mutation probability per gene, leg genes"),
    "pm_ends": (float, None, "probability per child of the end move (the Reeds-Shepp car)"),
    "ends_of_best": (int, None, "children per generation that are the parents' best moved "
                     "at its ends (the Reeds-Shepp car)"),
    "straight_of_best": (int, None, "children per generation that are the parents' best with "
                         "every leg straight (free turns, the Reeds-Shepp car)"),
    "tight_of_best": (int, None, "children per generation that are the parents' best with "
                      "every leg straight, moved as the tight rope would move it (free turns, "
                      "the Reeds-Shepp car)"),
}


class _Help(argparse.ArgumentDefaultsHelpFormatter):
    """Shows ``(default: X)`` where there is a default to show (not None, False or [])."""

    def _get_help_string(self, action: argparse.Action) -> str:
        if action.default is None or action.default is False or action.default in (
                [], argparse.SUPPRESS):
            return action.help or ""
        return super()._get_help_string(action)


class _Parser(argparse.ArgumentParser):
    """Usage errors (a bad flag value, a missing argument) as one line, exit status 2,
    like every other input error; ``--help`` still shows the whole usage."""

    def error(self, message: str):  # noqa: D401 (argparse's name)
        _error(f"{self.prog}: {message} (see {self.prog} --help)")
        sys.exit(2)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="hga-jax", formatter_class=_Help, description=(
        "Shortest Dubins-car paths among circular obstacles: hierarchical GA in JAX, "
        "compared with the model's exact optimum."))
    p.add_argument("--version", action="version", version=f"hga-jax {__version__}")
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")

    run = sub.add_parser("run", help="many seeded GA runs on a scenario", formatter_class=_Help,
                         description="Many seeded GA runs on a scenario, compared with the "
                         "exact optimum; writes result.json and history.csv (and PNGs).")
    run.add_argument("scenario", help=f"scenario TOML file, e.g. {DEFAULT_SCENARIO}")
    run.add_argument("--runs", type=int, default=1, metavar="N", help="number of runs")
    run.add_argument("--seed", type=int, default=0, metavar="S",
                     help="seed (0..2**32-1); run k uses (seed, k)")
    run.add_argument("--first-run", type=int, default=0, metavar="K",
                     help="index of the first run")
    run.add_argument("--preset", choices=tuple(PRESETS), default="recommended",
                     help="settings to start from: hga-jax's recommended HGA, or the paper's "
                     "exactly (roulette, CX, inversion, two-point, label redraw, pc 0.4, "
                     "pm 0.02, no elites); the scenario's [ga], --ga and flags go on top")
    run.add_argument("--ga", metavar="GA.toml",
                     help="TOML file of GA settings (top-level keys), over the scenario's [ga]")
    g = run.add_argument_group("GA settings", "override the scenario's [ga] table and --ga; "
                               "unset flags keep those (the paper's value is shown)")
    for key, (kind, choices, text) in GA_FLAGS.items():
        # Operators and car models are checked after parsing (GASettings reads their
        # registries, which a --plugin adds to); the help lists the ones registered now.
        named = choices in ("registry", "models")
        known = registry.names(key) if choices == "registry" else car_model.names()
        tail = (f"; registered: {', '.join(known)}, or one a --plugin registers"
                if named else "")
        g.add_argument(validation.flag(key), type=kind, choices=None if named else choices,
                       metavar="NAME" if named else None if choices else (
                           "P" if kind is float else "N"),
                       help=f"{text} (recommended: {getattr(RECOMMENDED, key)}, "
                            f"paper: {getattr(PAPER, key)}){tail}")
    _pose_args(run)
    _car_arg(run)
    _plugin_arg(run)
    run.add_argument("--chunk", type=int, metavar="N", help="runs per compiled batch (default: "
                     "about 50,000 chromosomes per batch, fewer if memory is short)")
    devices.add_option(run)
    run.add_argument("--resume", action="store_true",
                     help="finish an interrupted run in its output folder: the same command "
                     "with --resume searches the runs it had not finished (the results are "
                     "those of an uninterrupted run)")
    run.add_argument("--no-exact", action="store_true",
                     help="skip the exact optimum and the gaps to it")
    _output_args(run, "results/<scenario file name>")
    d = run.add_argument_group(
        "several processes", "one job over several processes (JAX's multi-process runtime): "
        "every process runs the same command and searches its share of the runs; process 0 "
        "writes and prints the whole result, the same as one process would")
    d.add_argument("--distributed", action="store_true",
                   help="join a multi-process job; under SLURM (srun) or Open MPI the processes "
                   "find each other by themselves, else give the three options below")
    d.add_argument("--coordinator", metavar="HOST:PORT", help="process 0's address and a free "
                   "port, the same for every process (implies --distributed)")
    d.add_argument("--num-processes", type=int, metavar="N",
                   help="processes in the job (implies --distributed)")
    d.add_argument("--process-id", type=int, metavar="K",
                   help="this process's number, 0..N-1 (implies --distributed)")

    ex = sub.add_parser("exact", help="the model's exact optimum (tangent-graph shortest path)",
                        formatter_class=_Help, description="The model's exact optimum: the "
                        "shortest path in the tangent graph; writes result.json (and path.png).")
    ex.add_argument("scenario", help="scenario TOML file")
    ex.add_argument("--collision", choices=COLLISIONS,
                    help="collision test (default: the scenario's [ga] collision, else full)")
    ex.add_argument("--turns", metavar="NAME", default=car_model.DEFAULT,
                    help="the car model: " + car_model.help_text() + "; or one a --plugin "
                    "registers")
    _car_arg(ex)
    _pose_args(ex)
    _plugin_arg(ex)
    _output_args(ex, "results/<scenario file name>-exact")

    ck = sub.add_parser("check", help="validate scenario (and --ga) files and exit",
                        formatter_class=_Help, description="Validate each scenario file (and "
                        "a --ga file on top of each); one line per file; exit 2 if any is bad.")
    ck.add_argument("scenario", nargs="+", help="scenario TOML files")
    ck.add_argument("--ga", metavar="GA.toml", help="GA settings file to check as well")
    _pose_args(ck)
    _plugin_arg(ck)

    pl = sub.add_parser("plot", help="redraw a path from a result.json", formatter_class=_Help,
                        description="Redraw the best path of a result file, or run K's, "
                        "optionally with the exact optimum overlaid; violations are marked.")
    pl.add_argument("result", help="result.json written by run or exact")
    pl.add_argument("--run", type=int, metavar="K", help="draw run K's best path (default: the "
                    "result's best)")
    pl.add_argument("--with-optimum", action="store_true",
                    help="overlay the exact optimum (solved if the file has none)")
    pl.add_argument("--out", metavar="FILE.png", help="PNG to write (default: path.png, or "
                    "path_run<K>.png with --run, beside the result file)")
    pl.add_argument("--force", action="store_true", help="replace an existing PNG")
    pl.add_argument("--no-cache", action="store_true", help="do not keep compiled programs on disk")
    _plugin_arg(pl)

    xp = sub.add_parser("export", help="a result's path as poses (CSV and JSON)",
                        formatter_class=_Help, description="Sample the best path of a result "
                        "file, or run K's, every SPACING metres (and at each segment boundary "
                        "and both ends) as poses s, x, y, heading, curvature, gear; writes "
                        "poses.csv and poses.json.")
    xp.add_argument("result", help="result.json written by run or exact")
    xp.add_argument("--spacing", default="0.01", metavar="M",
                    help="metres between poses along the path (> 0)")
    xp.add_argument("--run", type=int, metavar="K", help="export run K's best path (default: "
                    "the result's best)")
    xp.add_argument("--out", metavar="DIR", help="folder to write to (default: the result "
                    "file's folder); files poses.csv and poses.json, or poses_run<K>.csv and "
                    "poses_run<K>.json with --run")
    xp.add_argument("--force", action="store_true", help="replace existing pose files")
    xp.add_argument("--no-cache", action="store_true", help="do not keep compiled programs on disk")
    _plugin_arg(xp)

    study_cli.add_parser(sub, _Help)  # hga-jax study: see hga_jax/study/cli.py
    episode_cli.add_parser(sub, _Help)  # hga-jax episode: see hga_jax/loop/cli.py
    return p


def _pose_args(p: argparse.ArgumentParser) -> None:
    for key in ("start", "goal"):
        p.add_argument(f"--{key}", metavar="X,Y,HEADING_DEG",
                       help=f"replace the scenario's {key} pose: metres, metres, degrees "
                       f"counter-clockwise from +x (--{key}=-1,2,90 for a negative X)")


def _car_arg(p: argparse.ArgumentParser) -> None:
    p.add_argument("--car", metavar="CAR", help="replace the scenario's [robot] car: "
                   + ", ".join(car_model.cars()) + " (reeds-shepp also drives backward)")
    p.add_argument("--speed", metavar="M_PER_S", type=float,
                   help="replace the scenario's [robot] speed: the car's constant speed "
                   "along its path (m/s, > 0), which times it against robots that move")


def _with_car(scenario, args):
    """The scenario with ``--car`` as its car and ``--speed`` as its speed (checked: one
    line naming the flag)."""
    if args.car is not None:
        if args.car not in car_model.cars():
            raise validation.error("command line", "--car", f"must be one of "
                                   f"{', '.join(car_model.cars())}, got {args.car!r}")
        scenario = dataclasses.replace(scenario, car=args.car)
    speed = getattr(args, "speed", None)
    if speed is not None:
        if not (math.isfinite(speed) and speed > 0.0):
            raise validation.error("command line", "--speed", f"must be a finite number > 0, "
                                   f"got {speed!r}")
        scenario = dataclasses.replace(scenario, speed=float(speed))
    return scenario


def _pose_flags(args) -> dict[str, Any]:
    """``--start`` and ``--goal`` as overrides of the scenario file's poses
    (:data:`hga_jax.host.config.PoseOverride`); the scenario's rules check them."""
    poses = {}
    for key in ("start", "goal"):
        text = getattr(args, key, None)
        if text is None:
            continue
        try:
            x, y, heading = (float(part) for part in text.split(","))
        except ValueError:
            raise validation.error("command line", f"--{key}", "must be X,Y,HEADING_DEG "
                                   f"(metres, metres, degrees), got {text!r}") from None
        poses[key] = ({"x": x, "y": y, "heading_deg": heading}, "command line", f"--{key}")
    return poses


def _plugin_arg(p: argparse.ArgumentParser) -> None:
    p.add_argument("--plugin", action="append", default=[], metavar="FILE.py",
                   help="Python file (or module name) imported first, which may register "
                   "operators (hga_jax.search.registry.register; docs/operators.md); "
                   "repeatable")


def _output_args(p: argparse.ArgumentParser, default_out: str) -> None:
    p.add_argument("--out", metavar="DIR", help=f"output folder (default: {default_out})")
    p.add_argument("--plot", action="store_true", help="also write PNG plots")
    p.add_argument("--force", action="store_true",
                   help="replace the result already in the output folder (all its files)")
    p.add_argument("--json", action="store_true",
                   help="print the summary as one JSON object on stdout instead of text")
    p.add_argument("--quiet", action="store_true", help="no progress or compile messages")
    p.add_argument("--no-cache", action="store_true", help="do not keep compiled programs on "
                   "disk (default: $HGA_JAX_CACHE_DIR or ~/.cache/hga-jax/programs)")


def _ga_file(path: str) -> tuple[dict[str, Any], list[str]]:
    """A --ga file's settings (its top-level keys) and its ``plugins`` (paths relative
    to the file, joined to its folder; module names as written)."""
    table = validation.read_toml(path)
    plugins = validation.strings(table.pop("plugins", []), path, "plugins")
    here = os.path.dirname(path)
    return table, [os.path.normpath(os.path.join(here, p)) if validation.is_file(p) else p
                   for p in plugins]


def _plugins(args) -> list[str]:
    """Import the command's plugins (``--plugin``, then the --ga file's), before any
    settings are read; returns them in that order."""
    loaded = validation.load_plugins(args.plugin, "command line", "--plugin")
    if getattr(args, "ga", None):
        ga_plugins = _ga_file(args.ga)[1]
        loaded += validation.load_plugins(ga_plugins, args.ga, lambda i: f"plugins[{i + 1}]")
    return loaded


def _settings(scenario, ga_path: str | None, flags: dict[str, Any],
              base: GASettings | None = None) -> GASettings:
    """The layered settings: ``base`` (a preset; default the paper's), scenario [ga],
    --ga file, flags (None: unset)."""
    layers = [validation.file_layer(scenario.ga, scenario.source, "ga")]
    if ga_path:
        layers.append(validation.file_layer(_ga_file(ga_path)[0], ga_path))
    layers.append(validation.flag_layer(flags))
    return validation.settings(layers, base)


def _default_out(scenario_path: str, suffix: str = "") -> str:
    return os.path.join("results", os.path.splitext(os.path.basename(scenario_path))[0] + suffix)


def _cache(args) -> None:
    """Keep compiled programs on disk unless ``--no-cache``; warn if that cannot be done."""
    if not args.no_cache:
        from hga_jax.compiled import enable_compilation_cache

        enable_compilation_cache(on_error=lambda m: _warn(m))


def _warn(message: str) -> None:
    print(f"hga-jax: warning: {message}", file=sys.stderr, flush=True)


@contextlib.contextmanager
def _ctrl_c_deferred() -> Iterator[None]:
    """Hold Ctrl-C while files are written (so a result is whole); raise it after."""
    caught = []
    try:
        previous = signal.signal(signal.SIGINT, lambda *_: caught.append(True))
    except ValueError:  # not the main thread: nothing to defer
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
    if caught:
        raise Interrupted("interrupted after the result was written")


class _StdoutError(Exception):
    """Writing standard output failed (closed pipe, full device); carries the OSError."""


def _emit(text: str) -> None:
    """Print to stdout now (so a closed or full stdout is seen here, not at exit)."""
    try:
        sys.stdout.write(text + "\n")
        sys.stdout.flush()
    except OSError as e:
        raise _StdoutError(e) from None


def _cmd_run(args) -> int:
    plugins = _plugins(args)
    scenario = _with_car(load_scenario(args.scenario, _pose_flags(args)), args)
    settings = _settings(scenario, args.ga, {k: getattr(args, k) for k in GA_FLAGS},
                         PRESETS[args.preset])
    validation.run_range(args.seed, args.runs, args.first_run, args.chunk, "command line",
                         validation.flag, grouped=True)
    joined = args.distributed or any(v is not None for v in (
        args.coordinator, args.num_processes, args.process_id))
    if args.resume and joined:
        raise ConfigError("command line: --resume: not with --distributed (resume on one "
                          "process, or run the missing runs with --first-run)")
    if args.resume and args.force:
        raise ConfigError("command line: --resume: not with --force (--force starts over)")
    from hga_jax.running import distributed

    devices.from_option(args)  # before anything starts JAX's runtime
    if joined:
        distributed.initialize(args.coordinator, args.num_processes, args.process_id,
                               source="command line")
    import jax

    out = args.out or _default_out(args.scenario)
    prior = []  # a resumed job's partial result: (document, runs)
    check = functools.partial(_run_checks, args, scenario, settings, out, prior)
    distributed.together(check) if joined else check()
    _cache(args)
    res = _search_runs(args, scenario, settings, out, prior[0] if prior else None, joined,
                       plugins)
    if jax.process_index() != 0:  # process 0 writes and prints the result
        return 0
    from hga_jax.host import report

    with _ctrl_c_deferred():
        written = report.write_run(res, out, plot=args.plot, force=args.force or args.resume)
    if args.json:
        _emit(json.dumps(report.run_json(res, written), allow_nan=False))
    else:
        _emit(report.run_summary(res))
        _emit("wrote " + ", ".join(written))
    return 0


def _run_checks(args, scenario, settings, out: str, prior: list) -> None:
    """Before a run searches: the GA searches the car's paths under the collision test,
    a feasible path can exist (else the line ``check`` prints, as bad input: nothing is
    searched), the job fits in memory (each process holds the whole result), and (on
    the process that writes) the output folder takes it: empty, or replaced with
    --force, or holding the partial result that --resume finishes (appended to
    ``prior``)."""
    import jax

    from hga_jax.host import report
    from hga_jax.running import budget
    from .output import check_folder

    # before for_car: the error names where the car and the collision test came from
    validation.car(scenario, settings, "command line: --car" if args.car else None,
                   _collision_from(args, scenario))
    problem = _no_path(scenario, settings)  # what check refuses, run refuses (exit 2)
    if problem:
        raise ConfigError(f"{args.scenario}: {problem}")
    budget.plan(scenario.n, settings.for_car(scenario.car), args.runs, args.chunk,
                jax.local_device_count())
    if jax.process_index() != 0:
        return
    if args.resume:
        prior.append(report.load_partial(out, scenario, settings, args.seed, args.first_run,
                                         args.runs))
        return
    part = None if args.force else report.partial_in(out)
    if part is not None:
        raise ConfigError(f"{out}: output folder: holds an interrupted run ({part['runs_done']:,} "
                          f"of {part['runs_requested']:,} runs): add --resume to finish "
                          "it, or --force to start over")
    check_folder(out, args.force)


def _collision_from(args, scenario) -> str:
    """Where ``run``'s collision test came from: a flag, the --ga file, the scenario's
    [ga] table, or the preset."""
    if args.collision is not None:
        return "command line: --collision"
    if args.ga and "collision" in _ga_file(args.ga)[0]:
        return f"{args.ga}: collision"
    if "collision" in scenario.ga:
        return f"{scenario.source}: ga.collision"
    return f"the {args.preset} preset"


def _search_runs(args, scenario, settings, out: str, prior, joined: bool, plugins):
    """The runs still to do (all, or those after a resumed partial result ``prior``),
    joined with ``prior``'s. Interrupted, the finished runs are written as a partial
    result that ``--resume`` finishes (a single process only) before the interruption
    is passed on."""
    from hga_jax.host import report
    from hga_jax.running.runner import joined as join_runs, resumed, run_many

    done = 0 if prior is None else int(prior[0]["partial"]["runs_done"])

    def with_prior(res):
        if prior is None:
            return res
        kept = resumed(scenario, settings, args.seed, args.first_run, prior[1], res)
        whole = join_runs([kept, res])
        whole.earlier = {"runs": done, "compile_s": kept.compile_s, "search_s": kept.search_s}
        return whole

    try:
        res = run_many(scenario, settings, seed=args.seed, runs=args.runs - done,
                       first_run=args.first_run + done, chunk=args.chunk,
                       exact=not args.no_exact, progress=not args.quiet, preset=args.preset)
    except Interrupted as e:
        part = getattr(e, "partial", None)
        if part is None and prior is not None:
            raise Interrupted(f"{e}; the partial result written in {out} is as it was") from None
        if part is None or joined:
            raise
        part = with_prior(part)
        part.plugins = tuple(plugins)
        with _ctrl_c_deferred():
            report.write_partial(part, out, args.runs, force=True)
        raise Interrupted(f"{e}; the {len(part.length):,} finished runs of {args.runs:,} are "
                          f"written in {out} (the same command with --resume finishes the "
                          "job)") from None
    res = with_prior(res)
    res.plugins = tuple(plugins)
    return res


def _cmd_exact(args) -> int:
    _plugins(args)
    scenario = _with_car(load_scenario(args.scenario, _pose_flags(args)), args)
    collision = args.collision or _settings(scenario, None, {}).collision
    turns = car_model.resolve(args.turns, scenario.car)
    validation.turns(turns, collision, "command line", "--car" if args.car else "--turns")
    out = args.out or _default_out(args.scenario, "-exact")
    from .output import check_folder

    check_folder(out, args.force)
    _cache(args)
    from hga_jax.host import report
    from hga_jax.model.exact import solve

    opt = solve(scenario, collision, turns=turns, car=car_model.DUBINS)
    with _ctrl_c_deferred():
        written = report.write_exact(scenario, opt, out, plot=args.plot, force=args.force)
    if args.json:
        _emit(json.dumps(report.exact_json(scenario, opt, written), allow_nan=False))
    else:
        _emit(report.exact_summary(scenario, opt))
        _emit("wrote " + ", ".join(written))
    return 0


def _cmd_check(args) -> int:
    """One line per scenario file (ok, or an error), then one for ``--ga`` and the plugins.

    Robots that move: a moving robot whose model circle holds the start at time 0 is
    refused by the loader (an error line naming the obstacle; the file counts as bad).
    After a scene's ok line comes one line per moving robot whose model circle holds the
    goal when the car arrives there on the standing robots' shortest path (the exact
    optimum of :meth:`~hga_jax.model.scenario.Scenario.still_scene` in the scene's model,
    its length over ``[robot] speed``): a note, not an error, since a longer path that
    arrives later may still find the goal free. Exit status: 2 if any file is bad, else
    0, as for a scene where nothing moves (the notes change nothing).
    """
    from hga_jax.model.no_path import model_words
    from hga_jax.words import count

    plugins = _plugins(args)
    poses = _pose_flags(args)
    bad = 0
    ga_ok = args.ga is not None
    for path in args.scenario:
        try:
            sc = load_scenario(path, poses)
            st = _settings(sc, None, {})
        except ConfigError as e:
            _error(str(e))
            bad += 1
            continue
        if args.ga:
            try:
                st = _settings(sc, args.ga, {})
            except ConfigError as e:
                _error(str(e))
                ga_ok, bad = False, bad + 1
        problem = _no_path(sc, st)
        if problem:
            _error(f"{path}: {problem}")
            bad += 1
            continue
        turns = car_model.resolve(st.turns, sc.car)
        _emit(f"{path}: ok (scenario {sc.name}, {count(sc.n, 'obstacle')}, a feasible path "
              f"exists under {model_words(st.collision, turns)})")
        if sc.has_motion:  # a robot on the goal when the car gets there the shortest way
            from hga_jax.model.exact import solve
            from hga_jax.model.in_time import clearance

            still = solve(sc.still_scene(), st.collision, turns=turns)
            if still.feasible and math.isfinite(still.length):
                t = still.length / sc.speed
                for k, gap in clearance.at(sc, sc.goal[:2], t):
                    _emit(f"{path}: note: moving robot {k + 1} holds the goal at t = {t:.3f} s, "
                          f"when the car arrives on the standing robots' shortest path "
                          f"({still.length:.3f} m at {sc.speed:g} m/s; {-gap:.3f} m inside "
                          "its model circle): a path clear of it arrives later")
    if args.ga and ga_ok:
        keys = _ga_file(args.ga)[0]
        shown = ", ".join(f"{k} = {v}" for k, v in keys.items()) or "no settings"
        _emit(f"{args.ga}: ok (GA settings: {shown})")
    if plugins and not bad:
        _emit(f"plugins: {', '.join(plugins)}: ok (imported)")
    return 2 if bad else 0


def _no_path(scenario, settings) -> str | None:
    """None if the model of ``settings`` holds a feasible path in ``scenario``, else the
    line that says there is none, and why (the tangent graph alone: milliseconds)."""
    from hga_jax.model import no_path

    turns = car_model.resolve(settings.turns, scenario.car)
    if no_path.exists(scenario, settings.collision, turns):
        return None
    return no_path.verdict(settings.collision, turns,
                           no_path.why(scenario, settings.collision, turns))


def _cmd_plot(args) -> int:
    from .output import atomic_write, figure_writer
    from .report import redraw

    _plugins(args)
    folder = os.path.dirname(args.result) or "."
    out = args.out or os.path.join(folder, "path.png" if args.run is None
                                   else f"path_run{args.run}.png")
    if os.path.exists(out) and not args.force:
        raise ConfigError(f"{out}: already exists (use --force to replace it, or --out)")
    if not out.lower().endswith(".png"):
        raise ConfigError(f"{out}: --out: must name a .png file")
    _cache(args)
    fig = redraw(args.result, run=args.run, with_optimum=args.with_optimum)
    with _ctrl_c_deferred():
        atomic_write(out, figure_writer(fig), binary=True)
    _emit(f"wrote {out}")
    return 0


MAX_POSES = 1_000_000  # poses one export may write


def _cmd_export(args) -> int:
    from hga_jax.words import count

    from . import poses
    from .output import writable_folder
    from .report import load_result, result_path, result_scenario

    _plugins(args)
    try:
        spacing = float(args.spacing)
    except ValueError:
        spacing = math.nan
    if not (math.isfinite(spacing) and spacing > 0.0):
        raise validation.error("command line", "--spacing", "must be a number of metres > 0, "
                               f"got {args.spacing!r}")
    folder = args.out or os.path.dirname(args.result) or "."
    tail = "" if args.run is None else f"_run{args.run}"
    files = [os.path.join(folder, f"poses{tail}.{ext}") for ext in ("csv", "json")]
    writable_folder(folder)
    for name in files:
        if os.path.exists(name) and not args.force:
            raise ConfigError(f"{name}: already exists (use --force to replace it, or --out)")
    data = load_result(args.result)
    sc = result_scenario(args.result, data)
    if args.run is not None:
        _cache(args)  # run K's path is decoded again
    chosen = result_path(args.result, data, sc, args.run)
    key = "best" if args.run is None else "per_run"
    if chosen is None:
        raise ConfigError(f"{args.result}: best: no path in this result (no feasible path "
                          "exists)")
    length = float(chosen["length"])
    if length / spacing > MAX_POSES:
        raise validation.error("command line", "--spacing", f"{spacing:g} m makes "
                               f"{length / spacing:,.0f} poses along {length:.6f} m; at most "
                               f"{MAX_POSES:,}")
    table = poses.sample(chosen["segments"], spacing, start=sc.start)
    _check_ends(f"{args.result}: {key}", table, length, sc)
    what = "best path" if args.run is None else f"best path of run {args.run}"
    meta = {"source": args.result, "scenario": sc.name, "path": what, "run": chosen.get("run"),
            "length": length, "feasible": bool(chosen["feasible"]),
            "violations": int(chosen["violations"]), "spacing": spacing, "count": len(table)}
    with _ctrl_c_deferred():
        poses.write_csv(files[0], table)
        poses.write_json(files[1], table, meta)
    if not chosen["feasible"]:
        _warn(f"{args.result}: the {what} is infeasible "
              f"({count(int(chosen['violations']), 'violation')}); exported as it is")
    _emit(f"wrote {files[0]}, {files[1]}: {count(len(table), 'pose')} every {spacing:g} m "
          f"along the {what} ({length:.6f} m)")
    return 0


def _check_ends(where: str, table, length: float, sc) -> None:
    """The sampled path must have the file's length and start and end at the
    scenario's start and goal poses (1e-6 m and rad); else a ConfigError."""
    from .poses import wrap

    tol = 1e-6 * max(1.0, length)
    if abs(table[-1, 0] - length) > tol:
        raise ConfigError(f"{where}: segments: sum to {table[-1, 0]:.9f} m, not the path's "
                          f"length {length:.9f} m")
    for name, row, (x, y, heading) in (("start", table[0], sc.start), ("goal", table[-1], sc.goal)):
        if math.dist(row[1:3], (x, y)) > tol or abs(wrap(row[3] - heading)) > 1e-6:
            raise ConfigError(
                f"{where}: segments: the path's {name} pose ({row[1]:.6g}, {row[2]:.6g}, "
                f"{math.degrees(row[3]):.6g} deg) is not the scenario's ({x:.6g}, {y:.6g}, "
                f"{math.degrees(heading):.6g} deg)")


def _error(message: str) -> None:
    print(f"hga-jax: error: {message}", file=sys.stderr, flush=True)


def _silence_stdout() -> None:
    """Point file descriptor 1 at /dev/null, so the exit's flush of stdout cannot fail."""
    with contextlib.suppress(OSError):
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)


COMMANDS: dict[str, Callable[[Any], int]] = {
    "run": _cmd_run, "exact": _cmd_exact, "check": _cmd_check, "plot": _cmd_plot,
    "export": _cmd_export, "study": study_cli.run, "episode": episode_cli.run}


def _use_file_backend() -> None:
    """The command draws to files only: matplotlib's Agg backend, chosen here and
    nowhere in the library (its figures are ``Figure`` objects that need none), so
    importing ``hga_jax`` in a notebook leaves that notebook's backend alone. Not
    imported yet, matplotlib is told through its environment variable, so that a
    command that draws nothing does not import it."""
    if "matplotlib" in sys.modules:
        sys.modules["matplotlib"].use("Agg")
    else:
        os.environ["MPLBACKEND"] = "Agg"


def _terminated(signum, frame):  # SIGTERM stops a command as Ctrl-C does
    raise KeyboardInterrupt("terminated")


def main(argv: Sequence[str] | None = None) -> int:
    _use_file_backend()
    args = _parser().parse_args(argv)
    try:
        before = signal.signal(signal.SIGTERM, _terminated)
    except ValueError:  # not the main thread: leave signals alone
        before = None
    try:
        return _main(args)
    finally:
        if before is not None:
            signal.signal(signal.SIGTERM, before)


def _main(args) -> int:
    from hga_jax import compiled

    # every command's --no-cache (study's and episode's too): programs in memory only
    cache = (compiled.memory_only() if getattr(args, "no_cache", False)
             else contextlib.nullcontext())
    try:
        with cache:
            return COMMANDS[args.command](args)
    except ConfigError as e:
        _error(str(e))
        return 2
    except ModelMismatchError as e:
        print(f"hga-jax: internal error: {e} (please report this scenario)", file=sys.stderr,
              flush=True)
        return 3
    except PeerCrashed as e:
        _error(str(e))
        return 1
    except KeyboardInterrupt as e:
        text = str(e) if isinstance(e, Interrupted) or str(e) == "terminated" else "interrupted"
        tail = "" if "written" in text else "; nothing written"
        print(f"hga-jax: {text}{tail}", file=sys.stderr, flush=True)
        return 130
    except _StdoutError as wrapped:
        e = wrapped.args[0]
        _silence_stdout()
        if e.errno == errno.EPIPE:  # the reader stopped reading (| head): not an error
            return 0
        _error(f"standard output: {e.strerror or e}")
        return 1
    except OSError as e:
        where = f"{e.filename}: " if e.filename else ""
        _error(f"{where}{e.strerror or e}")
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
