"""The command line: result files, summaries, and one-line errors for bad input."""
import csv
import json
import os
import subprocess
import sys

import pytest

from hga_jax.cli import main
from hga_jax.path import segments_length

OPEN = "configs/scenarios/open_field.toml"
ROBOCUP = "configs/scenarios/robocup_paper.toml"

GOOD = """name = "tiny"
[robot]
radius = 0.09
min_turn_radius = 0.2
[start]
x = 0.3
y = 0.5
heading_deg = 0
[goal]
x = 2.5
y = 0.5
heading_deg = 0
[[obstacles]]
x = 1.4
y = 0.5
[field]
xmin = 0
xmax = 3
ymin = 0
ymax = 1.2
keep_inside = true
"""


def test_run_writes_result_history_and_plots(tmp_path, capsys):
    out = tmp_path / "res"
    code = main(["run", ROBOCUP, "--runs", "6", "--generations", "8", "--seed", "5",
                 "--out", str(out), "--plot", "--quiet"])
    assert code == 0
    printed = capsys.readouterr().out
    assert "best length" in printed and "compile" in printed and "search" in printed
    data = json.loads((out / "result.json").read_text())
    best = data["best"]
    assert data["scenario"]["name"] == data["scenario_name"] == "robocup_paper"
    assert data["seed"] == 5
    assert data["settings"]["generations"] == 8 and data["settings"]["population"] == 50
    assert {"jax", "hga_jax"} <= set(data["versions"])
    assert len(data["per_run"]) == 6
    assert best["length"] == min(r["length"] for r in data["per_run"] if r["feasible"])
    assert segments_length(best["segments"]) == pytest.approx(best["length"], rel=1e-9)
    assert best["upper"][0] == 0 and best["upper"][-1] == 10 and len(best["lower"]) == 11
    rows = list(csv.DictReader((out / "history.csv").open()))
    assert len(rows) == 9 and rows[0]["generation"] == "0"
    assert float(rows[-1]["best_so_far_fitness_median"]) >= float(rows[0]["best_so_far_fitness_median"])
    for png in ("path.png", "convergence.png"):
        assert (out / png).stat().st_size > 10_000


