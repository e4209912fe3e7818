"""Benchmark of hga-jax's GA, and of the same GA written with DEAP, in one process.

What it measures (the paper's GA settings: population 50, 50 generations):

- runs: ``robocup_paper.toml`` (n = 9) with R = 1, 100, 1,000 and 10,000 runs;
- sizes: R = 1,000 runs of clutter scenes with n = 25, 50 and 100 obstacles (the
  scene generator of the studies, scene 0 of the scaling study's family: seed 21,
  1.4 obstacles per square metre, the density of the RoboCup scene);
- each in float32 and float64 (``GASettings(precision=...)``): the compile time
  (the first call of a batch shape; no on-disk compilation cache), the median
  search time over repeats, evaluations/s ``R * population * (generations + 1) /
  search`` and runs/s; the float64 re-evaluation after the search ("finish") is
  reported apart;
- memory: peak RSS (the process's high-water mark) of one ``run_many`` call of
  10,000 and of 100,000 runs, each in a fresh process;
  ``--million`` adds 1,000,000 runs done in chunks of 100,000 (progress on stderr);
- models: R = 1,000 runs on ``robocup_paper`` per preset (paper, recommended) and car
  model (``hga_jax.model.car_model.names()``): the median search time and a
  fingerprint of the runs' arrays (perm, labels, leg genes, lengths, violations), so
  that two checkouts can be compared side by side (same fingerprint: the same runs);
- presets: the recommended preset against the paper's for the same evaluations
  (both 50 x 51 per run, the recommended budget's growth with n switched off), R =
  1,000 runs of ``robocup_paper`` (n = 9) and of the clutter scenes with 25 and 40
  obstacles, timed alternately (paper, recommended, paper, ...): the median search
  times and their ratio, the figure the speed goal is stated in;
- DEAP: the same GA written with DEAP (:mod:`hga_jax.peers.deap_ga`, its
  fitness from a pure-Python decoder) on ``robocup_paper``, median wall time per
  run, and the ratio to hga-jax's search time per run at R = 10,000 (float32).

hga-jax spreads its runs over one JAX device per CPU core (``--cpu-devices N`` for
another count; the memory cases' processes get the same count), the default of
``hga-jax run``; the DEAP version runs on one core.

A fixed pure-Python loop (``calibration.py``) is timed beside every figure: the
machine is shared and its speed varies; compare figures taken with similar
calibration times.

Usage (from the repository root)::

    python3 experiments/benchmark.py [--quick] [--only runs sizes models presets parts memory deap]
        [--runs 1 100 1000 10000] [--sizes 25 50 100] [--precisions float32 float64]
        [--repeats 3] [--deap-runs 20] [--million] [--cpu-devices N]
        [--out results/benchmark/benchmark.json]

``--quick`` is a smoke run of every part (R = 1 and 100, n = 25 with 100 runs, one
repeat, memory of 1,000 runs, 2 DEAP runs). The DEAP part needs ``deap`` (the
``compare`` extra) and is skipped without it. Prints a table and writes the JSON.
"""
from __future__ import annotations

import argparse
import dataclasses
import importlib.util
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from typing import Any

import jax
import numpy as np

from calibration import calibration

import hga_jax
from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.host.output import write_json
from hga_jax.running.runner import run_many
from hga_jax.search.settings import GASettings
from hga_jax.study.scenes import generate

HERE = os.path.dirname(os.path.abspath(__file__))
PAPER_SCENE = os.path.join("configs", "scenarios", "robocup_paper.toml")
SCENE_SEED, DENSITY = 21, 1.4  # configs/studies/scaling.toml's clutter family
MILLION, MILLION_CHUNK = 1_000_000, 100_000
MEMORY_LIMIT_MB = 4096

jax.config.update("jax_enable_compilation_cache", False)  # compile times from scratch


# -- scenes and machine ------------------------------------------------------------------

def paper_scene():
    return load_scenario(PAPER_SCENE)


