"""Benchmarks, run on demand and alone: ``python3 -m pytest -m benchmark -n 0 -s``.

They print measured figures (with a calibration loop beside them). Speed depends on
the machine of the day, so they assert that the scripts ran and that their figures
hang together, not how fast they are.
"""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.benchmark
ROOT = Path(__file__).resolve().parents[1]


def _run(script, *args):
    env = dict(os.environ, PYTHONPATH=str(ROOT))  # this checkout's hga_jax
    proc = subprocess.run([sys.executable, script, *args], capture_output=True, text=True,
                          cwd=ROOT, env=env)
    print(proc.stdout)
    assert proc.returncode == 0, proc.stderr
    assert "calibration" in proc.stdout
    return proc


def test_benchmark_quick(tmp_path):
    out = tmp_path / "benchmark.json"
    _run("experiments/benchmark.py", "--quick", "--out", str(out))
    report = json.loads(out.read_text())
    cases = report["cases"]
    assert {(c["scenario"], c["runs"], c["precision"]) for c in cases} == {
        ("robocup_paper", r, p) for r in (1, 100) for p in ("float32", "float64")} | {
        ("clutter_n025_000", 100, p) for p in ("float32", "float64")}
    for c in cases:
        assert c["evaluations"] == c["runs"] * 50 * 51
        assert c["search_median_s"] > 0 and c["calibration_s"] > 0 and c["compile_s"] >= 0
        assert c["evaluations_per_s"] == pytest.approx(c["evaluations"] / c["search_median_s"])
        assert c["runs_per_s"] == pytest.approx(c["runs"] / c["search_median_s"])
    assert {c["n"] for c in cases} == {9, 25}
    (mem,) = report["memory"]
    assert mem["runs"] == 1000 and 0 < mem["rss_before_runs_mb"] <= mem["peak_rss_mb"] < 4096
    assert mem["within_limit"] and 0 < mem["hit_rate"] < 0.2  # about 4% on this scene
    if report["deap"] is not None:  # deap installed
        assert len(report["deap"]["per_run_s"]) == 2
        r = report["ratio"]
        assert r["hga_jax_runs"] == 100
        assert r["deap_over_hga_jax"] == pytest.approx(r["deap_per_run_s"] / r["hga_jax_per_run_s"])


def _quick_part(tmp_path, part):
    """``benchmark.py --quick --only part``: its output and its cases (n = 9 and 25)."""
    out = tmp_path / "benchmark.json"
    proc = _run("experiments/benchmark.py", "--quick", "--only", part, "--out", str(out))
    cases = json.loads(out.read_text())[part]
    assert [c["n"] for c in cases] == [9, 25]
    return proc, cases


def test_benchmark_presets_ratio(tmp_path):
    """Prints the recommended preset's search time over the paper's, the same evaluations."""
    proc, cases = _quick_part(tmp_path, "presets")
    for c in cases:
        assert c["evaluations"] == c["runs"] * 50 * 51
        assert c["ratio"] == pytest.approx(c["recommended_s"] / c["paper_s"])
        print(f"n = {c['n']}: recommended / paper search time {c['ratio']:.2f}")
    assert "ratio" in proc.stdout


def test_benchmark_parts(tmp_path):
    """Prints where the recommended preset's search time goes: each of its additions off."""
    proc, cases = _quick_part(tmp_path, "parts")
    for c in cases:
        assert set(c["median_s"]) == {"paper", "recommended", "without guided move",
                                      "without seeding", "without restarts", "without islands",
                                      "without all four"}
        for name, t in c["median_s"].items():
            assert c["over_paper"][name] == pytest.approx(t / c["median_s"]["paper"])
        print(f"n = {c['n']}: " + ", ".join(f"{k} {v:.2f}" for k, v in c["over_paper"].items()))
    assert "without guided move" in proc.stdout


def test_benchmark_exact():
    _run("experiments/bench_exact.py", "--scenes", "8", "--repeats", "5")


def test_benchmark_free_turns():
    proc = _run("experiments/bench_free_turns.py", "--quick")
    rows = [line.split() for line in proc.stdout.splitlines() if line.strip().startswith("9 ")]
    assert [r[1] for r in rows] == ["paper", "recommended"]
    for r in rows:  # the ratio is tight / free as printed
        assert float(r[4]) == pytest.approx(float(r[2]) / float(r[3]), rel=0.02, abs=0.02)
