"""The command line: result files, summaries, and one-line errors for bad input."""
import csv
import dataclasses
import json
import os
import subprocess
import sys

import pytest

from hga_jax.host.cli import main
from hga_jax.model.path import segments_length

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
    # 60 runs: the program of the held-out floors and the island test
    code = main(["run", ROBOCUP, "--runs", "60", "--seed", "5", "--out", str(out), "--plot",
                 "--quiet"])
    assert code == 0
    printed = capsys.readouterr().out
    assert "best length" in printed and "compile" in printed and "search" in printed
    data = json.loads((out / "result.json").read_text())
    best = data["best"]
    assert data["scenario"]["name"] == data["scenario_name"] == "robocup_paper"
    assert data["seed"] == 5
    assert data["settings"]["generations"] == 50 and data["settings"]["population"] == 50
    assert {"jax", "hga_jax"} <= set(data["versions"])
    assert len(data["per_run"]) == 60
    assert best["length"] == min(r["length"] for r in data["per_run"] if r["feasible"])
    assert segments_length(best["segments"]) == pytest.approx(best["length"], rel=1e-9)
    assert best["upper"][0] == 0 and best["upper"][-1] == 10 and len(best["lower"]) == 11
    rows = list(csv.DictReader((out / "history.csv").open()))
    assert len(rows) == 51 and rows[0]["generation"] == "0"
    assert float(rows[-1]["best_so_far_fitness_median"]) >= float(rows[0]["best_so_far_fitness_median"])
    for png in ("path.png", "convergence.png"):
        assert (out / png).stat().st_size > 10_000


