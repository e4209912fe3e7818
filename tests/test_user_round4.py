"""What a new user met: one default preset, the program folder on by default, poses as
public API, and the command line's messages (compile, --car, no path, gaps, SIGTERM)."""
import dataclasses
import json
import math
import os
import signal
import subprocess
import sys

import numpy as np
import pytest

import hga_jax as hg
from hga_jax import compiled
from hga_jax.host import cli
from hga_jax.host.cli import main
from hga_jax.model.path import Path
from hga_jax.running import budget, runner
from hga_jax.running.results import BestPath, gap_of
from hga_jax.search.settings import PAPER, RECOMMENDED

ROBOCUP = "configs/scenarios/robocup_paper.toml"
OPEN = "configs/scenarios/open_field.toml"


def _err_lines(capsys):
    return capsys.readouterr().err.strip().splitlines()


# -- 1. one default preset -----------------------------------------------------------


class _Stop(Exception):
    pass


@pytest.fixture
def searched(monkeypatch):
    """run_many up to its search: the settings it would search (nothing compiles)."""
    seen = []

    def search(scenario, settings, *args):
        seen.append(settings)
        raise _Stop

    monkeypatch.setattr(runner, "_search", search)
    return seen


def test_run_many_and_settings_for_default_to_the_command_lines_preset(searched):
    sc = hg.load_scenario(ROBOCUP)
    assert runner.DEFAULT_PRESET == "recommended"
    assert hg.settings_for(sc) == hg.settings_for(sc, "recommended") == RECOMMENDED
    assert hg.settings_for(sc, "paper") == PAPER
    for call in (lambda: hg.run_many(sc, runs=20), lambda: hg.run_many(sc, None, runs=20),
                 lambda: hg.run_many(sc, "recommended", runs=20),
                 lambda: hg.run_many(sc, preset="recommended", runs=20)):
        with pytest.raises(_Stop):
            call()
    with pytest.raises(_Stop):
        hg.run_many(sc, "paper", runs=20)  # the paper's HGA: named
    with pytest.raises(_Stop):
        hg.run_many(sc, preset="paper", runs=20)
    recommended = RECOMMENDED.for_car(sc.car).for_obstacles(sc.n)
    assert searched[:4] == [recommended] * 4
    assert searched[4:] == [PAPER.for_car(sc.car).for_obstacles(sc.n)] * 2
    assert searched[0].selection == "tournament" and searched[0].elites > 0
    assert searched[4].selection == "roulette" and searched[4].elites == 0


def test_the_docs_say_the_default(capsys):
    python = open("docs/python.md").read()
    assert 'hg.run_many(sc, runs=20)' in python and '"recommended"' in python
    assert "hg.run_many(sc, \"paper\"" in python
    settings = open("docs/settings.md").read()
    assert "`run_many` and `settings_for`" in settings


# -- 2. use_cpu_cores: when --------------------------------------------------------


def test_use_cpu_cores_says_when_to_use_it():
    for text in (hg.__doc__, open("docs/python.md").read()):
        assert "hg.use_cpu_cores()" in text
        assert "many runs per call" in text and "one plan per call" in text


# -- 3. the program folder, on by default -------------------------------------------


def _lower():
    import jax
    import jax.numpy as jnp

    return jax.jit(lambda x: jnp.cos(x) * 3.25).lower(np.zeros(3, np.float32))


@pytest.fixture
def unset(monkeypatch, tmp_path):
    """A process where nothing chose a folder, HGA_JAX_CACHE_DIR naming a fresh one."""
    monkeypatch.setattr(compiled, "_FOLDER", [compiled._UNSET])
    monkeypatch.setattr(compiled, "_RECENT", {})
    monkeypatch.setenv("HGA_JAX_CACHE_DIR", str(tmp_path / "programs"))
    return tmp_path / "programs"


def _stored(where):
    return sorted(p.name for p in where.glob("*.jaxprog")) if where.is_dir() else []


def test_the_first_program_turns_the_folder_on(unset):
    assert compiled.folder() is None  # nothing chose yet
    compiled.program(("round4", 1), _lower)
    assert compiled.folder() == str(unset)
    assert len(_stored(unset)) == 1


