"""Peers inside the study: solver configurations, their cells judged by the model,
OMPL paths that clip an obstacle, skipped peers, anytime traces."""
import math
import os

import numpy as np
import pytest

from hga_jax.errors import ConfigError, PeerCrashed
from hga_jax.host.config import scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.study import anytime, solvers
from hga_jax.study.config import Config, Study, load_study
from hga_jax.study.run import run_study
from hga_jax.study.scenes import Scene
from hga_jax.search.settings import GASettings

PAPER_SCENE = os.path.abspath("configs/scenarios/robocup_paper.toml")


def _line_scene(obstacle_y: float):
    """Start (0, 0) and goal (2, 0), both heading east; one obstacle at (0.6, y) with
    model radius max(rho, r + robot) = 0.15 m; no field."""
    d = {"name": f"line_{obstacle_y}", "robot": {"radius": 0.05, "min_turn_radius": 0.15},
         "start": {"x": 0.0, "y": 0.0, "heading_deg": 0.0},
         "goal": {"x": 2.0, "y": 0.0, "heading_deg": 0.0},
         "obstacles": [{"x": 0.6, "y": obstacle_y, "radius": 0.05}]}
    return scenario_from_dict(d, d["name"])


def _study(tmp_path, runs=1):
    return Study("t", str(tmp_path / "t.toml"), 0, runs, [], [], [])


def _ompl_config(runs=1):
    return Config("BIT*", GASettings(), "ompl", "BITstar", 0.1, runs)


def test_an_ompl_path_that_clips_an_obstacle_counts_infeasible(tmp_path, monkeypatch):
    """The straight line from start to goal passes 0.1 m from an obstacle whose model
    radius is 0.15 m: a planner that checked too few states would return it; the
    cell judges it by the model and counts the run infeasible. Beside the obstacle
    (0.3 m away) the same line is feasible and exactly 2 m long."""
    from hga_jax.peers import ompl_planner

    def straight(sc, planner, time_limit, seed=0):
        poses = [tuple(sc.start), tuple(sc.goal)]
        return {"checkpoints": [(0.01, None), (0.05, poses)], "ompl_length": 2.0,
                "checks": 7, "seconds": 0.05}

    monkeypatch.setattr(ompl_planner, "plan", straight)
    from hga_jax.peers import isolated  # in this process, where the patch is

    monkeypatch.setattr(isolated, "call", lambda fn, *args, **kw: fn(*args))
    for y, feasible in ((0.1, False), (0.3, True)):
        sc = _line_scene(y)
        doc = solvers.run_cell(_study(tmp_path), _ompl_config(), Scene(sc.name, "f", "", sc, ""))
        cols = doc["columns"]
        assert cols["feasible"] == [feasible]
        opt = solve(sc).length
        if feasible:
            assert cols["length"][0] == pytest.approx(2.0, abs=1e-12)
            assert opt == pytest.approx(2.0, abs=1e-9)
            assert cols["gap"][0] == pytest.approx(0.0, abs=1e-9) and cols["hit"] == [True]
            assert cols["time_hit"] == [0.05]
        else:
            assert cols["violations"][0] >= 1 and cols["gap"] == [None]
            assert cols["hit"] == [False] and cols["time_hit"] == [None]
            assert opt > 2.0  # the optimum goes round the obstacle
        assert doc["paths"][0] == [list(sc.start), list(sc.goal)]


def test_a_peer_that_crashes_its_process_is_run_again_in_a_fresh_one(tmp_path):
    """OMPL's BIT* crashes its process now and then: a study's OMPL cells run in a
    worker process, a call whose worker dies is made again in a fresh one, and a peer
    that dies again is a one-line error, not the end of the study's process."""
    from _crashing_peer import crash_always, crash_once

    from hga_jax.peers import isolated

    marker = str(tmp_path / "crashed")
    pid = isolated.call(crash_once, marker, what="the test peer")
    assert os.path.exists(marker) and pid != os.getpid()
    assert isolated.call(crash_once, marker) == pid  # the fresh worker is kept
    with pytest.raises(PeerCrashed, match=r"^the test peer crashed 2 times in a row \(its "
                                          r"process died; the finished cells are kept"):
        isolated.call(crash_always, what="the test peer")
    assert isolated.call(crash_once, marker) != pid  # and replaced after a death


