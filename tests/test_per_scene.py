"""The study analysis ``per_scene`` on a table whose answers are counted by hand."""
from __future__ import annotations

import csv
import math
from types import SimpleNamespace

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

from hga_jax.study import per_scene as ps
from hga_jax.study.analyses import ANALYSES
from hga_jax.study.config import ANALYSES as NAMES


def _runs(config, scene, hits, feasible, runs, n=9, family="f"):
    """``runs`` rows of one cell: the first ``hits`` hit, the first ``feasible`` are
    feasible (gap 0 or 0.01), the rest infeasible (no gap)."""
    gap = [0.0] * hits + [0.01] * (feasible - hits) + [math.nan] * (runs - feasible)
    return pd.DataFrame({"config": config, "family": family, "obstacles": n,
                         "scenario": scene, "hit": [i < hits for i in range(runs)],
                         "gap": gap, "evaluations": 2550, "time_s": 0.002, "optimum": 1.0})


def _study(*labels):
    return SimpleNamespace(configs=[SimpleNamespace(label=c) for c in labels])


def _table():
    # scenes a, b, c, d, e at 9 obstacles, 100 runs each
    rec = [("a", 100, 100), ("b", 95, 100), ("c", 40, 90), ("d", 100, 100), ("e", 99, 100)]
    pap = [("a", 30, 60), ("b", 96, 100), ("c", 90, 100), ("d", 50, 100), ("e", 99, 99)]
    parts = [_runs("rec", s, h, f, 100) for s, h, f in rec]
    parts += [_runs("paper", s, h, f, 100) for s, h, f in pap]
    return pd.concat(parts, ignore_index=True)


def test_per_scene_counts_worst_scene_paired_tests_and_targets(tmp_path):
    files = ps.per_scene(_study("rec", "paper"), _table(), [], None, str(tmp_path), draw=False)
    assert {p.rsplit("/", 1)[-1] for p in files} == {"per_scene.csv", "per_scene_rates.csv",
                                                     "per_scene.md"}
    rows = {r["config"]: r for r in csv.DictReader(open(tmp_path / "per_scene.csv"))}
    rec, pap = rows["rec"], rows["paper"]
    assert float(rec["hit_rate"]) == pytest.approx(434 / 500)
    assert rec["worst_scene"] == "c" and float(rec["worst_scene_hit_rate"]) == 0.40
    # scene rates 1.0, 0.95, 0.40, 1.0, 0.99: the 10th percentile (lower) is the least
    assert float(rec["scene_hit_rate_p10"]) == 0.40
    assert float(rec["scene_hit_rate_median"]) == 0.99
    assert int(rec["scenes_below_floor"]) == 1  # c, under 90 %
    assert float(rec["feasible_rate"]) == pytest.approx(490 / 500)
    assert float(rec["worst_scene_feasible_rate"]) == 0.90
    assert rec["meets_targets"] == "False"
    # paired: rec is lower only on c (40 against 90 of 100), which survives Holm over 5
    p_c = sps.fisher_exact([[40, 60], [90, 10]]).pvalue
    assert p_c * 5 < 0.05
    assert int(pap["scenes_reference_lower"]) == 1
    assert float(pap["reference_largest_shortfall"]) == pytest.approx(0.50)
    assert float(pap["worst_scene_hit_rate"]) == 0.30 and pap["worst_scene"] == "a"
    assert float(pap["feasible_rate"]) == pytest.approx(459 / 500)
    per = list(csv.DictReader(open(tmp_path / "per_scene_rates.csv")))
    c = [r for r in per if r["config"] == "paper" and r["scenario"] == "c"][0]
    assert float(c["reference_hit_rate"]) == 0.40 and float(c["hit_rate"]) == 0.90
    assert float(c["p_fisher"]) == pytest.approx(p_c)
    text = (tmp_path / "per_scene.md").read_text()
    assert "40.0 % (c)" in text and "not met" in text


def test_a_row_meets_its_targets_only_when_every_scene_clears_the_floor(tmp_path):
    good = pd.concat([_runs("rec", s, 100, 100, 1000, n=25) for s in "abcd"]
                     + [_runs("rec", "e", 905, 1000, 1000, n=25)], ignore_index=True)
    ps.per_scene(_study("rec"), good, [], None, str(tmp_path), draw=False)
    row = next(csv.DictReader(open(tmp_path / "per_scene.csv")))
    # 4 x 100 + 905 hits of 4 x 100 + 1000 runs: 93.2 %, under 99 %
    assert row["meets_targets"] == "False"
    better = pd.concat([_runs("rec", s, 1000, 1000, 1000, n=25) for s in "abcdefghi"]
                       + [_runs("rec", "j", 905, 1000, 1000, n=25)], ignore_index=True)
    ps.per_scene(_study("rec"), better, [], None, str(tmp_path), draw=False)
    row = next(csv.DictReader(open(tmp_path / "per_scene.csv")))
    assert float(row["hit_rate"]) == pytest.approx(9905 / 10000)
    assert row["meets_targets"] == "True"  # 99.05 %, worst 90.5 %, all feasible
    assert ps.target(9) == (0.995, 0.90, 0.999) and ps.target(15) == ps.target(25)
    assert ps.target(40) == (0.97, 0.75, 0.99) and ps.target(41) is None


def test_per_scene_is_a_named_analysis():
    assert "per_scene" in NAMES and ANALYSES["per_scene"] is ps.per_scene
    assert set(NAMES) == set(ANALYSES)
    assert np.isfinite(ps.ALPHA)


def test_a_scene_without_a_feasible_optimum_is_counted_apart_not_as_a_miss(tmp_path):
    """A scene whose optimum is inf (no feasible path exists) is left out of the hit
    rate, the worst scene, the feasible share and the time per run, and counted in its
    own column; a row
    all of whose scenes lack a path has no rates."""
    none = _runs("rec", "x", 0, 0, 100).assign(optimum=math.inf, time_s=1.0)
    table = pd.concat([_runs("rec", "a", 100, 100, 100), _runs("rec", "b", 97, 100, 100),
                       none, _runs("rec", "y", 0, 0, 50, n=15).assign(optimum=math.inf)],
                      ignore_index=True)
    ps.per_scene(_study("rec"), table, [], None, str(tmp_path), draw=False)
    rows = {int(r["obstacles"]): r for r in csv.DictReader(open(tmp_path / "per_scene.csv"))}
    nine, fifteen = rows[9], rows[15]
    assert int(nine["scenes"]) == 2 and int(nine["runs"]) == 200
    assert float(nine["hit_rate"]) == pytest.approx(197 / 200)
    assert nine["worst_scene"] == "b" and float(nine["feasible_rate"]) == 1.0
    assert int(nine["scenes_without_path"]) == 1
    assert float(nine["ga_ms_per_run"]) == pytest.approx(2.0)  # its runs' time left out
    assert int(fifteen["scenes"]) == 0 and int(fifteen["scenes_without_path"]) == 1
    assert math.isnan(float(fifteen["hit_rate"]))
    text = (tmp_path / "per_scene.md").read_text()
    assert "scenes without a path (left out)" in text and "97.0 % (b)" in text
