"""The gap to the exact optimum in every result (1000 runs of the paper's GA)."""
import numpy as np
import pytest

from hga_jax.host.config import load_scenario
from hga_jax.model.exact import solve
from hga_jax.running.results import HIT_GAP
from hga_jax.running.runner import run_many


@pytest.fixture(scope="module")
def batch():
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    return sc, run_many(sc, "paper", seed=0, runs=1000)


def test_no_run_beats_the_optimum(batch):
    sc, res = batch
    opt = solve(sc)
    assert res.optimum_length == opt.length
    feasible = res.length[res.feasible]
    assert len(feasible) > 500
    assert np.all(feasible >= opt.length * (1 - 1e-9))
    assert res.summary()["shorter_than_optimum"] == 0


def test_hits_and_gaps_are_consistent(batch):
    _, res = batch
    opt = res.optimum_length
    hit = res.hit
    assert 0 < hit.sum() < len(hit)  # the default scene is hard for the paper's GA
    assert np.allclose(res.length[hit], opt, rtol=1e-9, atol=0)
    assert np.all(res.gap[res.feasible & ~hit] >= HIT_GAP)
    assert np.all(np.isinf(res.gap[~res.feasible]))
    s = res.summary()
    gap = res.length[res.feasible] / opt - 1
    assert s["hit_rate"] == pytest.approx(hit.mean())
    assert s["gap_median"] == pytest.approx(np.median(gap))
    assert s["gap_max"] == pytest.approx(gap.max())
    assert s["infeasible_runs"] == int((~res.feasible).sum())


def test_generations_to_within_one_percent_and_to_the_hit(batch):
    _, res = batch
    near = res.first_generation_within(0.01)
    hit_gen = res.generation_hit
    assert np.all(hit_gen[res.hit] == res.generation[res.hit])
    assert np.all(hit_gen[~res.hit] == -1)
    assert np.all((near[res.hit] >= 0) & (near[res.hit] <= hit_gen[res.hit]))
    # A run within 1% at the end was within 1% at some generation, and vice versa.
    final_near = res.feasible & (res.gap <= 0.01)
    assert np.array_equal(near >= 0, final_near)
    rows = res.history_rows()
    frac = [r["within_1pct_fraction"] for r in rows]
    assert np.all(np.diff(frac) >= 0) and frac[-1] == pytest.approx(final_near.mean())
    assert rows[-1]["hit_fraction"] == pytest.approx(res.hit.mean())


def test_result_file_carries_the_gap(batch):
    _, res = batch
    data = res.to_dict()
    assert data["optimum"]["length"] == res.optimum_length
    runs = data["per_run"]
    assert [r["hit"] for r in runs] == res.hit.tolist()
    gaps = [r["gap"] for r in runs]
    assert all((g is None) == (not r["feasible"]) for g, r in zip(gaps, runs))
