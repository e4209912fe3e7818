"""What a user waits for at the command line: wall time of each command, cold and warm.

Times, in fresh processes (median of ``--repeats``): ``hga-jax --help``, ``run
--help``, ``check`` on the bundled scene and an input error (a missing file); then
``exact`` on the bundled scene and a one-run ``hga-jax run``, each cold (an empty
folder of compiled programs) and warm (the same command again, the folder filled by
the cold one; median of ``--repeats``), with the compile time each run reports. A fixed pure-Python loop is timed beside them
(calibration: the machine is shared).

Usage: ``python3 experiments/bench_cli.py [--repeats 3] [--out results/bench_cli.json]``
"""
from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENE = os.path.join("configs", "scenarios", "robocup_paper.toml")
sys.path.insert(0, HERE)
from calibration import calibration  # noqa: E402  (beside this file)


def _timed(args: list[str], env: dict[str, str]) -> tuple[float, str]:
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "hga_jax.host.cli", *args], cwd=ROOT,
                          env=env, capture_output=True, text=True)
    return time.perf_counter() - t0, proc.stdout + proc.stderr


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--out", default=os.path.join("results", "bench_cli.json"))
    args = p.parse_args(argv)
    cal = calibration()
    work = tempfile.mkdtemp(prefix="bench_cli_")
    env = dict(os.environ, HGA_JAX_CACHE_DIR=os.path.join(work, "programs"),
               PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    quick = {"help": ["--help"], "run --help": ["run", "--help"],
             "check": ["check", SCENE], "input error": ["run", os.path.join(work, "none.toml")]}
    report: dict[str, object] = {"calibration_s": cal}
    for name, cmd in quick.items():
        times = [_timed(cmd, env)[0] for _ in range(args.repeats)]
        report[name] = statistics.median(times)
        print(f"{name:12s} {statistics.median(times):6.2f} s (median of {args.repeats})")
    exact = ["exact", SCENE, "--out", os.path.join(work, "exact"), "--force"]
    cold = _timed(exact, env)[0]
    warm = statistics.median(_timed(exact, env)[0] for _ in range(args.repeats))
    report["exact cold"], report["exact warm"] = cold, warm
    print(f"exact, cold: {cold:6.2f} s wall; warm: {warm:6.2f} s (median of {args.repeats})")
    run = ["run", SCENE, "--runs", "1", "--out", os.path.join(work, "run"), "--force", "--quiet"]
    for label, repeats in (("cold", 1), ("warm", args.repeats)):
        walls, compiles = [], []
        for _ in range(repeats):
            wall, out = _timed(run + ["--json"], env)
            walls.append(wall)
            compiles.append(json.loads(out[out.index("{"):])["summary"]["compile_s"])
        wall, compile_s = statistics.median(walls), statistics.median(compiles)
        report[f"run {label}"] = {"wall_s": wall, "compile_s": compile_s}
        print(f"run, {label}: {wall:6.2f} s wall, {compile_s:.2f} s compiling"
              + (f" (median of {repeats})" if repeats > 1 else ""))
    print(f"calibration {cal:.3f} s")
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as fh:
        json.dump(report, fh, indent=1)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
