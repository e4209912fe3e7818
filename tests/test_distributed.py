"""One job over several processes (JAX's multi-process runtime, on the loopback
address) writes the result of one process."""
import json
import os
import socket
import subprocess
import sys
import time

import pytest

from hga_jax.running.distributed import share

ROBOCUP = "configs/scenarios/robocup_paper.toml"
# 25 runs from run 3: uneven shares over two processes (runs 3..15 and 16..27);
# batches of 6 runs, so the single process and both shares compile the same shapes
# (process 0 finds the single process's programs on disk; JAX writes and reads
# them from process 0 only).
JOB = [ROBOCUP, "--preset", "paper", "--runs", "25", "--first-run", "3", "--seed", "4", "--generations", "5",
       "--population", "12", "--chunk", "6", "--json", "--quiet"]
TIMINGS = {("summary", "compile_s"), ("summary", "search_s"), ("summary", "evaluations_per_s"),
           ("optimum", "seconds"), ("summary", "devices")}
LIMIT_S = 480  # a job on the loaded 2-core machine takes well under a minute


def _gloo_missing() -> bool:
    try:
        from jax._src.lib import _jax
    except ImportError:
        return True
    return not hasattr(_jax, "make_gloo_tcp_collectives")


needs_runtime = pytest.mark.skipif(
    _gloo_missing(), reason="this jaxlib has no Gloo CPU collectives (JAX's multi-process "
    "runtime on the CPU)")


def _env(tmp_path) -> dict:
    env = {k: v for k, v in os.environ.items() if "proxy" not in k.lower()}  # loopback direct
    return {**env, "JAX_PLATFORMS": "cpu", "HGA_JAX_CACHE_DIR": str(tmp_path / "cache")}


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _processes(argvs: list[list[str]], env: dict) -> list[tuple[int, str, str]]:
    """Run ``hga-jax run`` once per argv, all at once; (status, stdout, stderr) of each.
    Every process still running at the deadline, or when anything fails, is killed."""
    procs = []
    try:
        for argv in argvs:
            procs.append(subprocess.Popen([sys.executable, "-m", "hga_jax", "run", *argv], env=env,
                                          stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                          text=True))
        deadline = time.monotonic() + LIMIT_S
        outs = []
        for p in procs:
            out, err = p.communicate(timeout=max(1.0, deadline - time.monotonic()))
            outs.append((p.returncode, out, err))
        return outs
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.wait()


def _pair(argv: list[str], port: int) -> list[list[str]]:
    return [argv + ["--coordinator", f"127.0.0.1:{port}", "--num-processes", "2",
                    "--process-id", str(i)] for i in range(2)]


def _without_timings(doc: dict) -> dict:
    doc = json.loads(json.dumps(doc))
    for part, key in TIMINGS:
        assert key in doc[part]
        doc[part].pop(key)
    return doc


def test_shares_take_every_run_once_in_order():
    for runs in (1, 2, 3, 7, 24, 25, 1000):
        for count in (1, 2, 3, 5, 8):
            shares = [share(10, runs, p, count) for p in range(count)]
            ids = [k for first, size in shares for k in range(first, first + size)]
            assert ids == list(range(10, 10 + runs)), (runs, count)
            sizes = [size for _, size in shares]
            assert sizes == sorted(sizes, reverse=True) and sizes[0] - sizes[-1] <= 1
    assert [share(3, 25, p, 2) for p in range(2)] == [(3, 13), (16, 12)]
    assert [share(0, 2, p, 3) for p in range(3)] == [(0, 1), (1, 1), (2, 0)]  # one idle


@pytest.mark.slow  # three processes, each compiling: about 20 s
@needs_runtime
def test_two_processes_write_the_result_of_one(tmp_path):
    env = _env(tmp_path)
    ((status, out, err),) = _processes([JOB + ["--out", str(tmp_path / "one")]], env)
    assert status == 0, err
    single = json.loads(out)
    (s0, out0, err0), (s1, out1, err1) = _processes(
        _pair(JOB + ["--out", str(tmp_path / "two")], _free_port()), env)
    assert (s0, s1) == (0, 0), err0 + err1
    assert out1 == "" and sorted(os.listdir(tmp_path / "two")) == ["history.csv", "result.json"]
    pair = json.loads(out0)  # process 0's standard output: one JSON object, nothing else

    one = json.loads((tmp_path / "one" / "result.json").read_text())
    two = json.loads((tmp_path / "two" / "result.json").read_text())
    assert [r["run"] for r in two["per_run"]] == list(range(3, 28)) and two["runs"] == [3, 27]
    # The runs are real and differ from each other, so a share out of place shows.
    lengths = [r["length"] for r in one["per_run"]]
    assert len(set(lengths)) > 10 and len({tuple(r["upper"]) for r in one["per_run"]}) > 10
    assert _without_timings(two) == _without_timings(one)
    assert two["summary"]["evaluations"] == 25 * 12 * 6
    assert ((tmp_path / "two" / "history.csv").read_bytes()
            == (tmp_path / "one" / "history.csv").read_bytes())
    assert pair["summary"]["best_length"] == single["summary"]["best_length"] == one["best"]["length"]
    assert pair["summary"]["hit_rate"] == single["summary"]["hit_rate"]


@needs_runtime
def test_bad_input_found_by_one_process_stops_both_with_one_line(tmp_path):
    out = tmp_path / "taken"
    out.mkdir()
    (out / "result.json").write_text("{}")  # only process 0 writes, so only it checks
    runs = _processes(_pair([ROBOCUP, "--runs", "4", "--generations", "1", "--quiet",
                             "--out", str(out)], _free_port()), _env(tmp_path))
    line = f"hga-jax: error: {out}: output folder: already holds a result (result.json); "
    for status, stdout, stderr in runs:
        assert status == 2 and stdout == ""
        assert stderr.count("\n") == 1 and stderr.startswith(line), stderr
    assert (out / "result.json").read_text() == "{}"


def test_process_coordinates_that_cannot_work_are_one_line(tmp_path):
    env = _env(tmp_path)
    for name in [k for k in env if k.startswith(("SLURM_", "OMPI_", "PMI_", "JAX_COORD"))]:
        env.pop(name)  # nothing to detect the job from
    runs = _processes([[ROBOCUP, "--distributed", "--quiet"],
                       [ROBOCUP, "--num-processes", "2", "--process-id", "2", "--quiet"]], env)
    assert [(status, stdout) for status, stdout, _ in runs] == [(2, ""), (2, "")]
    assert runs[0][2].startswith("hga-jax: error: command line: --coordinator, --num-processes, "
                                 "--process-id: not given, and no cluster environment (SLURM, "
                                 "Open MPI) to read them from (")
    assert runs[1][2] == ("hga-jax: error: command line: --process-id: must be in 0..1 (with 2 "
                          "processes), got 2\n")
    assert all(stderr.count("\n") == 1 for _, _, stderr in runs)
