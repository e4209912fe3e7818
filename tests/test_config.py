"""Tests of scenario loading and validation (hga_jax.host.config)."""
from __future__ import annotations

import itertools
import math
import re
from pathlib import Path

import numpy as np
import pytest

from hga_jax.running.runner import settings_for

from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.errors import ConfigError
from hga_jax.model.scenario import Scenario

SCENARIOS = Path(__file__).resolve().parents[1] / "configs" / "scenarios"

# A valid scenario (r = 0.1, rho = 0.2, so default model radius R = 0.2).
BASE = """\
name = "t"

[robot]
radius = 0.1
min_turn_radius = 0.2

[start]
x = 0.5
y = 0.4
heading_deg = 0.0

[goal]
x = 2.5
y = 1.5
heading_deg = 90.0

[field]
xmin = 0.0
xmax = 3.0
ymin = 0.0
ymax = 2.0
keep_inside = true

[[obstacles]]
x = 1.5
y = 1.0

[[obstacles]]
x = 2.0
y = 0.6
radius = 0.15
"""


def mutate(*edits: tuple[str, str]) -> str:
    """BASE with each ``(old, new)`` applied; ``old`` must occur exactly once as whole
    lines (``radius = 0.1`` does not match ``radius = 0.15``)."""
    text = BASE
    for old, new in edits:
        pattern = r"(?m)^" + re.escape(old.strip("\n")) + r"$"
        text, count = re.subn(pattern, lambda _: new.strip("\n"), text)
        assert count == 1, old
    return text


def write(tmp_path: Path, text: str, name: str = "case.toml") -> Path:
    """Write ``text`` to a TOML file under ``tmp_path``."""
    path = tmp_path / name
    path.write_text(text)
    return path


# ---------------------------------------------------------------- bundled files


def test_bundled_scenarios_all_load() -> None:
    names = sorted(p.stem for p in SCENARIOS.glob("*.toml"))
    assert {"robocup_paper", "open_field", "overlapping", "cluttered"} <= set(names)
    for path in SCENARIOS.glob("*.toml"):
        s = load_scenario(path)
        assert isinstance(s, Scenario)
        assert s.name == path.stem
        assert s.source == str(path)


def test_robocup_paper() -> None:
    s = load_scenario(SCENARIOS / "robocup_paper.toml")
    assert s.robot_radius == 0.09
    assert s.n == 9
    assert s.centres.shape == (9, 2) and s.radii.shape == (9,)
    np.testing.assert_allclose(s.radii, 0.09)  # default: the robot's radius
    # the paper's R = max(rho_min, 2r)
    np.testing.assert_allclose(s.model_radii, max(s.min_turn_radius, 0.18))
    assert s.start[2] == 0.0
    assert s.goal[2] == pytest.approx(math.radians(-26.565))
    f = s.field
    assert f is not None and f.keep_inside
    assert (f.xmin, f.xmax, f.ymin, f.ymax) == (0.0, 2.8, 0.0, 2.3)
    assert s.ga == {}


def test_open_field() -> None:
    s = load_scenario(SCENARIOS / "open_field.toml")
    assert s.n == 0
    assert s.centres.shape == (0, 2) and s.radii.shape == (0,)
    assert s.field is not None and not s.field.keep_inside
    assert s.start[2] == pytest.approx(math.pi / 2)
    assert s.goal[2] == pytest.approx(-math.pi / 4)
    assert s.delta == pytest.approx(2 * math.pi * s.min_turn_radius)


def overlaps(s: Scenario, i: int, j: int) -> bool:
    """Whether the model circles of obstacles i and j overlap."""
    d = np.linalg.norm(s.centres[i] - s.centres[j])
    return bool(d < s.model_radii[i] + s.model_radii[j])