def test_existing_results_are_not_overwritten(tmp_path, capsys):
    out = tmp_path / "res"
    out.mkdir()
    (out / "result.json").write_text("precious")
    code = main(["run", OPEN, "--runs", "1", "--generations", "1", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "already holds a result (result.json)" in err and "--force" in err
    assert (out / "result.json").read_text() == "precious" and os.listdir(out) == ["result.json"]


def _write(tmp_path, text, name="bad.toml"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


BAD = [
    ("missing key", GOOD.replace("min_turn_radius = 0.2\n", ""), "robot.min_turn_radius"),
    ("NaN", GOOD.replace("x = 1.4", "x = nan"), "obstacles[1].x"),
    ("negative radius", GOOD.replace("radius = 0.09", "radius = -0.09"), "robot.radius"),
    ("start inside", GOOD.replace("x = 1.4", "x = 0.35"), "start"),
    ("same centre", GOOD + "[[obstacles]]\nx = 1.4\ny = 0.5\n", "obstacles[2]"),
    ("out of field", GOOD.replace("y = 0.5\nheading_deg = 0\n[goal]", "y = 0.05\nheading_deg = 0\n[goal]"),
     "start"),
    ("bad ga value", GOOD + "[ga]\npopulation = 1\n", "ga.population"),
    ("unknown ga key", GOOD + "[ga]\npopsize = 10\n", "ga.popsize"),
    ("syntax", GOOD.replace("[goal]", "[goal"), "syntax error"),
    ("unknown key", GOOD.replace("[robot]\n", "[robot]\nradus = 0.1\n"), "robot.radus"),
    ("wrong type", GOOD.replace("y = 0.5\n[field]", "y = \"0.5\"\n[field]"), "obstacles[1].y"),
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
    assert "command line: --pc-upper: must be a probability" in capsys.readouterr().err
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
    proc = subprocess.run([sys.executable, "-m", "hga_jax.host.cli", "check", bad],
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
    assert data["random_stream"] == "generation-draw"
    best = data["best"]
    assert best["feasible"] and best["length"] == data["optimum"]["length"]
    assert best["upper"] == [0, 2, 4, 5, 6, 1, 3, 7, 8, 9, 10]
    assert best["lower"] == [-1, 1, 1, -1, 1, 0, 0, 0, 0, 0, 1]
    assert segments_length(best["segments"]) == pytest.approx(best["length"], rel=1e-9)
    assert (out / "path.png").stat().st_size > 10_000


# ------------------------------------------------------------ what a new user meets

SAME = GOOD.replace("x = 2.5\ny = 0.5\nheading_deg = 0", "x = 0.3\ny = 0.5\nheading_deg = 0")
# The paper's preset: these tests are about the command line, and its program compiles
# in half the time of the recommended one (guided moves).
TINY = ["--runs", "3", "--generations", "3", "--population", "10", "--quiet", "--preset", "paper"]
QUICK = ["--runs", "2", "--generations", "0", "--population", "10", "--quiet",
         "--preset", "paper"]  # one program


def _run_cli(argv):
    """main(argv) with stdout and stderr captured: (status, out, err)."""
    import contextlib
    import io

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """One small run with plots and --json; (folder, printed JSON, stderr)."""
    base = tmp_path_factory.mktemp("tiny")
    scen = base / "good.toml"
    scen.write_text(GOOD)
    out = base / "res"
    code, printed, err = _run_cli(["run", str(scen), *TINY, "--plot", "--json", "--out", str(out)])
    assert code == 0, err
    return out, json.loads(printed), err, str(scen)


def test_json_summary_on_stdout(tiny):
    out, doc, err, _ = tiny
    assert err == ""
    assert doc["command"] == "run" and doc["scenario"] == "tiny" and doc["seed"] == 0
    assert doc["settings"]["population"] == 10 and doc["summary"]["runs"] == 3
    data = json.loads((out / "result.json").read_text())
    assert doc["summary"] == data["summary"]
    assert doc["best"]["length"] == data["best"]["length"]
    assert doc["written"] == [str(out / n) for n in
                              ("result.json", "history.csv", "path.png", "convergence.png")]


def test_touched_has_one_format_numbered_from_one(tiny):
    out, *_ = tiny
    data = json.loads((out / "result.json").read_text())
    for touched in (data["best"]["touched"], data["optimum"]["touched"]):
        assert touched and all(set(t) == {"obstacle", "label"} for t in touched)
        assert [t["obstacle"] for t in touched] == [1]  # the one obstacle is number 1
    assert data["best"]["upper"] == [0, 1, 2]
    from hga_jax.host.config import scenario_from_dict
    from hga_jax.host.plots import plot_path

    sc = scenario_from_dict(data["scenario"]["definition"])
    ax = plot_path(sc, data["best"]["segments"], touched=data["best"]["touched"]).axes[0]
    assert [t.get_text() for t in ax.texts if t.get_gid() == "touched"] == [
        "CW" if data["best"]["touched"][0]["label"] > 0 else "CCW"]


def test_plot_command_redraws_any_run_with_the_optimum(tiny, tmp_path):
    out, *_ = tiny
    res = str(out / "result.json")
    code, printed, err = _run_cli(["plot", res, "--run", "2", "--with-optimum", "--no-cache"])
    assert code == 0 and err == "" and printed.strip() == f"wrote {out / 'path_run2.png'}"
    assert (out / "path_run2.png").stat().st_size > 10_000
    code, _, err = _run_cli(["plot", res, "--run", "2"])
    assert code == 2 and "path_run2.png: already exists" in err
    code, _, err = _run_cli(["plot", res, "--run", "99", "--out", str(tmp_path / "x.png")])
    assert code == 2 and err.strip() == f"hga-jax: error: {res}: per_run: no run 99 in this file (runs 0..2)"
    from hga_jax.host.report import redraw

    ax = redraw(res, run=1, with_optimum=True).axes[0]
    opt = json.loads((out / "result.json").read_text())["optimum"]
    dashed = [a for a in ax.get_lines() if a.get_gid() == "optimum_path"]
    assert len(dashed) == len(opt["segments"])
    assert "run 1" in ax.get_title() and "collision full" in ax.get_title()


def test_summary_reads_well(tmp_path, capsys):
    # one run of the bundled scene: test_islands.py's single run compiles the program
    assert main(["run", ROBOCUP, "--runs", "1", "--quiet", "--out", str(tmp_path / "o")]) == 0
    text = capsys.readouterr().out
    assert "None" not in text and "1 runs" not in text and "1 run of seed 0" in text
    assert "collision full" in text and "tournament selection (size 2)" in text
    assert "operators (preset recommended)" in text
    assert "path move guided (pm 1, arcs at 100.00% of the penalty)" in text
    assert "in a restart of a run whose best collides, 100.00% of them via a random obstacle" in text
    # 9 obstacles: 50 generations, as the rule says
    assert "50 generations (generations = 50 + 24 * max(0, n - 9))" in text
    assert "restart after 12 stalled generations" in text
    assert "penalty 10 x 2 pi R per violation in the search" in text
    import re

    assert re.findall(r"\d+\.(\d+)%", text) and all(
        len(d) == 2 for d in re.findall(r"\d+\.(\d+)%", text))
    assert re.findall(r"(?<![\d.])\d+%", text) == ["1%"]  # "within 1%", no other bare figure
    assert "(median over the 1 run that got there)" in text or "no run got there" in text


def test_start_equal_to_goal_is_a_hit_with_zero_gap(tmp_path, capsys):
    import warnings

    scen = _write(tmp_path, SAME, "same.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["run", scen, *TINY, "--out", str(tmp_path / "o")]) == 0
    text = capsys.readouterr().out
    assert "optimum 0.000000 m: hit rate 100.00% (3 of 3 runs)" in text
    assert "median 0.00%, mean 0.00%, max 0.00%" in text and "nan" not in text


def test_results_of_exact_and_run_never_mix(tmp_path, monkeypatch, capsys):
    import hga_jax as hg

    scen = os.path.abspath(_write(tmp_path, GOOD, "good.toml"))
    monkeypatch.chdir(tmp_path)
    assert main(["exact", scen, "--plot"]) == 0
    assert main(["run", scen, *QUICK, "--plot"]) == 0
    assert sorted(os.listdir("results")) == ["good", "good-exact"]
    assert sorted(os.listdir("results/good-exact")) == ["path.png", "result.json"]
    assert sorted(os.listdir("results/good")) == ["convergence.png", "history.csv", "path.png",
                                                  "result.json"]
    capsys.readouterr()
    # --force without --plot: the earlier result's PNGs go with it
    assert main(["run", scen, *QUICK, "--seed", "1", "--force"]) == 0
    assert sorted(os.listdir("results/good")) == ["history.csv", "result.json"]
    # exact --force into a run's folder leaves no history.csv behind
    assert main(["exact", scen, "--out", "results/good", "--force"]) == 0
    assert os.listdir("results/good") == ["result.json"]
    # the API refuses as the command line does, and replaces with force=True
    res = hg.run_many(hg.load_scenario(scen), hg.GASettings(population=10, generations=0), runs=2)
    with pytest.raises(hg.ConfigError, match="already holds a result"):
        hg.write_run(res, "results/good")
    assert hg.write_run(res, "results/good", force=True) == ["results/good/result.json",
                                                            "results/good/history.csv"]


def test_closed_or_full_stdout_costs_no_result(tmp_path):
    env = {**os.environ, "JAX_PLATFORMS": "cpu", "PYTHONUNBUFFERED": "1"}
    cmd = f"{sys.executable} -u -m hga_jax run {OPEN} --runs 2 --generations 2 --quiet"
    proc = subprocess.run(["bash", "-c", f"set -o pipefail; {cmd} --out {tmp_path / 'a'} | head -2"],
                          capture_output=True, text=True, env=env)
    assert proc.returncode == 0 and proc.stderr == "" and len(proc.stdout.splitlines()) == 2
    assert json.loads((tmp_path / "a" / "result.json").read_text())["summary"]["runs"] == 2
    assert (tmp_path / "a" / "history.csv").exists()
    if os.path.exists("/dev/full"):
        proc = subprocess.run(["bash", "-c", f"{cmd} --out {tmp_path / 'b'} > /dev/full"],
                              capture_output=True, text=True, env=env)
        assert proc.returncode == 1
        assert proc.stderr == "hga-jax: error: standard output: No space left on device\n"
        assert (tmp_path / "b" / "result.json").exists()


@pytest.mark.slow  # interruption stays in the default lane: test_resume.py (Ctrl-C and SIGTERM)
def test_ctrl_c_stops_a_long_run_promptly_and_writes_nothing(tmp_path):
    import signal
    import time

    out = tmp_path / "never"
    env = {**os.environ, "JAX_PLATFORMS": "cpu", "HGA_JAX_CACHE_DIR": "off"}
    # As from a terminal, whatever this test process inherited or another test left: a
    # blocked or ignored SIGINT would be passed on to the child.
    mask = signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT])
    handler = signal.getsignal(signal.SIGINT)
    if handler == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        proc = subprocess.Popen([sys.executable, "-m", "hga_jax", "run", ROBOCUP, "--preset", "paper",
                                 "--runs", "100", "--generations", "100000", "--out", str(out)],
                                stderr=subprocess.PIPE, stdout=subprocess.PIPE, env=env)
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, mask)
        if handler == signal.SIG_IGN:
            signal.signal(signal.SIGINT, handler)
    blocked = signal.SIGINT in mask
    import re

    seen = b""
    while not re.search(rb"\| *[1-9]\d*/100001", seen):  # the bar has moved: searching
        chunk = proc.stderr.read1(4096)
        assert chunk, seen
        seen += chunk
    t0 = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        rest = proc.communicate(timeout=60)[1]
    except subprocess.TimeoutExpired:
        proc.kill()
        raise AssertionError(f"no exit 60 s after SIGINT (SIGINT blocked in the test: {blocked}, "
                             f"handler {signal.getsignal(signal.SIGINT)})") from None
    waited = time.monotonic() - t0
    assert proc.returncode == 130 and waited < 10
    last = rest.decode().replace("\r", "\n").strip().splitlines()[-1]
    assert last.startswith("hga-jax: interrupted in batch 1 of 1 after ")
    assert last.endswith(" of 100001 generations; nothing written")
    assert not out.exists()


def test_chunk_and_memory_limits_are_refused_in_one_line(tmp_path, capsys):
    good = _write(tmp_path, GOOD, "good.toml")
    out = str(tmp_path / "o")
    assert main(["run", good, "--chunk", "0", "--out", out]) == 2
    assert capsys.readouterr().err == ("hga-jax: error: command line: --chunk: must be in "
                                       "1..2,147,483,647, got 0\n")
    assert main(["run", good, "--runs", "2147483647", "--out", out]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("hga-jax: error: command line: runs: ")
    assert "2,147,483,647 runs of 50 generations need about" in err and "--runs " in err
    assert err.rstrip().endswith("would fit")
    assert main(["run", good, "--population", "100000000", "--out", out]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--population " in err and err.rstrip().endswith("would fit")
    assert not os.path.exists(out)


def test_budget_sizes_batches_to_fit():
    from hga_jax.running import budget
    from hga_jax.search.settings import GASettings

    s = GASettings()
    free = budget.plan(9, s, 2000, None, available=10**11)
    assert (free.chunk, free.batches) == (1000, 2) and 1 <= free.block <= 50
    tight = budget.plan(9, s, 2000, None, available=int(3 * free.device_bytes / 4 / budget.FILL)
                        + free.host_bytes * 2)
    assert tight.chunk < 1000 and tight.device_bytes + tight.host_bytes <= 3 * free.device_bytes
    assert budget.plan(9, s, 10, 4, devices=3, available=10**11).chunk == 6


def test_layered_settings_errors_name_each_source(tmp_path, capsys):
    scen = _write(tmp_path, GOOD + "[ga]\nselection = \"tournament\"\ntournament_size = 40\n",
                  "layered.toml")
    assert main(["run", scen, "--population", "30", "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == (
        f"hga-jax: error: {scen}: ga.tournament_size: must be in 1..population (30, from "
        "command line: --population), got 40\n")


def test_check_reports_every_file(tmp_path, capsys):
    good = _write(tmp_path, GOOD, "good.toml")
    bad = _write(tmp_path, GOOD.replace("radius = 0.09", "radius = 0"), "bad.toml")
    ga = _write(tmp_path, "population = 20\nselection = \"tournament\"\n", "ga.toml")
    assert main(["check", good, bad, ROBOCUP, "--ga", ga]) == 2
    out, err = capsys.readouterr()
    path = ", a feasible path exists under collision full)"
    assert out.splitlines() == [f"{good}: ok (scenario tiny, 1 obstacle{path}",
                                f"{ROBOCUP}: ok (scenario robocup_paper, 9 obstacles{path}",
                                f"{ga}: ok (GA settings: population = 20, selection = tournament)"]
    assert err.splitlines() == [f"hga-jax: error: {bad}: robot.radius: must be > 0, got 0.0"]
    assert main(["check", good, "--ga", _write(tmp_path, "elites = 60\n", "g2.toml")]) == 2
    assert f"{tmp_path / 'g2.toml'}: elites: must be in 0..population (50, from the default)" \
        in capsys.readouterr().err


def test_help_shows_defaults_and_every_argument_is_explained(capsys):
    from hga_jax.host.cli import _parser

    parser = _parser()
    subs = parser._subparsers._group_actions[0].choices
    assert set(subs) == {"run", "exact", "check", "plot", "export", "study", "episode"}
    for name, sub in subs.items():
        for action in sub._actions:
            assert action.help, (name, action.dest)
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "number of runs (default: 1)" in text and "(default: 0)" in text
    assert "individuals per run (recommended: 50, paper: 50)" in text
    assert "parent selection (recommended: tournament, paper: roulette)" in text
    assert "{recommended,paper}" in text and "(default: recommended)" in text


def test_preset_paper_reproduces_the_papers_settings_and_is_recorded(tmp_path):
    from hga_jax.search.settings import PAPER, RECOMMENDED

    scen = _write(tmp_path, GOOD, "good.toml")
    docs = {}
    for preset in ("paper", "recommended"):
        out = tmp_path / preset
        assert main(["run", scen, "--runs", "1", "--generations", "2", "--quiet",
                     "--preset", preset, "--out", str(out)]) == 0
        docs[preset] = json.loads((out / "result.json").read_text())
    assert docs["paper"]["preset"] == "paper"
    assert docs["paper"]["settings"] == {**dataclasses.asdict(PAPER), "generations": 2,
                                       "car": "dubins"}
    assert docs["recommended"]["preset"] == "recommended"
    # result.json holds the settings the runs used (the budget rule resolved) and the rule
    assert docs["recommended"]["settings"] == {**dataclasses.asdict(RECOMMENDED), "generations": 2,
                                               "generations_per_obstacle": 0, "car": "dubins",
                                               "path_mutation": "guided", "pairs_from": 0}
    assert docs["recommended"]["budget"] == {
        "rule": "generations = 2 + 24 * max(0, n - 9)", "obstacles": 1, "generations": 2,
        "evaluations_per_run": 50 * 3}
    assert "budget" not in docs["paper"]
    # the paper's HGA: roulette, CX, inversion, two-point, redraw, 0.4/0.02, no elites
    p = docs["paper"]["settings"]
    assert (p["selection"], p["perm_crossover"], p["perm_mutation"], p["label_crossover"],
            p["pc_upper"], p["pm_upper"], p["pc_lower"], p["pm_lower"], p["elites"],
            p["path_mutation"], p["seeding"], p["restart_after"]) == (
        "roulette", "cx", "inversion", "two_point", 0.4, 0.02, 0.4, 0.02, 0, "none", 0.0, 0)


def test_a_bad_cache_folder_is_reported(tmp_path, monkeypatch, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    monkeypatch.setenv("HGA_JAX_CACHE_DIR", str(blocker / "cache"))
    assert main(["exact", OPEN, "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert err == (f"hga-jax: warning: HGA_JAX_CACHE_DIR={blocker / 'cache'}: cannot keep "
                   "compiled programs there (Not a directory); compiling without a cache\n")


def test_internal_errors_are_one_line_with_status_3(monkeypatch, tmp_path, capsys):
    import hga_jax.model.exact
    from hga_jax.errors import ModelMismatchError

    def mismatch(scenario, collision="full", turns="tight-rope", car=None):
        raise ModelMismatchError(f"{scenario.name}: walk 2.0 m, decoder 2.1 m")

    monkeypatch.setattr(hga_jax.model.exact, "solve", mismatch)
    assert main(["exact", ROBOCUP, "--out", str(tmp_path / "o")]) == 3
    out, err = capsys.readouterr()
    assert out == "" and err == ("hga-jax: internal error: robocup_paper: walk 2.0 m, decoder "
                                 "2.1 m (please report this scenario)\n")
    assert not (tmp_path / "o").exists()


def test_exact_in_paper_mode_says_so(tmp_path, capsys):
    assert main(["exact", ROBOCUP, "--collision", "paper", "--out", str(tmp_path / "o"),
                 "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["optimum"]["collision"] == "paper"
    assert main(["exact", ROBOCUP, "--collision", "paper", "--out", str(tmp_path / "p")]) == 0
    text = capsys.readouterr().out
    assert "collision paper" in text
    assert "note: collision \"paper\": segments judged by the paper's Appendix B test" in text
    assert "this path is feasible under the full test too" in text


def test_exact_in_paper_mode_says_what_the_full_test_finds(tmp_path, capsys):
    scen = "configs/scenarios/overlapping.toml"
    assert main(["exact", scen, "--collision", "paper", "--out", str(tmp_path / "o")]) == 0
    assert ("; this path has 5 violations under the full test (collision \"full\")"
            in capsys.readouterr().out)


def test_run_ranges_are_one_rule_for_the_command_line_and_run_many(tmp_path, capsys):
    from hga_jax.errors import ConfigError
    from hga_jax.host.config import load_scenario
    from hga_jax.running.runner import run_many

    sc = load_scenario(ROBOCUP)
    for kwargs, message in (
            ({"seed": -1}, "run_many: seed: must be an integer in 0..4294967295, got -1"),
            ({"seed": 2**32}, "run_many: seed: must be an integer in 0..4294967295, "
                              "got 4294967296"),
            ({"runs": 0}, "run_many: runs: must be an integer in 1..2147483647, got 0"),
            ({"runs": 2, "first_run": 2**31 - 2},
             "run_many: first_run: must be an integer in 0..2147483645, got 2147483646"),
            ({"chunk": 1.5}, "run_many: chunk: must be an integer in 1..2147483647, got 1.5"),
            ({"seed": True}, "run_many: seed: must be an integer in 0..4294967295, got True")):
        with pytest.raises(ConfigError) as err:
            run_many(sc, **kwargs)
        assert str(err.value) == message
    good = _write(tmp_path, GOOD, "good.toml")
    for flags, message in ((["--seed", "4294967296"], "--seed: must be in "
                            "0..4,294,967,295, got 4,294,967,296"),
                           (["--runs", "2", "--first-run", "2147483646"], "--first-run: must "
                            "be in 0..2,147,483,645, got 2,147,483,646")):
        assert main(["run", good, *flags, "--out", str(tmp_path / "o")]) == 2
        assert capsys.readouterr().err == f"hga-jax: error: command line: {message}\n"
