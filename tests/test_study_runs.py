"""Studies end to end: the --quick studies' outputs checked by value, resuming after a
kill, and an operator registered from outside the package taking part in a study."""
import csv
import importlib.util
import json
import math
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from hga_jax.search import registry
from hga_jax.host.config import load_scenario
from hga_jax.model.exact import solve
from hga_jax.model.path import decode64
from hga_jax.running.runner import run_many
from hga_jax.search.settings import GASettings
from hga_jax.study import run_study, stats

ROBOCUP = os.path.abspath("configs/scenarios/robocup_paper.toml")


def _study(name, *options):
    """``hga-jax study configs/studies/<name>.toml OPTIONS``: its exit status."""
    from hga_jax.host.cli import main

    return main(["study", os.path.join("configs", "studies", name + ".toml"), *options])


def _csv(path):
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))


def _num(v):
    return math.inf if v in ("", "inf") else float(v)


@pytest.fixture(scope="module")
def paper_quick(tmp_path_factory):
    out = tmp_path_factory.mktemp("reproduce")
    assert _study("reproduce_paper", "--quick", "--out", str(out), "--quiet") == 0
    return out


def test_reproduce_paper_quick_table_is_right_run_by_run(paper_quick):
    rows = _csv(paper_quick / "runs.csv")
    scenes = sorted({r["scenario"] for r in rows})
    assert len(rows) == 3 * 40 and len(scenes) == 3
    assert len({(r["config"], r["scenario"], r["run"]) for r in rows}) == len(rows)
    jsonl = [json.loads(line) for line in open(paper_quick / "runs.jsonl")]
    assert [(j["scenario"], j["run"], j["length"]) for j in jsonl] == [
        (r["scenario"], int(r["run"]), float(r["length"])) for r in rows]
    for r in rows:
        opt, length = float(r["optimum"]), float(r["length"])
        assert r["generations"] == "30" and r["population"] == "50"
        if r["feasible"] == "True":
            assert float(r["gap"]) == pytest.approx(length / opt - 1, rel=1e-12, abs=1e-15)
            assert float(r["gap"]) >= -1e-9  # nothing beats the exact optimum
        else:
            assert r["gap"] == "" and r["hit"] == "False"
        assert (r["hit"] == "True") == (r["gap"] != "" and float(r["gap"]) < 1e-6)
        for tag in ("1pct", "5pct", "hit"):
            g = int(r[f"generation_{tag}"])
            assert r[f"evaluations_{tag}"] == ("" if g < 0 else str(50 * (g + 1)))
        assert int(r["generation_5pct"]) <= int(r["generation_1pct"]) or r["generation_1pct"] == "-1"
        assert r["evaluations"] == str(50 * 31)
    # Each scene's optimum is the exact solver's, and its rows are run_many's runs 0..39.
    for scene in scenes:
        mine = [r for r in rows if r["scenario"] == scene]
        path = ROBOCUP if scene == "robocup_paper" else str(paper_quick / "scenes" / f"{scene}.toml")
        sc = load_scenario(path)
        assert float(mine[0]["optimum"]) == solve(sc).length
        res = run_many(sc, GASettings(generations=30), seed=0, runs=40)
        assert [float(r["length"]) for r in mine] == res.length.tolist()
        assert [int(r["generation_best"]) for r in mine] == res.generation.tolist()


def test_reproduce_paper_quick_summary_states_what_was_run(paper_quick):
    text = (paper_quick / "summary.md").read_text()
    assert "Seed 0: run k of every cell is run k of this seed." in text
    assert ("Scenes (3): scene files: robocup_paper (9 obstacles); family obstructed9: "
            "2 with 9 obstacles.") in text
    # the quick budget: population 50, 30 generations, 40 runs per scene
    assert "population 50, 30 generations: 1,550 evaluations" in text
    assert "40 runs per scene" in text