def test_overlapping() -> None:
    s = load_scenario(SCENARIOS / "overlapping.toml")
    assert s.n == 8
    assert s.field is None
    pairs = [(i, j) for i, j in itertools.combinations(range(s.n), 2) if overlaps(s, i, j)]
    assert len(pairs) >= 3
    # a cluster of three: each pair overlaps
    assert any(
        overlaps(s, a, b) and overlaps(s, b, c) and overlaps(s, a, c)
        for a, b, c in itertools.combinations(range(s.n), 3)
    )
    np.testing.assert_allclose(s.model_radii, np.maximum(0.2, s.radii + 0.1))
    assert s.start[0] < s.centres[:, 0].min() and s.goal[0] > s.centres[:, 0].max()


def test_cluttered() -> None:
    s = load_scenario(SCENARIOS / "cluttered.toml")
    assert 25 <= s.n <= 30
    assert s.field is not None and s.field.keep_inside
    assert len(set(s.radii.tolist())) > 1  # mixed radii
    np.testing.assert_allclose(s.model_radii, np.maximum(s.min_turn_radius, s.radii + 0.09))


# ---------------------------------------------------------------- good inputs


def test_base_is_valid(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, BASE))
    assert s.n == 2
    np.testing.assert_allclose(s.radii, [0.1, 0.15])
    np.testing.assert_allclose(s.model_radii, [0.2, 0.25])
    assert s.goal == (2.5, 1.5, pytest.approx(math.pi / 2))


def test_ints_accepted_for_floats(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, mutate(("heading_deg = 90.0", "heading_deg = 90"),
                                             ("xmax = 3.0", "xmax = 3"))))
    assert isinstance(s.goal[2], float) and s.field is not None and s.field.xmax == 3.0


def test_optional_parts_absent(tmp_path: Path) -> None:
    text = BASE.split("[field]")[0]  # no field, no obstacles
    s = load_scenario(write(tmp_path, text))
    assert s.n == 0 and s.field is None and s.ga == {}


def test_point_on_model_circle_is_allowed(tmp_path: Path) -> None:
    # start (0.5, 0.4); obstacle at distance exactly R = 0.2 (tangent)
    s = load_scenario(write(tmp_path, mutate(("x = 1.5\ny = 1.0", "x = 0.7\ny = 0.4"))))
    assert s.n == 2


def test_outside_field_allowed_when_not_kept(tmp_path: Path) -> None:
    text = mutate(("keep_inside = true", "keep_inside = false"), ("x = 0.5", "x = -1.0"))
    assert load_scenario(write(tmp_path, text)).start[0] == -1.0


def test_ga_table_is_stored(tmp_path: Path) -> None:
    s = load_scenario(write(tmp_path, BASE + '\n[ga]\npopulation = 20\nselection = "tournament"\n'))
    assert s.ga == {"population": 20, "selection": "tournament"}


def test_scenario_from_dict() -> None:
    d = {
        "name": "nb",
        "robot": {"radius": 0.1, "min_turn_radius": 0.2},
        "start": {"x": 0, "y": 0, "heading_deg": 180},
        "goal": {"x": 2.0, "y": 0.0, "heading_deg": 0.0},
        "obstacles": [{"x": 1.0, "y": 0.0, "radius": 0.05}],
        "ga": {"generations": 10},
    }
    s = scenario_from_dict(d)
    assert s.source == "<dict>" and s.name == "nb" and s.n == 1
    assert s.start == (0.0, 0.0, pytest.approx(math.pi))
    np.testing.assert_allclose(s.model_radii, [0.2])
    assert s.ga == {"generations": 10}
    d["obstacles"][0]["x"] = 0.1  # now the start is inside its model circle
    with pytest.raises(ConfigError, match=r"^nb\.py: start: .*obstacles\[1\]"):
        scenario_from_dict(d, source="nb.py")
    with pytest.raises(ConfigError, match="scenario"):
        scenario_from_dict([1, 2], source="nb.py")  # type: ignore[arg-type]
    with pytest.raises(ConfigError, match=r"obstacles: must be an array"):
        scenario_from_dict({**d, "obstacles": 3}, source="nb.py")


def test_same_as_file(tmp_path: Path) -> None:
    import tomllib

    path = SCENARIOS / "robocup_paper.toml"
    a = load_scenario(path)
    b = scenario_from_dict(tomllib.loads(path.read_text()))
    assert (a.name, a.start, a.goal, a.field) == (b.name, b.start, b.goal, b.field)
    np.testing.assert_array_equal(a.centres, b.centres)


