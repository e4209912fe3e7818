"""Study machinery without GA runs: study files, statistics, scene families."""
import json
import math
import os

import numpy as np
import pytest
from scipy import stats as sps

from hga_jax.host.cli import main
from hga_jax.host.config import load_scenario
from hga_jax.errors import ConfigError
from hga_jax.model.exact import solve
from hga_jax.model.path import evaluate_path
from hga_jax.study import load_study, stats
from hga_jax.study.config import Family
from hga_jax.study.scenes import MODEL_RADIUS, family_scenes, field_size, generate, to_toml

GOOD = """name = "s"
runs = 10
scenarios = ["{scene}"]
[[configs]]
label = "paper"
[[configs]]
perm_crossover = ["pmx", "ox1"]
elites = [0, 1]
"""
ROBOCUP = "configs/scenarios/robocup_paper.toml"


def _write(tmp_path, text):
    p = tmp_path / "study.toml"
    p.write_text(text.replace("{scene}", os.path.abspath(ROBOCUP)))
    return str(p)


def test_grid_expands_products_labels_and_drops_duplicates(tmp_path):
    s = load_study(_write(tmp_path, GOOD + '[[configs]]\nlabel = "again"\nelites = 0\n'))
    assert [c.label for c in s.configs] == [
        "paper", "perm_crossover=pmx, elites=0", "perm_crossover=pmx, elites=1",
        "perm_crossover=ox1, elites=0", "perm_crossover=ox1, elites=1"]
    assert s.configs[2].settings.perm_crossover == "pmx" and s.configs[2].settings.elites == 1
    assert s.runs == 10 and s.seed == 0 and not s.quick


def test_quick_table_overrides(tmp_path):
    text = GOOD + "[quick]\nruns = 3\nga = { generations = 4 }\nconfigs = [{ label = \"q\" }]\n"
    s = load_study(_write(tmp_path, text), quick=True)
    assert s.runs == 3 and [c.label for c in s.configs] == ["q"]
    assert s.configs[0].settings.generations == 4 and s.quick