def test_ompl_accepts_the_clipping_motion_that_the_model_rejects():
    """OMPL itself, at a coarse validity-checking resolution, accepts the straight
    motion of the test above; the project's model does not."""
    pytest.importorskip("ompl")
    from ompl import base as ob

    from hga_jax.peers.judge import judge_poses

    sc = _line_scene(0.1)
    space = ob.DubinsStateSpace(0.15, False)
    box = ob.RealVectorBounds(2)
    box.setLow(-1.0)
    box.setHigh(3.0)
    space.setBounds(box)
    si = ob.SpaceInformation(space)
    si.setStateValidityChecker(lambda s: (s.getX() - 0.6) ** 2 + (s.getY() - 0.1) ** 2
                               >= 0.15 ** 2)
    si.setStateValidityCheckingResolution(0.25)  # states 1 m apart along the line
    si.setup()
    a, b = space.allocState(), space.allocState()
    for st, (x, y, h) in ((a, sc.start), (b, sc.goal)):
        st.setX(x)
        st.setY(y)
        st.setYaw(h)
    assert si.checkMotion(a, b)  # OMPL's sampled check misses the obstacle
    j = judge_poses(sc, [sc.start, sc.goal])
    assert not j.feasible and j.length == pytest.approx(space.distance(a, b), abs=1e-12)


def _peer_study(tmp_path, ompl=True, ga=True):
    lines = [
        'name = "peers"', "seed = 0", "runs = 3", "cpu_devices = 1",
        f'scenarios = ["{PAPER_SCENE}"]', "[ga]", "generations = 4"]
    if ga:
        lines += ['[[configs]]', 'label = "HGA paper"',
                  '[[configs]]', 'label = "random"', 'solver = "random"', "evaluations = 60",
                  '[[configs]]', 'label = "HGA alone"', "batch = false", "runs = 2"]
    lines += [
        '[[configs]]', 'label = "exact"', 'solver = "exact"',
        '[[configs]]', 'label = "DEAP"', 'solver = "deap"', "runs = 2",
    ]
    if ompl:
        lines += ['[[configs]]', 'label = "BIT*"', 'solver = "ompl"', 'planner = "BITstar"',
                  "time_limit = 0.2", "runs = 2"]
    path = tmp_path / "peers.toml"
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_a_study_with_every_solver_judges_ompl_paths_by_the_model(tmp_path):
    """HGA (batched and alone), random search, the exact solver, DEAP and OMPL's BIT*
    in one study: one summary table holds them all; each OMPL row's length is the
    model's length of its stored waypoints, close to OMPL's own; a second start runs
    nothing."""
    pytest.importorskip("ompl")
    pytest.importorskip("deap")
    from hga_jax.peers.judge import judge_poses

    path = _peer_study(tmp_path)
    out = run_study(path, out=str(tmp_path / "out"), progress=False)
    assert out.skipped == {}
    sc = out.docs[0]  # noqa: F841
    from hga_jax.host.config import load_scenario

    scene = load_scenario(PAPER_SCENE)
    opt = solve(scene).length
    rows = {r["config"]: r for r in out.summary}
    assert set(rows) == {"HGA paper", "random", "HGA alone", "exact", "DEAP", "BIT*"}
    assert {r["group"] for r in out.summary} == {scene.name}  # the scene file's own group
    assert rows["exact"]["hit_rate"] == 1.0 and rows["exact"]["runs"] == 1
    assert rows["HGA alone"]["runs"] == 2 and rows["DEAP"]["runs"] == 2
    tab = out.table
    for r in tab[tab["config"] == "HGA paper"].itertuples():
        assert r.time_s > 0 and r.evaluations == 50 * 5
    ompl = next(d for d in out.docs if d["config"] == "BIT*")
    assert ompl["solver"] == "ompl" and ompl["evaluations_per_run"] is None
    solved = 0
    for k, poses in enumerate(ompl["paths"]):
        if poses is None:
            continue
        solved += 1
        j = judge_poses(scene, poses)
        assert ompl["columns"]["length"][k] == pytest.approx(j.length, abs=1e-12)
        assert j.length == pytest.approx(ompl["columns"]["ompl_length"][k], rel=1e-6)
        assert ompl["columns"]["feasible"][k] == j.feasible
        if j.feasible:
            assert ompl["columns"]["gap"][k] == pytest.approx(j.length / opt - 1, abs=1e-12)
        assert 0 < ompl["columns"]["time_s"][k] < 1.0
    assert solved >= 1
    md = open(os.path.join(out.folder, "summary.md")).read()
    for name in ("HGA paper", "random", "DEAP", "BIT*", "exact", "shorter than optimum"):
        assert name in md
    for fig in ("anytime.png", "time_ecdf.png"):
        assert os.path.getsize(os.path.join(out.folder, "figures", fig)) > 10_000
    again = run_study(path, out=str(tmp_path / "out"), progress=False, figures=False)
    assert again.cells_run == 0 and again.cells_reused == len(out.docs)