# ---------------------------------------------------------------- bad inputs

BAD = {
    # id: (TOML text, expected key in the message)
    "missing_name": (mutate(('name = "t"\n', "")), "name"),
    "empty_name": (mutate(('name = "t"', 'name = " "')), "name"),
    "name_not_string": (mutate(('name = "t"', "name = 3")), "name"),
    "missing_table": (mutate(("[start]\nx = 0.5\ny = 0.4\nheading_deg = 0.0\n", "")), "start"),
    "missing_robot_radius": (mutate(("radius = 0.1\n", "")), "robot.radius"),
    "missing_heading": (mutate(("heading_deg = 90.0\n", "")), "goal.heading_deg"),
    "missing_obstacle_x": (mutate(("\nx = 2.0\n", "\n")), "obstacles[2].x"),
    "missing_field_ymax": (mutate(("ymax = 2.0\n", "")), "field.ymax"),
    "unknown_top": ("colour = 1\n" + BASE, "colour"),
    "unknown_robot": (mutate(("radius = 0.1\n", "radius = 0.1\nmass = 2.0\n")), "robot.mass"),
    "speed_zero": (mutate(("radius = 0.1\n", "radius = 0.1\nspeed = 0.0\n")), "robot.speed"),
    "speed_negative": (mutate(("radius = 0.1\n", "radius = 0.1\nspeed = -1\n")), "robot.speed"),
    "speed_inf": (mutate(("radius = 0.1\n", "radius = 0.1\nspeed = inf\n")), "robot.speed"),
    "velocity_nan": (mutate(("x = 1.5\n", "x = 1.5\nvx = nan\n")), "obstacles[1].vx"),
    "velocity_text": (mutate(("x = 1.5\n", "x = 1.5\nvy = \"fast\"\n")), "obstacles[1].vy"),
    "unknown_start": (mutate(("heading_deg = 0.0", "heading = 0.0")), "start.heading"),
    "unknown_obstacle": (mutate(("x = 1.5\n", "x = 1.5\nz = 0.0\n")), "obstacles[1].z"),
    "unknown_field": (mutate(("keep_inside = true", "keep = true")), "field.keep"),
    "string_for_number": (mutate(("x = 0.5", 'x = "0.5"')), "start.x"),
    "bool_for_number": (mutate(("y = 1.5", "y = true")), "goal.y"),
    "string_for_bool": (mutate(("keep_inside = true", 'keep_inside = "yes"')), "field.keep_inside"),
    "int_for_bool": (mutate(("keep_inside = true", "keep_inside = 1")), "field.keep_inside"),
    "table_for_number": (mutate(("y = 0.4", "y = {v = 1}")), "start.y"),
    "nan": (mutate(("min_turn_radius = 0.2", "min_turn_radius = nan")), "robot.min_turn_radius"),
    "inf": (mutate(("x = 0.5", "x = inf")), "start.x"),
    "minus_inf": (mutate(("y = 1.0", "y = -inf")), "obstacles[1].y"),
    "negative_robot_radius": (mutate(("radius = 0.1", "radius = -0.1")), "robot.radius"),
    "zero_robot_radius": (mutate(("radius = 0.1", "radius = 0")), "robot.radius"),
    "zero_turn_radius": (mutate(("min_turn_radius = 0.2", "min_turn_radius = 0.0")),
                         "robot.min_turn_radius"),
    "negative_obstacle_radius": (mutate(("radius = 0.15", "radius = -0.15")),
                                 "obstacles[2].radius"),
    "zero_obstacle_radius": (mutate(("radius = 0.15", "radius = 0.0")), "obstacles[2].radius"),
    "start_inside": (mutate(("x = 2.0\ny = 0.6", "x = 0.6\ny = 0.5")), "obstacles[2]"),
    "goal_inside": (mutate(("x = 1.5\ny = 1.0", "x = 2.4\ny = 1.4")), "goal: point (2.5, 1.5)"),
    "same_centre": (mutate(("x = 2.0\ny = 0.6", "x = 1.5\ny = 1.0")),
                    "obstacles[2]: same centre as obstacles[1]"),
    "start_outside_field": (mutate(("x = 0.5", "x = 0.05")), "start"),
    "goal_outside_field": (mutate(("y = 1.5", "y = 1.95")), "goal"),
    "xmin_ge_xmax": (mutate(("xmin = 0.0", "xmin = 3.0")), "field.xmax"),
    "ymin_ge_ymax": (mutate(("ymax = 2.0", "ymax = -1.0")), "field.ymax"),
    "field_too_small": (mutate(("ymax = 2.0", "ymax = 0.15")), "field"),
    "ga_population": (BASE + "\n[ga]\npopulation = 1\n", "ga.population"),
    "ga_selection": (BASE + '\n[ga]\nselection = "foo"\n', "ga.selection"),
    "ga_unknown": (BASE + "\n[ga]\nmutation = 0.1\n", "ga.mutation"),
    "ga_type": (BASE + '\n[ga]\npc_upper = "high"\n', "ga.pc_upper"),
    "ga_ends_of_best": (BASE + "\n[ga]\nends_of_best = 50\n", "ga.ends_of_best"),
    "ga_ends_of_best_type": (BASE + "\n[ga]\nends_of_best = 1.5\n", "ga.ends_of_best"),
    "ga_straight_of_best": (BASE + "\n[ga]\nstraight_of_best = 50\n", "ga.straight_of_best"),
    "ga_straight_of_best_sign": (BASE + "\n[ga]\nstraight_of_best = -1\n",
                                 "ga.straight_of_best"),
    "ga_tight_of_best": (BASE + "\n[ga]\nstraight_of_best = 30\ntight_of_best = 20\n",
                         "ga.tight_of_best"),
    "ga_tight_of_best_type": (BASE + "\n[ga]\ntight_of_best = 1.5\n", "ga.tight_of_best"),
    "syntax_error": (mutate(("radius = 0.1", "radius = = 0.1")), "line 4"),
    "duplicate_key": (mutate(("x = 0.5\n", "x = 0.5\nx = 0.6\n")), "line"),
}