def clutter_scene(n: int):
    """Scene 0 with ``n`` obstacles of the scaling study's clutter family."""
    return scenario_from_dict(generate("clutter", n, SCENE_SEED, 0, f"clutter_n{n:03d}_000",
                                       DENSITY))


def machine() -> dict[str, Any]:
    """What the figures were measured on."""
    cpu = platform.processor() or ""
    try:
        with open("/proc/cpuinfo") as fh:
            cpu = next((line.split(":", 1)[1].strip() for line in fh
                        if line.startswith("model name")), cpu)
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "system": platform.platform(),
            "python": platform.python_version(), "jax": jax.__version__,
            "numpy": np.__version__, "hga_jax": hga_jax.__version__,
            "devices": [str(d) for d in jax.devices()]}


def peak_rss_mb() -> float:
    """This process's peak resident memory so far (MB).

    Linux's ``VmHWM`` (``/proc/self/status``): ``ru_maxrss`` would do, but on Linux a
    child process inherits its parent's figure at the fork, so a fresh process
    started by a large one would report the parent's peak. ``ru_maxrss`` (kB) where
    there is no ``/proc``.
    """
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


# -- hga-jax -----------------------------------------------------------------------------

def bench_case(sc, runs: int, precision: str, repeats: int, seed: int = 0) -> dict[str, Any]:
    """Compile (first call of this batch shape), then ``repeats`` timed searches."""
    settings = GASettings(precision=precision)
    cal = calibration()
    first = run_many(sc, settings, seed=seed, runs=runs, exact=False)
    search = [first.search_s]
    for _ in range(1, repeats):
        search.append(run_many(sc, settings, seed=seed, runs=runs, exact=False).search_s)
    med = statistics.median(search)
    evaluations = runs * settings.population * (settings.generations + 1)
    return {"scenario": sc.name, "n": sc.n, "runs": runs, "precision": precision,
            "compile_s": first.compile_s, "search_s": search, "search_median_s": med,
            "finish_s": first.finish_s, "evaluations": evaluations,
            "evaluations_per_s": evaluations / med, "runs_per_s": runs / med,
            "per_run_s": med / runs, "calibration_s": cal}


def model_case(sc, preset_name: str, turns: str, runs: int, repeats: int) -> dict[str, Any]:
    """``runs`` runs of a preset under a car model: compile, then ``repeats`` timed
    searches; the fingerprint (sha256, 16 hex digits) of the runs' arrays."""
    import hashlib

    from hga_jax.search.settings import preset

    settings = preset(preset_name).replace(turns=turns)
    cal = calibration()
    results = [run_many(sc, settings, seed=0, runs=runs, exact=False) for _ in range(repeats + 1)]
    res = results[-1]
    arrays = (res.perm, res.labels, res.length, res.violations) + (
        () if res.legs is None else (res.legs,))
    fingerprint = hashlib.sha256(b"".join(np.ascontiguousarray(a).tobytes()
                                          for a in arrays)).hexdigest()[:16]
    search = [r.search_s for r in results[1:]]
    med = statistics.median(search)
    evaluations = runs * settings.population * (settings.for_obstacles(sc.n).generations + 1)
    return {"preset": preset_name, "turns": turns, "runs": runs, "search_s": search,
            "search_median_s": med, "evaluations_per_s": evaluations / med,
            "fingerprint": fingerprint, "calibration_s": cal}


def same_evaluations() -> tuple[GASettings, GASettings]:
    """The paper's preset and the recommended one with the paper's evaluations per run
    (50 x 51: the recommended budget's growth with n switched off)."""
    from hga_jax.search.settings import preset

    paper = preset("paper")
    return paper, dataclasses.replace(preset("recommended"), generations_per_obstacle=0,
                                      generations=paper.generations)


