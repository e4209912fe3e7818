"""experiments/budget_curve.py: hit rate and feasible share against evaluations, read
off the runs' first hits and their best-so-far histories."""
import importlib.util
import os

import numpy as np

import hga_jax as hg
from hga_jax.host.config import load_scenario


def _script():
    spec = importlib.util.spec_from_file_location(
        "budget_curve", os.path.join("experiments", "budget_curve.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_curve_at_the_presets_budget_is_the_presets_runs():
    """With the preset's own generations (``times = 1``) the runs are the preset's, so
    the curve's last point is their hit rate and their feasible share (the latter read
    from the float32 histories, the run's figure from the float64 re-evaluation); earlier
    points count the runs hit by then, and never fall."""
    sc = load_scenario("configs/scenarios/overlapping.toml")
    rows = _script().curve(sc, "paper", 1, 48, 5)
    res = hg.run_many(sc, "paper", seed=5, runs=48)
    assert 0 < res.hit.mean() < 1 and 0 < res.feasible.mean() < 1  # the check can fail
    last = rows[-1]
    assert last["multiple"] == 1 and last["evaluations"] == 50 * 51
    assert last["hit_rate"] == res.hit.mean()
    assert last["feasible"] == res.feasible.mean()
    for r in rows:
        g = r["evaluations"] // 50 - 1
        assert r["hit_rate"] == np.mean(res.hit & (res.generation <= g))
    assert [r["multiple"] for r in rows] == [0.25, 0.5, 1]
    assert np.all(np.diff([r["hit_rate"] for r in rows]) >= 0)
