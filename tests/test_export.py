"""Poses for a robot: the sampled path (hga_jax.host.poses), ``hga-jax export``, and
start and goal given on the command line."""
import contextlib
import csv
import io
import json
import math

import numpy as np
import pytest

from hga_jax.host import poses
from hga_jax.host.cli import main
from hga_jax.host.config import load_scenario

ROBOCUP = "configs/scenarios/robocup_paper.toml"
QUERY = ["--start", "0.3,1.8,0", "--goal", "2.3,0.6,-90"]  # a start and goal of the field
TWO_PI = 2 * math.pi


def _cli(argv):
    """main(argv) with stdout and stderr captured: (status, out, err)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def _angle_gap(a, b):
    """|a - b| modulo 2 pi (rad)."""
    d = np.mod(np.asarray(a) - np.asarray(b), TWO_PI)
    return np.minimum(d, TWO_PI - d)


# A quarter circle to the left (radius 0.5) from (0, 0) heading +x, then 1 m of line
# heading +y.
R1 = 0.5
QUARTER_LINE = [
    {"type": "arc", "center": [0.0, R1], "radius": R1, "start_angle": -math.pi / 2,
     "sweep": math.pi / 2},
    {"type": "line", "start": [R1, R1], "end": [R1, R1 + 1.0]},
]


def _quarter_line(s):
    """(x, y, heading, curvature) of QUARTER_LINE at s (the piece starting at s)."""
    bend = R1 * math.pi / 2
    if s < bend:
        a = -math.pi / 2 + s / R1
        return R1 * math.cos(a), R1 + R1 * math.sin(a), a + math.pi / 2, 1 / R1
    return R1, R1 + (s - bend), math.pi / 2, 0.0


# A Dubins RSL path with radius 1: right (CW) a quarter turn from (0, 0) heading +x,
# 2 m down, left (CCW) a quarter turn to (2, -4) heading +x.
RSL = [
    {"type": "arc", "center": [0.0, -1.0], "radius": 1.0, "start_angle": math.pi / 2,
     "sweep": -math.pi / 2},
    {"type": "line", "start": [1.0, -1.0], "end": [1.0, -3.0]},
    {"type": "arc", "center": [2.0, -3.0], "radius": 1.0, "start_angle": math.pi,
     "sweep": math.pi / 2},
]


def _rsl(s):
    q = math.pi / 2
    if s < q:
        a = math.pi / 2 - s
        return math.cos(a), -1 + math.sin(a), a - math.pi / 2, -1.0
    if s < q + 2:
        return 1.0, -1 - (s - q), -math.pi / 2, 0.0
    a = math.pi + min(s - q - 2, q)
    return 2 + math.cos(a), -3 + math.sin(a), a + math.pi / 2, 1.0


CASES = {  # name: segments, analytic pose, spacing, expected count, start, goal
    # 18 multiples of 0.1 below 1.785, less s = 0 (the start), plus 3 boundaries
    "quarter-line": (QUARTER_LINE, _quarter_line, 0.1, 20, (0, 0, 0), (R1, R1 + 1, math.pi / 2)),
    # 52 multiples of 0.1 below 5.142, less s = 0, plus 4 boundaries
    "dubins-rsl": (RSL, _rsl, 0.1, 55, (0, 0, 0), (2, -4, 0)),
    # 8 multiples of 0.25 below 1.785, less s = 0, plus 3 boundaries
    "quarter-line-coarse": (QUARTER_LINE, _quarter_line, 0.25, 10, (0, 0, 0),
                            (R1, R1 + 1, math.pi / 2)),
}


@pytest.mark.parametrize("name", CASES)
def test_sampled_poses_follow_the_analytic_path(name):
    segments, exact, spacing, count, start, goal = CASES[name]
    table = poses.sample(segments, spacing)
    length = sum(s["radius"] * abs(s["sweep"]) if s["type"] == "arc"
                 else math.dist(s["start"], s["end"]) for s in segments)
    assert table.shape == (count, 6) and table.dtype == np.float64
    s = table[:, 0]
    assert s[0] == 0.0 and abs(s[-1] - length) <= 1e-9
    steps = np.diff(s)
    assert (steps > 0).all() and (steps <= spacing + 1e-9).all()
    bounds = np.cumsum([0.0] + [math.dist(g["start"], g["end"]) if g["type"] == "line"
                                else g["radius"] * abs(g["sweep"]) for g in segments])
    assert all(np.min(np.abs(s - b)) <= 1e-12 for b in bounds)  # every boundary is a pose
    assert np.abs(table[0, 1:3] - start[:2]).max() <= 1e-9
    assert _angle_gap(table[0, 3], start[2]) <= 1e-9
    assert np.abs(table[-1, 1:3] - goal[:2]).max() <= 1e-9
    assert _angle_gap(table[-1, 3], goal[2]) <= 1e-9
    want = np.array([exact(v) for v in s[:-1]])
    assert np.abs(table[:-1, 1:3] - want[:, :2]).max() <= 1e-12
    assert _angle_gap(table[:-1, 3], want[:, 2]).max() <= 1e-12
    assert ((table[:, 3] > -math.pi) & (table[:, 3] <= math.pi)).all()
    assert (table[:-1, 4] == want[:, 3]).all()  # +-1/r on arcs, exactly 0 on lines
    last = segments[-1]
    assert table[-1, 4] == (0.0 if last["type"] == "line" else math.copysign(1 / last["radius"],
                                                                             last["sweep"]))


def test_boundaries_win_over_multiples_and_degenerate_input():
    line = [{"type": "line", "start": [0.0, 0.0], "end": [0.0, -1.0]}]
    table = poses.sample(line, 0.25)
    assert table[:, 0].tolist() == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert np.allclose(table[:, 3], -math.pi / 2) and (table[:, 4] == 0).all()
    west = poses.sample([{"type": "line", "start": [0.0, 0.0], "end": [-1.0, 0.0]}], 2.0)
    assert west[:, 3].tolist() == [math.pi, math.pi]  # (-pi, pi]: west is +pi
    near = poses.sample(line, 1.0 - 1e-10)  # a multiple within 1e-9 of the end gives way
    assert near[:, 0].tolist() == [0.0, 1.0]
    alone = poses.sample([], 0.1, start=(1.0, 2.0, 1.5 * math.pi))  # start equal to goal
    assert alone.shape == (1, 6) and alone[0, :3].tolist() == [0.0, 1.0, 2.0]
    assert alone[0, 3] == pytest.approx(-math.pi / 2, abs=1e-12) and alone[0, 4] == 0.0
    with pytest.raises(ValueError, match="start"):
        poses.sample([], 0.1)
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ValueError, match="spacing"):
            poses.sample(line, bad)


def test_writers_round_trip(tmp_path):
    table = poses.sample(RSL, 0.3)
    poses.write_csv(str(tmp_path / "p.csv"), table)
    poses.write_json(str(tmp_path / "p.json"), table, {"length": 5.0})
    rows = list(csv.reader((tmp_path / "p.csv").open()))
    assert tuple(rows[0]) == poses.COLUMNS
    assert np.array([[float(v) for v in r] for r in rows[1:]]).tolist() == table.tolist()
    doc = json.loads((tmp_path / "p.json").read_text())
    assert doc["length"] == 5.0 and doc["columns"] == list(poses.COLUMNS)
    assert set(doc["units"]) == set(poses.COLUMNS) and doc["poses"] == table.tolist()


# ------------------------------------------------------------------ the command line


@pytest.fixture(scope="module")
def exact_result(tmp_path_factory):
    out = tmp_path_factory.mktemp("export") / "D"
    code, _, err = _cli(["exact", ROBOCUP, "--out", str(out)])
    assert code == 0, err
    return out


def test_export_writes_poses_of_the_optimum(exact_result):
    res = exact_result / "result.json"
    code, printed, err = _cli(["export", str(res), "--spacing", "0.05"])
    assert code == 0 and err == ""
    best = json.loads(res.read_text())["best"]
    n = len(poses.sample(best["segments"], 0.05))
    assert printed == (f"wrote {exact_result / 'poses.csv'}, {exact_result / 'poses.json'}: "
                       f"{n} poses every 0.05 m along the best path (2.245430 m)\n")
    lines = (exact_result / "poses.csv").read_text().splitlines()
    assert lines[0] == "s,x,y,heading,curvature,gear" and len(lines) == n + 1
    assert n > best["length"] / 0.05
    table = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    sc = load_scenario(ROBOCUP)
    assert abs(table[-1, 0] - best["length"]) <= 1e-9
    assert np.abs(table[0, 1:3] - sc.start[:2]).max() <= 1e-9
    assert _angle_gap(table[0, 3], sc.start[2]) <= 1e-9
    assert np.abs(table[-1, 1:3] - sc.goal[:2]).max() <= 1e-9
    assert _angle_gap(table[-1, 3], sc.goal[2]) <= 1e-9
    assert set(np.round(np.abs(table[:, 4]), 9)) <= {0.0, round(1 / 0.18, 9), round(1 / 0.15, 9)}
    doc = json.loads((exact_result / "poses.json").read_text())
    assert doc["poses"] == table.tolist() and doc["count"] == n and doc["spacing"] == 0.05
    assert doc["length"] == best["length"] and doc["feasible"]
    assert doc["scenario"] == "robocup_paper"

    code, _, err = _cli(["export", str(res), "--spacing", "0.05"])  # refused: files exist
    assert code == 2 and err.count("\n") == 1 and "poses.csv: already exists" in err
    assert "--force" in err
    assert _cli(["export", str(res), "--spacing", "0.1", "--force"])[0] == 0
    assert len((exact_result / "poses.csv").read_text().splitlines()) < n


@pytest.mark.parametrize("spacing", ["0", "-0.1", "abc", "nan", "inf", "1e-12"])
def test_bad_spacing_is_one_line(exact_result, tmp_path, spacing):
    code, _, err = _cli(["export", str(exact_result / "result.json"), f"--spacing={spacing}",
                         "--out", str(tmp_path / "p")])
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("hga-jax: error: command line: --spacing: ")
    assert not (tmp_path / "p").exists()


def test_export_refuses_a_path_that_does_not_end_at_the_goal(exact_result, tmp_path):
    data = json.loads((exact_result / "result.json").read_text())
    data["best"]["segments"] = data["best"]["segments"][:-1]
    bad = tmp_path / "result.json"
    bad.write_text(json.dumps(data))
    code, _, err = _cli(["export", str(bad)])
    assert code == 2 and err.count("\n") == 1 and f"{bad}: best: segments: " in err
    assert not (tmp_path / "poses.csv").exists()
    code, _, err = _cli(["export", str(exact_result / "result.json"), "--run", "0",
                         "--out", str(tmp_path)])
    assert code == 2 and "per_run: no run 0 in this file (no runs)" in err


def test_start_and_goal_flags_replace_the_files_poses(tmp_path):
    code, _, err = _cli(["exact", ROBOCUP, *QUERY, "--out", str(tmp_path / "flags")])
    assert code == 0, err
    text = open(ROBOCUP).read()
    text = text.replace("x = 0.30\ny = 0.60\nheading_deg = 0.0",
                        "x = 0.3\ny = 1.8\nheading_deg = 0")
    text = text.replace("x = 2.30\ny = 1.40\nheading_deg = -26.565",
                        "x = 2.3\ny = 0.6\nheading_deg = -90")
    scen = tmp_path / "query.toml"
    scen.write_text(text)
    assert load_scenario(scen).start == (0.3, 1.8, 0.0)
    assert _cli(["exact", str(scen), "--out", str(tmp_path / "file")])[0] == 0
    flags, file = (json.loads((tmp_path / d / "result.json").read_text())
                   for d in ("flags", "file"))
    assert flags["best"]["length"] == file["best"]["length"]
    assert abs(flags["best"]["length"] - 2.245430) > 0.01  # another optimum than the file's
    assert flags["best"]["segments"] == file["best"]["segments"]
    assert flags["scenario"]["definition"]["start"] == {"x": 0.3, "y": 1.8, "heading_deg": 0.0}
    # export checks the ends against the poses the result was solved for
    assert _cli(["export", str(tmp_path / "flags" / "result.json")])[0] == 0
    code, printed, _ = _cli(["check", ROBOCUP, *QUERY])
    assert code == 0 and printed.startswith(f"{ROBOCUP}: ok")


@pytest.mark.parametrize("flags, message", [
    (["--start", "1.2,0.8,0"], "command line: --start: point (1.2, 0.8) is inside the model "
                               "circle of obstacles[4]"),
    (["--goal", "2.75,1,0"], "command line: --goal: point (2.75, 1) is outside the field"),
    (["--goal", "nan,1,0"], "command line: --goal.x: must be finite, got nan"),
    (["--start", "1,2"], "command line: --start: must be X,Y,HEADING_DEG"),
    (["--start", "a,b,c"], "command line: --start: must be X,Y,HEADING_DEG"),
])
def test_bad_start_or_goal_is_one_line(tmp_path, flags, message):
    for command in (["exact", ROBOCUP, "--out", str(tmp_path / "o")], ["check", ROBOCUP]):
        code, printed, err = _cli([*command, *flags])
        assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
        assert err.startswith(f"hga-jax: error: {message}"), err
    assert not (tmp_path / "o").exists()


def test_run_with_flags_then_export_a_run(tmp_path):
    """One tiny GA run (one compiled program) from the command line's poses; run 1's
    path exported beside the best one, and a replaced result takes its poses along."""
    out = tmp_path / "run"
    code, _, err = _cli(["run", ROBOCUP, *QUERY, "--runs", "2", "--generations", "0",
                         "--population", "10", "--quiet", "--preset", "paper", "--out", str(out)])
    assert code == 0, err
    data = json.loads((out / "result.json").read_text())
    assert data["scenario"]["definition"]["goal"] == {"x": 2.3, "y": 0.6, "heading_deg": -90.0}
    code, printed, err = _cli(["export", str(out / "result.json"), "--run", "1", "--no-cache"])
    assert code == 0, err
    assert f"{out / 'poses_run1.csv'}, {out / 'poses_run1.json'}: " in printed
    assert "along the best path of run 1 (" in printed
    doc = json.loads((out / "poses_run1.json").read_text())
    run1 = next(r for r in data["per_run"] if r["run"] == 1)
    assert doc["run"] == 1 and doc["length"] == pytest.approx(run1["length"], abs=1e-9)
    assert doc["feasible"] == run1["feasible"]
    assert _cli(["export", str(out / "result.json")])[0] == 0
    assert {p.name for p in out.iterdir()} >= {"poses.csv", "poses.json", "poses_run1.csv"}
    # a new result in the folder replaces the earlier one's poses too
    assert _cli(["exact", ROBOCUP, "--out", str(out)])[0] == 2
    assert _cli(["exact", ROBOCUP, "--out", str(out), "--force"])[0] == 0
    assert sorted(p.name for p in out.iterdir()) == ["result.json"]