def test_reproduce_paper_quick_summary_and_claims(paper_quick):
    rows = _csv(paper_quick / "runs.csv")
    summary = _csv(paper_quick / "summary.csv")
    # a scene file is a group of its own, named by its scenario
    assert [(s["group"], s["config"]) for s in summary] == [("robocup_paper", "paper"),
                                                             ("obstructed9", "paper")]
    for s in summary:
        mine = [r for r in rows if r["group"] == s["group"]]
        hits = sum(r["hit"] == "True" for r in mine)
        assert int(s["runs"]) == len(mine) and float(s["hit_rate"]) == hits / len(mine)
        lo, hi = stats.wilson(hits, len(mine))
        assert (float(s["hit_rate_ci_low"]), float(s["hit_rate_ci_high"])) == (lo, hi)
        gaps = np.array([_num(r["gap"]) for r in mine])
        assert _num(s["gap_median"]) == np.median(gaps)
        e1 = np.array([_num(r["evaluations_1pct"]) for r in mine])
        reached = np.isfinite(e1)
        ert = (e1[reached].sum() + 1550 * (~reached).sum()) / reached.sum() if reached.any() else math.inf
        assert _num(s["ert_evaluations_1pct"]) == pytest.approx(ert)
        assert s["p_gap_mwu_holm"] in ("", "nan")  # the reference is not tested against itself
    obstructed = [r for r in rows if r["family"] == "obstructed9"]
    assert sum(r["hit"] == "True" for r in obstructed) > 0  # the quick study finds some optima
    claims = (paper_quick / "paper_claims.md").read_text()
    files = [r for r in rows if r["family"] == "files"]
    rate = sum(r["hit"] == "True" for r in files) / len(files)
    assert f"files (1 scenes, 40 runs): {100 * rate:.1f}%" in claims
    assert "| optimum reached by generation | 27 |" in claims
    manifest = json.loads((paper_quick / "study.json").read_text())
    assert manifest["cells"] == manifest["cells_finished"] == 3 and manifest["quick"]
    for png in ("hit_rate", "gap_ecdf", "evaluations_ecdf", "time_ecdf", "convergence",
                "paper_fig4_best_path",
                "paper_fig5_fitness"):
        assert (paper_quick / "figures" / f"{png}.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.slow  # a bundled study's quick run; reproduce_paper's quick run stays in the default lane
def test_operator_study_quick_compares_with_holm(tmp_path):
    assert _study("operator_study", "--quick", "--out", str(tmp_path), "--quiet") == 0
    rows = _csv(tmp_path / "runs.csv")
    summary = _csv(tmp_path / "summary.csv")
    assert {r["config"] for r in rows} == {"paper", "pmx + elitism 1"}
    assert {(r["perm_crossover"], r["elites"]) for r in rows} == {("cx", "0"), ("pmx", "1")}
    raw_mwu, raw_fisher = [], []
    for s in (s for s in summary if s["config"] != "paper"):
        a = [r for r in rows if r["family"] == s["group"] and r["config"] == s["config"]]
        b = [r for r in rows if r["family"] == s["group"] and r["config"] == "paper"]
        ga, gb = ([_num(r["gap"]) for r in x] for x in (a, b))
        ha, hb = (sum(r["hit"] == "True" for r in x) for x in (a, b))
        assert float(s["p_gap_mwu"]) == pytest.approx(stats.mann_whitney(np.array(ga), np.array(gb)))
        assert float(s["p_hit_fisher"]) == pytest.approx(stats.fisher(ha, len(a), hb, len(b)))
        raw_mwu.append(float(s["p_gap_mwu"]))
        raw_fisher.append(float(s["p_hit_fisher"]))
    holm = [float(s["p_gap_mwu_holm"]) for s in summary if s["config"] != "paper"]
    assert holm == pytest.approx(list(stats.holm(raw_mwu)))
    md = (tmp_path / "summary.md").read_text()
    assert "Mann-Whitney U (gap), Holm" in md and "Fisher exact (hits), Holm" in md


@pytest.mark.slow  # a bundled study's quick run (see test_operator_study_quick_compares_with_holm)
def test_penalty_and_collision_quick_counts_accepted_collisions(tmp_path):
    assert _study("penalty_and_collision", "--quick", "--out", str(tmp_path), "--quiet") == 0
    rows = _csv(tmp_path / "runs.csv")
    table = _csv(tmp_path / "penalty.csv")
    paper_rows = [r for r in rows if r["collision"] == "paper"]
    assert len(paper_rows) == 2 * 40
    # violations_full is the full test of the very path the paper-criterion run returned
    sc = load_scenario(ROBOCUP)
    res = run_many(sc, GASettings(generations=30, collision="paper"), seed=0, runs=40)
    full = decode64(sc, res.perm, res.labels, "full").violations
    mine = [r for r in paper_rows if r["scenario"] == "robocup_paper"]
    assert [int(r["violations_full"]) for r in mine] == full.tolist()
    for t in table:
        m = [r for r in rows if r["family"] == t["group"] and r["config"] == t["config"]]
        acc = [r for r in m if r["feasible"] == "True"]
        bad = [r for r in acc if int(r["violations_full"]) > 0]
        assert (int(t["accepted"]), int(t["accepted_but_colliding"])) == (len(acc), len(bad))
        if t["collision"] == "full":
            assert len(bad) == 0


@pytest.mark.slow  # a bundled study's quick run (see test_operator_study_quick_compares_with_holm)
def test_scaling_quick_reports_times(tmp_path):
    assert _study("scaling", "--quick", "--out", str(tmp_path), "--quiet") == 0
    table = _csv(tmp_path / "scaling.csv")
    assert [int(t["obstacles"]) for t in table] == [5, 9]
    rows = _csv(tmp_path / "runs.csv")
    for t in table:
        mine = [r for r in rows if int(r["obstacles"]) == int(t["obstacles"])]
        assert int(t["runs"]) == len(mine) == 40
        assert float(t["hit_rate"]) == sum(r["hit"] == "True" for r in mine) / 40
        assert float(t["exact_ms_median"]) > 0 and float(t["ga_ms_per_run"]) > 0
    for scene in {r["scenario"] for r in rows}:
        sc = load_scenario(tmp_path / "scenes" / f"{scene}.toml")
        w, h = sc.field.xmax, sc.field.ymax
        assert sc.n / (w * h) == pytest.approx(min(1.4, sc.n / (2.8 * 2.3)), rel=1e-3)


@pytest.mark.slow  # a bundled study's quick run
def test_held_out_quick_tables_every_scene(tmp_path):
    assert _study("held_out", "--quick", "--out", str(tmp_path), "--quiet", "--no-figures") == 0
    table = _csv(tmp_path / "per_scene.csv")
    rows = _csv(tmp_path / "runs.csv")
    assert {t["family"] for t in table} == {"scattered", "clusters", "obstructed", "corridors",
                                            "behind", "slot", "wall"}
    for t in table:
        by: dict[str, list[bool]] = {}
        for r in rows:
            if (r["config"], r["family"], r["obstacles"]) == (t["config"], t["family"],
                                                               t["obstacles"]):
                by.setdefault(r["scenario"], []).append(r["hit"] == "True")
        rates = {s: sum(v) / len(v) for s, v in by.items()}
        assert int(t["scenes"]) == len(rates) == 2 and int(t["runs"]) == 40
        assert float(t["worst_scene_hit_rate"]) == min(rates.values())
        assert rates[t["worst_scene"]] == min(rates.values())
        assert float(t["hit_rate"]) == sum(sum(v) for v in by.values()) / 40


RESUME = """name = "resume"
runs = 40
[[families]]
name = "c"
kind = "clutter"
obstacles = [9]
scenes = 8
seed = 4
[ga]
generations = 30
"""


def test_a_killed_study_resumes_without_losing_or_repeating(tmp_path):
    cfg = tmp_path / "resume.toml"
    cfg.write_text(RESUME)
    out = tmp_path / "out"
    env = dict(os.environ, HGA_JAX_CACHE_DIR="off", PYTHONPATH=os.getcwd())
    proc = subprocess.Popen([sys.executable, "-m", "hga_jax", "study", str(cfg), "--out",
                             str(out), "--quiet"], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    cells = out / "cells"

    def finished():  # a cell being written is a temporary file until it is renamed
        names = os.listdir(cells) if cells.exists() else []
        return [p for p in names if p.endswith(".json") and not p.startswith(".tmp-")]

    deadline = time.time() + 600
    while time.time() < deadline and proc.poll() is None and len(finished()) < 2:
        time.sleep(0.02)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    before = {p: (cells / p).read_bytes() for p in finished()}
    stamps = {p: os.stat(cells / p).st_mtime_ns for p in before}
    assert 2 <= len(before) < 8, "the study should have been killed mid-way"
    assert not (out / "runs.csv").exists()

    outcome = run_study(str(cfg), out=str(out), progress=False, figures=False)
    assert (outcome.cells_reused, outcome.cells_run) == (len(before), 8 - len(before))
    for p, data in before.items():  # finished cells were neither re-run nor rewritten
        assert (cells / p).read_bytes() == data and os.stat(cells / p).st_mtime_ns == stamps[p]
    assert not [p for p in os.listdir(cells) if p.startswith(".tmp-")]
    rows = _csv(out / "runs.csv")
    assert len(rows) == 8 * 40
    assert len({(r["scenario"], r["run"]) for r in rows}) == len(rows)
    for p, data in before.items():  # every run of a cell finished before the kill is kept
        doc = json.loads(data)
        mine = [r for r in rows if r["scenario"] == doc["scenario"]]
        assert [float(r["length"]) for r in mine] == doc["columns"]["length"]
    again = run_study(str(cfg), out=str(out), progress=False, figures=False)
    assert again.cells_run == 0 and len(again.table) == 8 * 40
    assert _csv(out / "runs.csv") == rows


PLUGIN = '''
from hga_jax.search import registry


def keep_parents(key, a, b):
    """A crossover that returns the parents unchanged."""
    return a, b


registry.register("perm_crossover", "keep_parents", keep_parents)
'''

CUSTOM = """name = "custom"
runs = 40
scenarios = ["{scene}"]
plugins = ["my_ops.py"]
[ga]
generations = 30
[[configs]]
label = "no crossover"
pc_upper = 0.0
[[configs]]
label = "keep_parents always"
perm_crossover = "keep_parents"
pc_upper = 1.0
"""


@pytest.mark.slow  # a study with a plugin operator stays in the default lane: test_plugins.py
def test_an_operator_registered_outside_the_package_takes_part(tmp_path, registries):
    (tmp_path / "my_ops.py").write_text(PLUGIN)
    cfg = tmp_path / "custom.toml"
    cfg.write_text(CUSTOM.replace("{scene}", ROBOCUP))
    outcome = run_study(str(cfg), out=str(tmp_path / "out"), progress=False)
    assert "keep_parents" in registry.names("perm_crossover")
    rows = _csv(tmp_path / "out" / "runs.csv")
    none = [r for r in rows if r["config"] == "no crossover"]
    mine = [r for r in rows if r["config"] == "keep_parents always"]
    assert {r["perm_crossover"] for r in mine} == {"keep_parents"} and len(mine) == 40
    # Returning the parents on every pair is the same search as never crossing over.
    assert [r["length"] for r in mine] == [r["length"] for r in none]
    assert outcome.summary[1]["p_hit_fisher"] == 1.0
    with pytest.raises(ValueError, match="already registered"):
        registry.register("perm_crossover", "keep_parents", lambda k, a, b: (b, a))
    with pytest.raises(ValueError, match="identifier"):
        registry.register("perm_mutation", "my op", lambda k, p: p)


@pytest.mark.slow
def test_baselines_quick_compares_every_solver(tmp_path, capsys):
    """The quick "HGA or OMPL?" study: the HGA, random search, DEAP, OMPL's BIT* and the
    exact solver are rows of one table (DEAP and OMPL skipped without the compare
    extra); a second start runs no cell again."""
    assert _study("baselines", "--quick", "--out", str(tmp_path), "--quiet") == 0
    first = capsys.readouterr().out
    rows = _csv(tmp_path / "runs.csv")
    by = lambda label: [r for r in rows if r["config"] == label]  # noqa: E731
    rs, ga = by("random search, 2550 evaluations"), by("HGA paper, batched")
    assert len(rs) == len(ga) == 20
    assert {(r["population"], r["generations"], r["evaluations"]) for r in rs} == {
        ("2550", "0", "2550")}
    assert {r["evaluations"] for r in ga} == {"2550"}  # equal evaluations: 50 x 51
    assert {r["generation_best"] for r in rs} == {"0"}
    solvers = {r["solver"] for r in rows}
    want = {"hga", "random", "exact"}
    for extra, package in (("deap", "deap"), ("ompl", "ompl")):
        if importlib.util.find_spec(package) is not None:
            want.add(extra)
    assert solvers == want
    summary = {(s["group"], s["config"]): s for s in _csv(tmp_path / "summary.csv")}
    for (group, config), s in summary.items():
        mine = [r for r in rows if r["family"] == group and r["config"] == config]
        assert float(s["time_per_run_ms"]) == pytest.approx(
            1000 * np.mean([float(r["time_s"]) for r in mine]))
    rec = by("HGA recommended, batched")
    assert np.mean([r["hit"] == "True" for r in rec]) >= np.mean([r["hit"] == "True" for r in ga])
    assert _study("baselines", "--quick", "--out", str(tmp_path), "--quiet") == 0
    assert "(0 run now" in capsys.readouterr().out and "run now" in first


@pytest.mark.slow  # 30 s; the recommended preset's hit rates are held by test_recommended.py
def test_recommended_study_quick_beats_the_paper(tmp_path):
    assert _study("recommended", "--quick", "--out", str(tmp_path), "--quiet") == 0
    rows = _csv(tmp_path / "runs.csv")
    assert {r["config"] for r in rows} == {"paper", "recommended"}
    rec = [r for r in rows if r["config"] == "recommended"]
    assert {(r["path_mutation"], r["seeding"], r["restart_after"]) for r in rec} == {
        ("flip", "1.0", "8")}
    assert all(r["evaluations"] == "2550" for r in rows)  # the same budget for both
    by = {c: sum(r["hit"] == "True" for r in rows if r["config"] == c) for c in ("paper",
                                                                                  "recommended")}
    # measured: recommended 238 of 240 quick runs (6 scenes x 40), the paper's 59 of 240
    assert by["recommended"] >= 230 and by["paper"] <= 120