def test_a_peer_whose_package_is_missing_is_skipped_in_one_line(tmp_path, monkeypatch, capsys):
    import hga_jax.peers as peers

    monkeypatch.setattr(peers, "NEEDS", {"deap": "no_such_package_hga_jax_test",
                                         "ompl": "no_such_package_hga_jax_test"})
    path = _peer_study(tmp_path, ga=False)  # no GA: nothing to compile
    out = run_study(path, out=str(tmp_path / "out"), progress=False, figures=False)
    assert set(out.skipped) == {"DEAP", "BIT*"}
    err = [line for line in capsys.readouterr().err.splitlines() if "skipped" in line]
    assert err == ["skipped 'DEAP', 'BIT*': no_such_package_hga_jax_test is not installed "
                   "(pip install 'hga-jax[compare]')"]
    assert {r["config"] for r in out.summary} == {"exact"}
    assert "Skipped `DEAP`" in open(os.path.join(out.folder, "summary.md")).read()


@pytest.mark.parametrize("table, key, words", [
    ('solver = "ompl"\ntime_limit = 1.0', "configs[1].planner", "missing key"),
    ('solver = "ompl"\nplanner = "RRT"\ntime_limit = 1.0', "configs[1].planner", "must be one of"),
    ('solver = "ompl"\nplanner = "BITstar"\ntime_limit = -1', "configs[1].time_limit", "seconds"),
    ('solver = "ompl"\nplanner = "BITstar"\ntime_limit = 1\npopulation = 9',
     "configs[1].population", "takes no GA settings"),
    ('solver = "deap"\nselection = "tournament"', "configs[1].selection", "paper's operators"),
    ('solver = "random"', "configs[1].evaluations", "missing key"),
    ('solver = "random"\nevaluations = 10\ngenerations = 3', "configs[1].generations",
     "evaluations instead"),
    ('solver = "exact"\nbatch = false', "configs[1].batch", "only for solver hga"),
    ('solver = "simplex"', "configs[1].solver", "must be one of hga, random, exact"),
    ('preset = "fast"', "configs[1].preset", "must be one of"),
    ('runs = 0', "configs[1].runs", ""),
])
def test_bad_solver_configurations_are_one_line_errors(tmp_path, table, key, words):
    path = tmp_path / "bad.toml"
    path.write_text(f'name = "bad"\nruns = 3\nscenarios = ["{PAPER_SCENE}"]\n'
                    f"[[configs]]\n{table}\n")
    with pytest.raises(ConfigError) as e:
        load_study(str(path))
    msg = str(e.value)
    assert msg.startswith(f"{path}: {key}: ") and words in msg and "\n" not in msg


def test_the_baselines_study_names_every_peer():
    full = load_study("configs/studies/baselines.toml")
    quick = load_study("configs/studies/baselines.toml", quick=True)
    assert {c.solver for c in full.configs} == {"hga", "random", "exact", "deap", "ompl"}
    assert {c.solver for c in quick.configs} == {"hga", "random", "exact", "deap", "ompl"}
    assert {c.planner for c in full.configs if c.solver == "ompl"} >= {"BITstar", "RRTstar"}
    assert full.families[0].obstacles == (9, 15, 25) and full.cpu_devices == 1
    presets = {c.label: c.settings for c in full.configs if c.solver == "hga"}
    assert presets["HGA recommended, batched"].selection == "tournament"
    assert presets["HGA paper, batched"] == GASettings()
    assert any(not c.batch for c in quick.configs)


def test_anytime_quartiles_and_first_times_by_hand():
    # Two runs: run 0 holds gap 0.5 from 1 ms and 0 from 10 ms; run 1 holds nothing
    # feasible until 0.1 s, then 0.02.
    times = np.array([[1e-3, 1e-1], [1e-2, 1e-1]])
    gaps = np.array([[0.5, math.inf], [0.0, 0.02]])
    q = np.array(anytime.quartiles(times, gaps))
    at = lambda t: int(np.argmin(np.abs(anytime.GRID - t)))  # noqa: E731
    assert np.all(np.isinf(q[:, at(1e-4)]))  # nothing yet
    assert q[0, at(2e-3)] == 0.5 and np.isinf(q[2, at(2e-3)])
    assert q[0, at(0.5)] == 0.0 and q[2, at(0.5)] == 0.02
    assert anytime.first_time(times, gaps, 0.01) == [1e-2, None]
    assert anytime.first_time(times, gaps, 0.05) == [1e-2, 1e-1]
    assert anytime.first_time(times, gaps, 0.0) == [1e-2, None]
    # a negative gap (shorter than the optimum) reaches every target
    assert anytime.first_time(np.array([0.3]), np.array([[-0.2]]), 0.0) == [0.3]