def test_existing_results_are_not_overwritten(tmp_path, capsys):
    out = tmp_path / "res"
    out.mkdir()
    (out / "result.json").write_text("precious")
    code = main(["run", OPEN, "--runs", "1", "--generations", "1", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "already exists" in err and (out / "result.json").read_text() == "precious"


def _write(tmp_path, text, name="bad.toml"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


BAD = [
    ("missing key", GOOD.replace("min_turn_radius = 0.2\n", ""), "robot.min_turn_radius"),
    ("NaN", GOOD.replace("x = 1.4", "x = nan"), "obstacles[0].x"),
    ("negative radius", GOOD.replace("radius = 0.09", "radius = -0.09"), "robot.radius"),
    ("start inside", GOOD.replace("x = 1.4", "x = 0.35"), "start"),
    ("same centre", GOOD + "[[obstacles]]\nx = 1.4\ny = 0.5\n", "obstacles[1]"),
    ("out of field", GOOD.replace("y = 0.5\nheading_deg = 0\n[goal]", "y = 0.05\nheading_deg = 0\n[goal]"),
     "start"),
    ("bad ga value", GOOD + "[ga]\npopulation = 1\n", "ga.population"),
    ("unknown ga key", GOOD + "[ga]\npopsize = 10\n", "ga.popsize"),
    ("syntax", GOOD.replace("[goal]", "[goal"), "syntax error"),
    ("unknown key", GOOD.replace("[robot]\n", "[robot]\nradus = 0.1\n"), "robot.radus"),
    ("wrong type", GOOD.replace("y = 0.5\n[field]", "y = \"0.5\"\n[field]"), "obstacles[0].y"),
    ("inf", GOOD.replace("heading_deg = 0\n[[obstacles]]", "heading_deg = inf\n[[obstacles]]"),
     "goal.heading_deg"),
    ("goal inside", GOOD.replace("x = 1.4", "x = 2.45"), "goal"),
    ("zero radius", GOOD.replace("min_turn_radius = 0.2", "min_turn_radius = 0"),
     "robot.min_turn_radius"),
]


@pytest.mark.parametrize("case,text,key", BAD, ids=[b[0] for b in BAD])
def test_bad_scenario_gives_one_line_error(tmp_path, capsys, case, text, key):
    path = _write(tmp_path, text)
    code = main(["run", path, "--runs", "1", "--out", str(tmp_path / "o"), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert path in err and key in err
    assert not (tmp_path / "o" / "result.json").exists()


def test_bad_flags_and_ga_file(tmp_path, capsys):
    good = _write(tmp_path, GOOD, "good.toml")
    assert main(["run", good, "--pc-upper", "1.5", "--quiet", "--out", str(tmp_path)]) == 2
    assert "ga.pc_upper" in capsys.readouterr().err
    ga = _write(tmp_path, "population = 10\nselektion = 'roulette'\n", "ga.toml")
    assert main(["run", good, "--ga", ga, "--quiet", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert ga in err and "selektion" in err
    assert main(["run", str(tmp_path / "missing.toml"), "--quiet"]) == 2
    assert "missing.toml" in capsys.readouterr().err
    assert main(["run", good, "--seed", str(2**32), "--quiet", "--out", str(tmp_path)]) == 2
    assert "--seed" in capsys.readouterr().err  # would alias seed 0: refused
    assert main(["check", good]) == 0


def test_console_script_prints_no_traceback(tmp_path):
    bad = _write(tmp_path, GOOD.replace("radius = 0.09", "radius = 0"))
    proc = subprocess.run([sys.executable, "-m", "hga_jax.cli", "check", bad],
                          capture_output=True, text=True, env={**os.environ, "JAX_PLATFORMS": "cpu"})
    assert proc.returncode == 2
    assert proc.stderr.count("\n") == 1 and "robot.radius" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_exact_command_writes_the_optimum(tmp_path, capsys):
    out = tmp_path / "exact"
    assert main(["exact", ROBOCUP, "--out", str(out), "--plot"]) == 0
    printed = capsys.readouterr().out
    assert "optimum 2.245430 m" in printed and "2CW 4CW 5CCW 6CW" in printed
    data = json.loads((out / "result.json").read_text())
    assert set(data) >= {"scenario_name", "settings", "versions", "best", "optimum", "per_run"}
    best = data["best"]
    assert best["feasible"] and best["length"] == data["optimum"]["length"]
    assert best["upper"] == [0, 2, 4, 5, 6, 1, 3, 7, 8, 9, 10]
    assert best["lower"] == [-1, 1, 1, -1, 1, 0, 0, 0, 0, 0, 1]
    assert segments_length(best["segments"]) == pytest.approx(best["length"], rel=1e-9)
    assert (out / "path.png").stat().st_size > 10_000


def test_compiled_programs_are_cached_on_disk_and_change_nothing(tmp_path):
    env = {**os.environ, "JAX_PLATFORMS": "cpu", "HGA_JAX_CACHE_DIR": str(tmp_path / "cache")}
    results, entries = [], []
    for i in range(2):
        out = tmp_path / f"r{i}"
        subprocess.run([sys.executable, "-m", "hga_jax", "run", ROBOCUP, "--runs", "3",
                        "--generations", "4", "--out", str(out), "--quiet", "--no-exact"],
                       env=env, check=True, capture_output=True)
        results.append(json.loads((out / "result.json").read_text()))
        entries.append(sorted(p.name for p in (tmp_path / "cache").iterdir()))
    assert entries[0] and entries[0] == entries[1]  # the second run found every program
    assert results[0]["per_run"] == results[1]["per_run"]