@pytest.mark.parametrize("text, key", BAD.values(), ids=list(BAD))
def test_bad_input(tmp_path: Path, text: str, key: str) -> None:
    path = write(tmp_path, text, "bad_case.toml")
    with pytest.raises(ConfigError) as info:
        sc = load_scenario(path)
        # A [ga] value is checked with every layer of settings merged (flags may change
        # it): here, the file's table over the defaults, as a run without flags does.
        settings_for(sc)
    msg = str(info.value)
    assert msg.startswith(f"{path}: ")
    assert key in msg
    assert "\n" not in msg and "\r" not in msg


def test_start_inside_message(tmp_path: Path) -> None:
    path = write(tmp_path, mutate(("x = 2.0\ny = 0.6", "x = 0.6\ny = 0.5")))
    with pytest.raises(ConfigError, match=r": start: point \(0\.5, 0\.4\) is inside the model "
                       r"circle of obstacles\[2\] \(distance 0\.141421 < R 0\.25\)$"):
        load_scenario(path)


def test_missing_file(tmp_path: Path) -> None:
    path = tmp_path / "nowhere.toml"
    with pytest.raises(ConfigError) as info:
        load_scenario(path)
    msg = str(info.value)
    assert msg.startswith(f"{path}: ") and "cannot read" in msg and "\n" not in msg


def test_directory_and_binary_file(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="cannot read"):
        load_scenario(tmp_path)
    bad = tmp_path / "bin.toml"
    bad.write_bytes(b"name = \"\xff\"\n")
    with pytest.raises(ConfigError, match=r"bin\.toml: file: not UTF-8"):
        load_scenario(bad)


def test_config_error_is_value_error(tmp_path: Path) -> None:
    with pytest.raises(ValueError):
        load_scenario(write(tmp_path, "name = 1\n"))
