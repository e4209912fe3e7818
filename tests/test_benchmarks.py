"""Benchmarks, run on demand: ``python3 -m pytest -m benchmark -s``.

They print measured figures (with a calibration loop beside them); they assert
only that the scripts ran, since speed depends on the machine of the day.
"""
import subprocess
import sys

import pytest

pytestmark = pytest.mark.benchmark


@pytest.mark.parametrize("script,args", [
    ("experiments/bench_run.py", ["--runs", "1000", "10000", "--repeats", "3"]),
    ("experiments/bench_exact.py", ["--scenes", "8", "--repeats", "5"]),
])
def test_benchmark(script, args):
    proc = subprocess.run([sys.executable, script, *args], capture_output=True, text=True)
    print(proc.stdout)
    assert proc.returncode == 0, proc.stderr
    assert "calibration" in proc.stdout