def test_off_by_a_call_or_the_environment(unset, monkeypatch):
    assert hg.enable_compilation_cache(False) is None
    compiled.program(("round4", 2), _lower)
    assert compiled.folder() is None and _stored(unset) == []
    monkeypatch.setattr(compiled, "_FOLDER", [compiled._UNSET])
    monkeypatch.setenv("HGA_JAX_CACHE_DIR", "off")
    compiled.program(("round4", 3), _lower)
    assert compiled.folder() is None and _stored(unset) == []
    monkeypatch.setenv("HGA_JAX_CACHE_DIR", str(unset))
    assert hg.enable_compilation_cache(True) == str(unset)  # on again, the default folder


def test_the_default_folder_under_xdg_cache_home(unset, monkeypatch, tmp_path):
    monkeypatch.delenv("HGA_JAX_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    compiled.program(("round4", 4), _lower)
    assert compiled.folder() == str(tmp_path / "xdg" / "hga-jax" / "programs")
    assert len(_stored(tmp_path / "xdg" / "hga-jax" / "programs")) == 1


def test_a_configured_jax_cache_is_left_alone(tmp_path):
    """In a fresh process whose JAX cache names a folder, hga-jax keeps none of its own."""
    code = ("import jax, numpy as np; jax.config.update('jax_compilation_cache_dir', "
            f"{str(tmp_path / 'jax')!r}); from hga_jax import compiled; "
            "compiled.program(('round4', 5), lambda: jax.jit(lambda x: x * 2.5).lower("
            "np.zeros(2, np.float32))); print(compiled.folder())")
    env = {**os.environ, "JAX_PLATFORMS": "cpu", "HGA_JAX_CACHE_DIR": str(tmp_path / "mine")}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "None"
    assert not (tmp_path / "mine").exists()


def test_no_cache_keeps_programs_in_memory_for_that_command(unset, tmp_path, capsys):
    out = str(tmp_path / "o")
    assert main(["exact", OPEN, "--out", out, "--no-cache"]) == 0
    assert _stored(unset) == [] and compiled._FOLDER[0] is compiled._UNSET  # as before
    compiled.forget()
    assert main(["exact", OPEN, "--out", out, "--force"]) == 0
    assert len(_stored(unset)) == 1  # the float64 decoder


def test_tests_keep_programs_outside_the_repository():
    """conftest.py names a temporary folder (removed after the session) for this process
    and every command it starts; the default one, under ~/.cache, is never the tests'."""
    repo = os.path.abspath(os.getcwd()) + os.sep
    where = os.environ["HGA_JAX_CACHE_DIR"]
    assert where == "off" or not os.path.abspath(where).startswith(repo)
    assert compiled.folder() in (None, where)


# -- 4. poses ----------------------------------------------------------------------

COLUMNS = ("s", "x", "y", "heading", "curvature", "gear", "t")


def test_a_straight_line_as_poses():
    length, speed = 2.0, 0.5
    line = [{"type": "line", "start": [1.0, 1.0], "end": [1.0 + length * math.cos(0.3),
                                                          1.0 + length * math.sin(0.3)]}]
    p = hg.poses(line, 0.25, speed=speed)
    assert p.dtype.names == COLUMNS
    assert p["gear"].dtype == np.int8 and np.all(p["gear"] == 1)
    assert len(p) == 9  # 0, 0.25, ..., 2.0
    np.testing.assert_allclose(p["s"], np.arange(9) * 0.25, atol=1e-12)
    np.testing.assert_allclose(p["heading"], 0.3, atol=1e-12)
    np.testing.assert_allclose(p["curvature"], 0.0)
    np.testing.assert_allclose(p["t"], p["s"] / speed)
    np.testing.assert_allclose(p["x"], 1.0 + p["s"] * math.cos(0.3), atol=1e-12)


def test_an_arc_as_poses_has_curvature_one_over_rho():
    rho = 0.2
    left = [{"type": "arc", "center": [0.0, 0.0], "radius": rho, "start_angle": -math.pi / 2,
             "sweep": math.pi / 2}]
    p = hg.poses(left, 0.01)
    np.testing.assert_allclose(p["curvature"], 1.0 / rho)
    np.testing.assert_allclose(np.hypot(p["x"], p["y"]), rho, atol=1e-12)
    assert p["s"][-1] == pytest.approx(rho * math.pi / 2)
    np.testing.assert_allclose(p["t"], p["s"])  # 1 m/s without a speed
    back = [{**left[0], "sweep": -math.pi / 2, "reverse": True}]
    q = hg.poses(back, 0.01)
    assert np.all(q["gear"] == -1) and np.allclose(q["curvature"], -1.0 / rho)


def test_best_poses_plan_poses_and_hg_poses_agree():
    from hga_jax.loop.replanner import Plan

    sc = dataclasses.replace(hg.load_scenario(OPEN), speed=2.0)
    opt = hg.solve(sc)
    path = hg.evaluate_path(sc, *hg.from_chromosome(opt.upper, opt.lower, sc.n))
    best = BestPath.of(path, sc)
    a = best.poses(0.05)
    plan = Plan(path.segments, path.length, 0, "clear", np.zeros(0), np.zeros(2), 0.0,
                sc.speed, sc.start)
    for other in (plan.poses(0.05), hg.poses(sc, 0.05), hg.poses(path, 0.05, scenario=sc)):
        assert other.dtype == a.dtype
        np.testing.assert_allclose(other["s"], a["s"], atol=1e-9)
        np.testing.assert_allclose(other["t"], a["t"], atol=1e-9)
    assert a.dtype.names == COLUMNS
    assert a["t"][-1] == pytest.approx(opt.length / 2.0)
    assert (a["x"][0], a["y"][0]) == pytest.approx(sc.start[:2])
    assert (a["x"][-1], a["y"][-1]) == pytest.approx(sc.goal[:2], abs=1e-9)
    empty = BestPath.of(Path(0.0, 0, [0, 1], [1, 1]), sc).poses(0.1)  # start equal to goal
    assert len(empty) == 1 and empty["x"][0] == sc.start[0] and empty["gear"][0] == 1


def test_poses_of_a_scenario_without_path_say_why():
    # start 0.03 m inside the kept left edge, facing it: a turn away needs 0.15 m
    facing = hg.Scenario("facing", 0.09, 0.15, (0.12, 1.0, math.pi), (2.0, 1.0, 0.0),
                         np.zeros((0, 2)), np.zeros(0), hg.Field(0.0, 2.8, 0.0, 2.3, True))
    with pytest.raises(ValueError, match="^facing: no feasible path exists"):
        hg.poses(facing)


# -- 5. the compile message --------------------------------------------------------


@pytest.mark.parametrize("gens, runs, words", [
    (150, 1, "generations 0..150 in one step"),
    (50, 1, "generations 0..50 in one step"),
    (150, 1000, "generations 0..150 in 7 steps of up to 23 each (1 batch for 1,000 runs)"),
    (50, 1000, "generations 0..50 in 3 steps of up to 23 each (1 batch for 1,000 runs)"),
])
def test_the_compile_message_says_the_generations_chosen(gens, runs, words):
    st = PAPER.replace(generations=gens)
    cut = budget.plan(9, st, runs, None, 1)
    text = runner._job_words(cut.chunk, st.population, gens, cut.block, cut.batches, runs)
    assert words in text and "per step" not in text
    if cut.block > gens + 1:  # the program's block length is no number the user chose
        assert str(cut.block) not in text


def test_the_compile_message_of_a_run(tmp_path, capsys):
    assert main(["run", ROBOCUP, "--preset", "paper", "--population", "4", "--generations",
                 "150", "--runs", "1", "--no-exact", "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    (line,) = [ln for ln in err.splitlines() if ln.startswith("compiling:")]
    assert "generations 0..150 in one step" in line and "per step" not in line


# -- 6. a value from the command line is named as the option ------------------------


def test_car_and_collision_from_the_command_line_are_named(tmp_path, capsys):
    out = str(tmp_path / "o")
    problem = ("reeds-shepp: the Reeds-Shepp car needs the full collision test (the paper's "
               "judges no arc against an obstacle), got collision 'paper'")
    assert main(["run", ROBOCUP, "--car", "reeds-shepp", "--collision", "paper",
                 "--out", out]) == 2
    assert _err_lines(capsys) == [f"hga-jax: error: command line: --car: {problem} (collision "
                                  "from command line: --collision)"]
    scene = tmp_path / "rs.toml"
    scene.write_text(open(ROBOCUP).read().replace("[robot]\n", '[robot]\ncar = "reeds-shepp"\n'))
    assert main(["run", str(scene), "--collision", "paper", "--out", out]) == 2
    assert _err_lines(capsys) == [f"hga-jax: error: {scene}: robot.car: {problem} (collision "
                                  "from command line: --collision)"]
    ga = tmp_path / "ga.toml"
    ga.write_text('collision = "paper"\n')
    assert main(["run", ROBOCUP, "--car", "reeds-shepp", "--ga", str(ga), "--out", out]) == 2
    assert _err_lines(capsys) == [f"hga-jax: error: command line: --car: {problem} (collision "
                                  f"from {ga}: collision)"]
    assert not os.path.exists(out)


# -- 7. a scene without path: run refuses it as check does; a GA that finds none: 0 --


def test_a_ga_that_finds_no_feasible_path_exits_0(tmp_path, capsys):
    out = tmp_path / "o"
    assert main(["run", ROBOCUP, "--preset", "paper", "--population", "2", "--generations",
                 "0", "--runs", "1", "--seed", "0", "--quiet", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    assert "INFEASIBLE" in text
    assert json.loads((out / "result.json").read_text())["best"]["feasible"] is False


# -- 8. gaps that round to zero ----------------------------------------------------


def test_a_gap_of_rounding_is_zero_and_never_prints_minus_zero():
    from hga_jax.host.report import gap_pct

    opt = 2.221351242664794
    gaps = gap_of([opt * (1 - 2.2e-16), opt, opt * (1 + 1e-3), opt * (1 - 1e-6)],
                  [True] * 4, opt)
    assert gaps[0] == 0.0 and gaps[1] == 0.0 and gaps[2] == pytest.approx(1e-3)
    assert gaps[3] == pytest.approx(-1e-6)  # a real difference is kept
    assert gap_pct(-2.2e-16) == "0.00%" and gap_pct(-1e-6) == "0.00%"
    assert gap_pct(-1e-4) == "-0.01%" and gap_pct(0.0123) == "1.23%" and gap_pct(None) == "n/a"


# -- 9. open_field.toml says which model gives the Dubins path -----------------------


def test_open_field_names_the_model_of_the_dubins_path():
    text = open(OPEN).read()
    assert "--turns free" in text and "tight-rope" in text
    sc = hg.load_scenario(OPEN)
    assert hg.solve(sc).length == pytest.approx(2.221351, abs=1e-6)
    assert hg.solve(sc, turns="free").length == pytest.approx(2.221351, abs=1e-6)
    close = dataclasses.replace(sc, goal=(0.6, 0.5, -math.pi / 2))  # 0.1 m to the right
    tight, free = hg.solve(close), hg.solve(close, turns="free")
    assert [s["type"] for s in tight.segments] == ["arc", "line", "arc"]
    assert [s["type"] for s in free.segments] == ["arc", "arc", "arc"]
    assert free.length == pytest.approx(1.344850, abs=1e-6)
    assert tight.length == pytest.approx(2.184956, abs=1e-6)


# -- 10. SIGTERM, without a signal ---------------------------------------------------


def test_sigterm_stops_a_command_with_130(monkeypatch, capsys):
    def check(args):
        handler = signal.getsignal(signal.SIGTERM)
        assert handler is cli._terminated
        handler(signal.SIGTERM, None)

    monkeypatch.setitem(cli.COMMANDS, "check", check)
    assert main(["check", ROBOCUP]) == 130
    assert _err_lines(capsys) == ["hga-jax: terminated; nothing written"]
    assert signal.getsignal(signal.SIGTERM) is not cli._terminated  # given back