def presets_case(sc, runs: int, repeats: int) -> dict[str, Any]:
    """The recommended preset against the paper's on ``sc``, the same evaluations per run
    (the recommended budget's growth with n off), timed alternately after a first call."""
    paper, rec = same_evaluations()
    cal = calibration()
    times: dict[str, list[float]] = {"paper": [], "recommended": []}
    for name, st in (("paper", paper), ("recommended", rec)):
        run_many(sc, st, seed=0, runs=runs, exact=False)  # compile
    for r in range(repeats):
        for name, st in (("paper", paper), ("recommended", rec)):
            times[name].append(run_many(sc, st, seed=1 + r, runs=runs, exact=False).search_s)
    med = {k: statistics.median(v) for k, v in times.items()}
    evaluations = runs * paper.population * (paper.generations + 1)
    return {"scenario": sc.name, "n": sc.n, "runs": runs, "evaluations": evaluations,
            "search_s": times, "paper_s": med["paper"], "recommended_s": med["recommended"],
            "ratio": med["recommended"] / med["paper"], "calibration_s": cal}


PARTS = (("guided move", {"path_mutation": "none"}), ("seeding", {"seeding": 0.0}),
         ("restarts", {"restart_after": 0}), ("islands", {"islands": 1}))
"""The recommended preset's additions to the paper's HGA that cost search time, each as
the settings that switch it off (``parts_case``)."""


def parts_case(sc, runs: int, repeats: int) -> dict[str, Any]:
    """The recommended preset's search (the paper's evaluations, as :func:`presets_case`)
    with each of :data:`PARTS` off, and with all of them off, beside the paper's and the
    whole preset: median search times, timed alternately after a first call."""
    paper, rec = same_evaluations()
    variants = {"paper": paper, "recommended": rec}
    for name, off in PARTS:
        variants[f"without {name}"] = dataclasses.replace(rec, **off)
    variants["without all four"] = dataclasses.replace(
        rec, **{k: v for _, off in PARTS for k, v in off.items()})
    cal = calibration()
    times: dict[str, list[float]] = {name: [] for name in variants}
    for st in variants.values():
        run_many(sc, st, seed=0, runs=runs, exact=False)  # compile
    for r in range(repeats):
        for name, st in variants.items():
            times[name].append(run_many(sc, st, seed=1 + r, runs=runs, exact=False).search_s)
    med = {k: statistics.median(v) for k, v in times.items()}
    return {"scenario": sc.name, "n": sc.n, "runs": runs, "search_s": times, "median_s": med,
            "over_paper": {k: v / med["paper"] for k, v in med.items()},
            "calibration_s": cal}