BAD = {
    "unknown top key": (GOOD.replace("runs = 10", "runs = 10\ncolour = 1"), "colour"),
    "runs zero": (GOOD.replace("runs = 10", "runs = 0"), "runs"),
    "no name": (GOOD.replace('name = "s"\n', ""), "name"),
    "bad ga value": (GOOD + "[ga]\npc_upper = 2.0\n", "ga.pc_upper"),
    "unknown operator": (GOOD.replace('"pmx", "ox1"', '"pmx", "ox9"'),
                         "configs[2].perm_crossover"),
    "unknown setting in grid": (GOOD + "[[configs]]\npopsize = [1]\n", "configs[3].popsize"),
    "label over many": (GOOD.replace('label = "paper"', 'label = "p"\nelites = [1, 2]'),
                        "configs[1].label"),
    "bad family kind": (GOOD + '[[families]]\nname = "f"\nkind = "maze"\nobstacles = [9]\n',
                        "families[1].kind"),
    "obstructed too few": (GOOD + '[[families]]\nname = "f"\nkind = "obstructed"\n'
                           'obstacles = [2]\n', "families[1].obstacles"),
    "unknown analysis": (GOOD.replace("runs = 10", 'runs = 10\nanalyses = ["fig9"]'),
                         "analyses"),
    "missing plugin": (GOOD.replace("runs = 10", 'runs = 10\nplugins = ["nope.py"]'),
                       "plugins[1]"),
    "toml syntax": ("name = \n", "toml"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_study_files_name_file_and_key(tmp_path, case, capsys):
    text, key = BAD[case]
    path = _write(tmp_path, text)
    with pytest.raises(ConfigError) as err:
        load_study(path)
    assert str(err.value).startswith(f"{path}: {key}")
    assert main(["study", path, "--out", str(tmp_path / "out")]) == 2
    printed = capsys.readouterr().err
    assert printed.count("\n") == 1 and printed.startswith(f"hga-jax: error: {path}: {key}")
    assert not (tmp_path / "out").exists()


def test_wilson_interval_matches_the_formula():
    lo, hi = stats.wilson(3, 100)
    z = sps.norm.ppf(0.975)
    p, n = 0.03, 100
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    assert (lo, hi) == pytest.approx((centre - half, centre + half), rel=1e-9)
    assert stats.wilson(0, 40) == pytest.approx((0.0, 0.0876), abs=1e-4)


def test_holm_step_down():
    adj = stats.holm([0.01, 0.04, 0.03, float("nan"), 0.5])
    assert adj[:3] == pytest.approx([0.04, 0.09, 0.09])
    assert math.isnan(adj[3]) and adj[4] == 0.5
    assert list(stats.holm([0.9, 0.6])) == [1.0, 1.0]


def test_ert_and_ecdf():
    inf = math.inf
    # Two of four runs reach the target after 100 and 300 evaluations; the others spend 1000.
    assert stats.ert([100, inf, 300, inf], [1000] * 4) == pytest.approx((100 + 300 + 2000) / 2)
    assert stats.ert([inf, inf], [10, 10]) == inf
    assert list(stats.ecdf([100, inf, 300, 50], np.array([0, 50, 299, 300, 1e9]))) == [
        0, 0.25, 0.5, 0.75, 0.75]


def test_median_interval_and_tests():
    rng = np.random.default_rng(0)
    x = rng.exponential(0.05, 500)
    med, lo, hi = stats.median_ci(x)
    assert med == np.median(x) and lo < med < hi and hi - lo < 0.02
    # with infinite (infeasible) values the median still has an interval
    med, lo, hi = stats.median_ci(np.concatenate([x, np.full(100, np.inf)]))
    assert np.isfinite(med) and lo <= med <= hi
    y = x + 0.01
    assert stats.mann_whitney(x, y) == pytest.approx(
        sps.mannwhitneyu(x, y, alternative="two-sided").pvalue)
    assert stats.mann_whitney(np.zeros(5), np.zeros(7)) == 1.0
    assert stats.fisher(30, 100, 10, 100) == pytest.approx(
        sps.fisher_exact([[30, 70], [10, 90]]).pvalue)


def test_obstructed_scenes_block_the_direct_paths(tmp_path):
    scenes = family_scenes(Family("ob", "obstructed", (9,), 3, 5), str(tmp_path))
    assert len({s.text for s in scenes}) == 3
    for s in scenes:
        sc = load_scenario(s.path)  # the file is a scenario hga-jax run accepts
        assert sc.n == 9 and sc.field.keep_inside
        c = sc.centres
        dist = np.hypot(*(c[:, None] - c[None]).transpose(2, 0, 1))
        assert np.min(dist[~np.eye(9, dtype=bool)]) >= 0.3
        a, b = np.array(sc.start[:2]), np.array(sc.goal[:2])
        ts = np.linspace(0, 1, 2001)[:, None]
        line = a + ts * (b - a)
        assert np.min(np.hypot(*(line[:, None] - c[None]).transpose(2, 0, 1))) < MODEL_RADIUS
        for ls in (-1, 1):
            for lg in (-1, 1):
                direct = evaluate_path(sc, np.arange(9), [ls] + [0] * 9 + [lg])
                assert direct.violations > 0
        opt = solve(sc)
        assert opt.feasible and opt.expressible and len(opt.touched) >= 3
    assert main(["check", scenes[0].path]) == 0
    again = family_scenes(Family("ob", "obstructed", (9,), 3, 5), str(tmp_path / "again"))
    assert [s.text for s in again] == [s.text for s in scenes]  # seeded


def test_clutter_density_sets_the_field():
    assert field_size(9, None) == (2.8, 2.3)
    w, h = field_size(100, 1.4)
    assert w * h == pytest.approx(100 / 1.4) and w / h == pytest.approx(2.8 / 2.3)
    d = generate("clutter", 30, 3, 0, "c30", density=1.4)
    assert len(d["obstacles"]) == 30
    assert d["field"]["xmax"] == pytest.approx(field_size(30, 1.4)[0], abs=1e-4)
    text = to_toml(d, "a comment")
    assert text.startswith("# a comment\nname = \"c30\"")


def _cell(config, gaps, population=10):
    """A cell document as the store writes it (only what the table reads)."""
    n = len(gaps)
    hit = [g is not None and g < 1e-6 for g in gaps]
    return {"config": config, "family": "f", "scenario": "s0", "obstacles": 3, "seed": 7,
            "runs": n, "settings": {"population": population, "perm_crossover": "cx"},
            "optimum": 2.5, "evaluations_per_run": 6 * population, "search_s": 0.5 * n,
            "columns": {"run": list(range(n)), "length": [2.5 * (1.5 if g is None else 1 + g) for g in gaps],
                        "feasible": [g is not None for g in gaps], "gap": gaps, "hit": hit,
                        "evaluations_hit": [3 * population if h else None for h in hit]}}


def test_run_table_files_keep_values_and_missing_ones(tmp_path):
    import pandas as pd

    from hga_jax.study import table

    tab = table.build("t", [_cell("a", [0.0, 0.1, None]), _cell("b", [0.25, 0.0, 0.0])])
    assert list(tab.columns) == ["study", "config", "solver", "family", "group", "scenario",
                                 "obstacles", "seed", "run", "population", "perm_crossover", "length",
                                 "feasible", "gap", "hit", "evaluations_hit", "optimum",
                                 "evaluations", "time_s", "compile_s"]
    assert len(tab) == 6
    assert table.numeric(tab, "gap").tolist() == [0.0, 0.1, math.inf, 0.25, 0.0, 0.0]
    assert table.numeric(tab, "evaluations_hit").tolist() == [30, math.inf, math.inf, math.inf,
                                                              30, 30]
    table.write_csv(str(tmp_path / "runs.csv"), tab)
    lines = (tmp_path / "runs.csv").read_text().splitlines()
    assert lines[1] == "t,a,hga,f,f,s0,3,7,0,10,cx,2.5,True,0.0,True,30,2.5,60,0.5,0.0"
    assert lines[3] == "t,a,hga,f,f,s0,3,7,2,10,cx,3.75,False,,False,,2.5,60,0.5,0.0"  # missing
    assert lines[2].split(",")[11] == repr(2.5 * 1.1)  # floats round-trip
    table.write_parquet(str(tmp_path / "runs.parquet"), tab)
    back = pd.read_parquet(tmp_path / "runs.parquet")
    assert list(back.columns) == list(tab.columns)
    assert back["gap"].isna().tolist() == [False, False, True, False, False, False]
    assert back["evaluations_hit"].isna().tolist() == [False, True, True, True, False, False]
    assert str(back["evaluations_hit"].dtype) == "Int64" and back["evaluations_hit"][0] == 30
    assert back["length"].tolist() == tab["length"].tolist()
    table.write_jsonl(str(tmp_path / "runs.jsonl"), tab)
    rows = [json.loads(x) for x in (tmp_path / "runs.jsonl").read_text().splitlines()]
    assert rows[2]["gap"] is None and rows[2]["evaluations_hit"] is None
    assert rows[0]["evaluations_hit"] == 30 and rows[0]["hit"] is True
    md = table.markdown(pd.DataFrame([["x", "1.5%"]], columns=["configuration", "hit rate"]))
    assert md.splitlines()[0] == "| configuration | hit rate |"
    assert md.splitlines()[2] == "| x | 1.5% |"


def test_a_family_that_keeps_no_scene_is_a_one_line_error_naming_the_file(tmp_path, capsys,
                                                                         monkeypatch):
    """A generator that finds no scene in its tries (a crowded field, a keep rule no draw
    meets) stops the study with one line naming the study file and the family, before
    any cell runs; nothing is written to the output folder's cells."""
    from hga_jax.study import run as study_run

    def crowded(fam, folder):
        raise RuntimeError(f"no wall scene with {fam.obstacles[0]} obstacles found in 400 tries")

    monkeypatch.setattr(study_run, "family_scenes", crowded)
    path = tmp_path / "s.toml"
    path.write_text('name = "s"\nseed = 0\nruns = 2\n[[families]]\nname = "w"\nkind = "wall"\n'
                    'obstacles = [60]\nscenes = 1\nseed = 1\ncar = "dubins"\n'
                    '[[configs]]\nlabel = "paper"\n')
    out = tmp_path / "out"
    assert main(["study", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(path) in err[0] and "families[1] ('w')" in err[0]
    assert "400 tries" in err[0]
    assert not (out / "cells").exists() or not os.listdir(out / "cells")