def memory_case(runs: int) -> dict[str, Any]:
    """Peak RSS of ``runs`` runs of the paper's setting, measured in a fresh process."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(hga_jax.__file__)))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]))
    proc = subprocess.run([sys.executable, os.path.abspath(__file__), "--child-runs", str(runs),
                           "--cpu-devices", str(jax.local_device_count())],
                          stdout=subprocess.PIPE, text=True, env=env)  # stderr: progress
    if proc.returncode != 0:
        raise RuntimeError(f"the memory case of {runs:,} runs failed (its messages are above)")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def child(runs: int) -> None:
    """The fresh process of :func:`memory_case`: one ``run_many`` call, or chunks of
    ``MILLION_CHUNK`` runs for more, and one JSON line on stdout."""
    sc = paper_scene()
    settings = GASettings()
    before = peak_rss_mb()
    cal = calibration()
    t0 = time.perf_counter()
    if runs <= MILLION_CHUNK:
        res = run_many(sc, settings, seed=0, runs=runs, exact=False)
        length, violations = res.length, res.violations
        compile_s, search_s = res.compile_s, res.search_s
    else:
        length, violations = np.empty(runs), np.empty(runs, np.int64)
        compile_s = search_s = 0.0
        for lo in range(0, runs, MILLION_CHUNK):
            size = min(MILLION_CHUNK, runs - lo)
            res = run_many(sc, settings, seed=0, runs=size, first_run=lo, exact=False,
                           progress=True)
            length[lo:lo + size], violations[lo:lo + size] = res.length, res.violations
            compile_s, search_s = compile_s + res.compile_s, search_s + res.search_s
            del res
            print(f"{lo + size:,} of {runs:,} runs done in {time.perf_counter() - t0:.0f} s, "
                  f"peak RSS {peak_rss_mb():.0f} MB", file=sys.stderr, flush=True)
    wall = time.perf_counter() - t0
    opt = solve(sc).length
    feasible = violations == 0
    hits = int(np.sum(feasible & (length / opt - 1 < 1e-6)))
    print(json.dumps({
        "runs": runs, "peak_rss_mb": peak_rss_mb(), "rss_before_runs_mb": before,
        "wall_s": wall, "compile_s": compile_s, "search_s": search_s,
        "runs_per_s": runs / search_s, "hit_rate": hits / runs,
        "feasible_rate": float(np.mean(feasible)), "calibration_s": cal}))


# -- DEAP ----------------------------------------------------------------------------------

def deap_case(runs: int, seed: int = 0) -> dict[str, Any] | None:
    """Median wall time per run of the DEAP version (None without deap)."""
    if importlib.util.find_spec("deap") is None:
        return None
    from hga_jax.peers.deap_ga import run
    from hga_jax.peers.python_decoder import PythonDecoder

    cal = calibration()
    sc, settings = paper_scene(), GASettings()
    decoder = PythonDecoder.from_scenario(sc, settings.collision)
    times = [run(sc, settings, seed, k, decoder)["seconds"] for k in range(runs)]
    return {"scenario": "robocup_paper", "runs": runs, "per_run_s": times,
            "median_per_run_s": statistics.median(times), "calibration_s": cal}


def ratio(cases: list[dict[str, Any]], deap: dict[str, Any] | None) -> dict[str, Any] | None:
    """DEAP's time per run over hga-jax's (float32 at n = 9, R = 10,000, else the largest R)."""
    mine = [c for c in cases if c["scenario"] == "robocup_paper" and c["precision"] == "float32"]
    if deap is None or not mine:
        return None
    ref = max(mine, key=lambda c: (c["runs"] == 10_000, c["runs"]))
    return {"hga_jax_runs": ref["runs"], "hga_jax_per_run_s": ref["per_run_s"],
            "deap_per_run_s": deap["median_per_run_s"],
            "deap_over_hga_jax": deap["median_per_run_s"] / ref["per_run_s"]}


# -- report --------------------------------------------------------------------------------

def print_header() -> None:
    print(f"{'scenario':16s} {'n':>4s} {'runs':>7s} {'precision':9s} {'compile s':>9s} "
          f"{'search s':>9s} {'evals/s':>11s} {'runs/s':>9s} {'finish s':>8s} {'calib s':>7s}")


def print_cases(cases: list[dict[str, Any]]) -> None:
    for c in cases:
        print(f"{c['scenario']:16s} {c['n']:4d} {c['runs']:7,d} {c['precision']:9s} "
              f"{c['compile_s']:9.2f} {c['search_median_s']:9.3f} "
              f"{c['evaluations_per_s']:11,.0f} {c['runs_per_s']:9,.1f} {c['finish_s']:8.2f} "
              f"{c['calibration_s']:7.4f}", flush=True)


def print_memory(m: dict[str, Any]) -> None:
    print(f"{m['runs']:>9,d} runs: peak RSS {m['peak_rss_mb']:7.0f} MB (before the runs "
          f"{m['rss_before_runs_mb']:.0f} MB), {m['wall_s']:.1f} s in all (compile "
          f"{m['compile_s']:.1f} s, search {m['search_s']:.1f} s), hit rate "
          f"{m['hit_rate']:.1%}; calibration {m['calibration_s']:.4f} s", flush=True)


def parse(argv=None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="See the module docstring for what each part measures.")
    p.add_argument("--quick", action="store_true", help="a fast smoke run of every part")
    p.add_argument("--only", nargs="+", choices=("runs", "sizes", "models", "presets", "parts",
                                                   "memory", "deap"),
                   default=["runs", "sizes", "models", "presets", "parts", "memory", "deap"],
                   help="parts to run")
    p.add_argument("--runs", type=int, nargs="+", help="run counts at n = 9 (1 100 1000 10000)")
    p.add_argument("--sizes", type=int, nargs="+", help="obstacle counts at R = 1000 (25 50 100)")
    p.add_argument("--size-runs", type=int, help="runs per size case (1000)")
    p.add_argument("--precisions", nargs="+", choices=("float32", "float64"),
                   default=["float32", "float64"])
    p.add_argument("--repeats", type=int, help="timed searches per case, median taken (3)")
    p.add_argument("--memory-runs", type=int, nargs="+", help="run counts measured for peak "
                   "RSS, each in a fresh process (10000 100000)")
    p.add_argument("--million", action="store_true",
                   help=f"also {MILLION:,} runs in chunks of {MILLION_CHUNK:,} (progress shown)")
    p.add_argument("--deap-runs", type=int, help="DEAP runs timed (20)")
    p.add_argument("--cpu-devices", type=int, metavar="N", help="CPU devices hga-jax spreads "
                   "its runs over (default: one per core); DEAP runs on one core")
    p.add_argument("--out", default=os.path.join("results", "benchmark", "benchmark.json"))
    p.add_argument("--child-runs", type=int, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    quick = args.quick
    defaults = {"runs": [1, 100] if quick else [1, 100, 1000, 10_000],
                "sizes": [25] if quick else [25, 50, 100], "size_runs": 100 if quick else 1000,
                "repeats": 1 if quick else 3,
                "memory_runs": [1000] if quick else [10_000, 100_000],
                "deap_runs": 2 if quick else 20}
    for key, value in defaults.items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    return args


def main(argv=None) -> int:
    args = parse(argv)
    try:
        hga_jax.use_cpu_cores(args.cpu_devices, source="--cpu-devices")  # before any JAX work
    except hga_jax.ConfigError as e:
        print(f"benchmark.py: error: {e}", file=sys.stderr)
        return 2
    if args.child_runs:
        child(args.child_runs)
        return 0
    report: dict[str, Any] = {"machine": machine(), "settings": dataclasses.asdict(GASettings()),
                              "quick": args.quick, "calibration_start_s": calibration()}
    print(f"hga-jax {hga_jax.__version__}, JAX {jax.__version__} on {report['machine']['cpu']} "
          f"({report['machine']['cores']} cores, hga-jax on {jax.local_device_count()} CPU "
          f"device(s)); calibration (10^6 pure-Python multiply-adds): "
          f"{report['calibration_start_s']:.4f} s", flush=True)
    cases: list[dict[str, Any]] = []
    if "runs" in args.only or "sizes" in args.only:
        print(f"\nhga-jax, paper settings; search: median of {args.repeats}", flush=True)
        print_header()
    if "runs" in args.only:
        sc = paper_scene()
        for precision in args.precisions:
            for runs in args.runs:
                cases.append(bench_case(sc, runs, precision, args.repeats))
                print_cases(cases[-1:])
    if "sizes" in args.only:
        for n in args.sizes:
            sc = clutter_scene(n)
            for precision in args.precisions:
                cases.append(bench_case(sc, args.size_runs, precision, args.repeats))
                print_cases(cases[-1:])
    if any(c["compile_s"] < 0.1 for c in cases):
        print("(compile s near 0: an earlier case compiled the same batch shape; large jobs "
              "run in batches of one shape)")
    report["cases"] = cases
    report["models"] = []
    if "models" in args.only:
        from hga_jax.model import car_model

        runs = 100 if args.quick else 1000
        print(f"\npresets x car models, robocup_paper, {runs:,} runs; search: median of "
              f"{args.repeats} after a first call", flush=True)
        print(f"{'preset':<12} {'turns':<11} {'search s':>9} {'evals/s':>12}  fingerprint")
        for name in ("paper", "recommended"):
            for turns in car_model.names():
                m = model_case(paper_scene(), name, turns, runs, args.repeats)
                report["models"].append(m)
                print(f"{name:<12} {turns:<11} {m['search_median_s']:9.3f} "
                      f"{m['evaluations_per_s']:12,.0f}  {m['fingerprint']}", flush=True)
    report["presets"] = []
    if "presets" in args.only:
        runs = 100 if args.quick else 1000
        print(f"\nrecommended against paper, the same {50 * 51:,} evaluations per run, {runs:,} "
              f"runs; search: median of {args.repeats}, timed alternately", flush=True)
        print(f"{'scene':<18} {'n':>3} {'paper s':>9} {'recommended s':>14} {'ratio':>7}")
        for sc in [paper_scene()] + [clutter_scene(n) for n in ((25,) if args.quick else (25, 40))]:
            c = presets_case(sc, runs, args.repeats)
            report["presets"].append(c)
            print(f"{c['scenario']:<18} {c['n']:>3} {c['paper_s']:9.3f} {c['recommended_s']:14.3f} "
                  f"{c['ratio']:7.2f}", flush=True)
    report["parts"] = []
    if "parts" in args.only:
        runs = 100 if args.quick else 1000
        print(f"\nwhere the recommended preset's time goes: its search with one addition off, "
              f"the same {50 * 51:,} evaluations per run, {runs:,} runs; median of "
              f"{args.repeats}, timed alternately; in units of the paper's search", flush=True)
        names = ["recommended"] + [f"without {name}" for name, _ in PARTS] + ["without all four"]
        print(f"{'scene':<18} {'n':>3} {'paper s':>8} " + " ".join(f"{k:>{max(len(k), 6)}}" for k in names))
        for sc in [paper_scene()] + [clutter_scene(n) for n in ((25,) if args.quick else (25, 40))]:
            c = parts_case(sc, runs, args.repeats)
            report["parts"].append(c)
            print(f"{c['scenario']:<18} {c['n']:>3} {c['median_s']['paper']:8.3f} " + " ".join(
                f"{c['over_paper'][k]:>{max(len(k), 6)}.2f}" for k in names), flush=True)
    report["memory"] = []
    if "memory" in args.only:
        counts = list(args.memory_runs) + ([MILLION] if args.million else [])
        print("\npeak memory (each in a fresh process, float32)", flush=True)
        for runs in counts:
            m = memory_case(runs)
            m["within_limit"] = m["peak_rss_mb"] <= MEMORY_LIMIT_MB
            report["memory"].append(m)
            print_memory(m)
    report["deap"] = report["ratio"] = None
    if "deap" in args.only:
        report["deap"] = deap = deap_case(args.deap_runs)
        if deap is None:
            print("\nDEAP: not installed (pip install deap), skipped")
        else:
            print(f"\nDEAP (same GA, pure-Python decoder) on robocup_paper: "
                  f"{deap['median_per_run_s'] * 1e3:.1f} ms per run (median of {deap['runs']}); "
                  f"calibration {deap['calibration_s']:.4f} s", flush=True)
            report["ratio"] = r = ratio(cases, deap)
            if r is not None:
                print(f"hga-jax: {r['hga_jax_per_run_s'] * 1e3:.3f} ms per run (search, "
                      f"R = {r['hga_jax_runs']:,}, float32, {jax.local_device_count()} CPU "
                      f"device(s); DEAP on one core): DEAP takes "
                      f"{r['deap_over_hga_jax']:,.0f}x as long per run")
    report["calibration_end_s"] = calibration()
    print(f"\ncalibration at the end: {report['calibration_end_s']:.4f} s")
    write_json(args.out, report)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
