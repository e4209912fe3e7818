"""User operators from a plugin file: the example plugin through ``hga-jax run --plugin``,
a ``--ga`` file's ``plugins``, a study's ``plugins``, and one-line errors for bad plugins."""
import csv
import json
import re
import shutil
import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.host.cli import main
from hga_jax.search import registry

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "configs" / "plugins" / "example_ops.py"
ROBOCUP = str(ROOT / "configs" / "scenarios" / "robocup_paper.toml")
SMALL = ["--preset", "paper", "--runs", "8", "--population", "8", "--generations", "6",
         "--quiet", "--no-exact", "--no-cache"]


@pytest.fixture
def plugins():
    """Plugins are imported afresh in the test, and what they register is gone after it."""
    def forget():
        for name in [m for m in sys.modules if m.startswith("hga_jax_plugin_")]:
            del sys.modules[name]

    forget()
    with registry.isolated():
        yield
    forget()


def _run(tmp_path, name, *flags) -> dict:
    out = tmp_path / name
    assert main(["run", ROBOCUP, *SMALL, "--out", str(out), *flags]) == 0
    return json.loads((out / "result.json").read_text())


def _runs(doc) -> list[tuple]:
    return [(r["length"], r["upper"], r["lower"]) for r in doc["per_run"]]


def test_example_operators_follow_their_definitions(plugins):
    from hga_jax import validation

    validation.load_plugin(str(EXAMPLE))
    cross = registry.get("perm_crossover", "one_point_order")
    a, b = jnp.arange(9, dtype=jnp.int32), jnp.array([8, 2, 6, 0, 4, 1, 7, 3, 5], jnp.int32)
    cuts = set()
    for i in range(20):
        c1, c2 = (np.asarray(c) for c in cross(jax.random.key(i), a, b))
        assert sorted(c1) == sorted(c2) == list(range(9))
        cut = next(c for c in range(10) if list(c1[:c]) == list(a[:c]) and
                   list(c1[c:]) == [g for g in b.tolist() if g not in a[:c].tolist()])
        assert list(c2[:cut]) == list(b[:cut])
        cuts.add(cut)
    assert len(cuts) > 3  # the cut is drawn
    select = registry.get("selection", "truncation")
    fitness = jnp.array([0.5, 0.9, 0.1, 0.7, 0.3, 0.8], jnp.float32)
    picked = np.asarray(select(jax.random.key(0), fitness))
    assert picked.dtype == np.int32 and sorted(picked) == [1, 1, 3, 3, 5, 5]


def test_run_with_plugin_operators_records_them_and_is_reproducible(tmp_path, plugins):
    mine = ["--plugin", str(EXAMPLE), "--perm-crossover", "one_point_order",
            "--selection", "truncation", "--pc-upper", "1.0"]
    doc = _run(tmp_path, "a", *mine)
    assert doc["plugins"] == [str(EXAMPLE)]
    st = doc["settings"]
    assert (st["perm_crossover"], st["selection"], st["pc_upper"]) == (
        "one_point_order", "truncation", 1.0)
    assert _runs(_run(tmp_path, "again", *mine)) == _runs(doc)  # same seed, same runs
    # The built-in crossover on the same runs and draws gives other children.
    cx = _run(tmp_path, "cx", "--selection", "truncation", "--pc-upper", "1.0")
    assert "plugins" not in cx and cx["settings"]["perm_crossover"] == "cx"
    assert _runs(cx) != _runs(doc)


@pytest.mark.slow  # plugin runs stay in the default lane: test_run_with_plugin_operators_...
def test_a_plugin_operator_never_applied_leaves_the_runs_as_they_were(tmp_path, plugins):
    # pc_upper = 0: the crossover is never applied; a registered operator draws its
    # keys from rows of its own, so every other draw, and every run, is unchanged.
    off = ["--pc-upper", "0.0"]
    mine = _run(tmp_path, "mine", "--plugin", str(EXAMPLE), "--perm-crossover",
                "one_point_order", *off)
    assert _runs(mine) == _runs(_run(tmp_path, "cx", *off))


def test_truncation_selection_fills_the_population_with_its_best(tmp_path, plugins):
    # No variation: each generation is the better half of the last one, twice, so
    # with 8 individuals every one is the first generation's best from generation 3.
    still = ["--pc-upper", "0", "--pm-upper", "0", "--pc-lower", "0", "--pm-lower", "0"]
    _run(tmp_path, "t", "--plugin", str(EXAMPLE), "--selection", "truncation", *still)
    with open(tmp_path / "t" / "history.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    best = {r["best_fitness_median"] for r in rows}
    assert len(rows) == 7 and len(best) == 1  # the best is never lost
    assert rows[0]["mean_fitness_median"] != rows[0]["best_fitness_median"]
    for r in rows[3:]:
        assert r["mean_fitness_median"] == r["best_fitness_median"]


STUDY = """name = "plugged"
runs = 8
scenarios = ["{scene}"]
plugins = ["ops/example_ops.py"]
[ga]
population = 8
generations = 6
pc_upper = 1.0
selection = "truncation"
[[configs]]
perm_crossover = ["cx", "one_point_order"]
"""


def test_study_plugins_are_relative_to_the_study_file(tmp_path, plugins, capsys):
    (tmp_path / "ops").mkdir()
    shutil.copy(EXAMPLE, tmp_path / "ops" / "example_ops.py")
    cfg = tmp_path / "plugged.toml"
    cfg.write_text(STUDY.replace("{scene}", ROBOCUP))
    assert main(["study", str(cfg), "--out", str(tmp_path / "out"), "--quiet",
                 "--no-cache", "--no-figures"]) == 0
    with open(tmp_path / "out" / "runs.csv", newline="") as fh:
        rows = list(csv.DictReader(fh))
    mine = [r for r in rows if r["config"] == "perm_crossover=one_point_order"]
    assert len(mine) == 8 and {r["perm_crossover"] for r in mine} == {"one_point_order"}
    assert {r["selection"] for r in rows} == {"truncation"}
    # A study cell is the same runs as hga-jax run with the same settings and seed.
    doc = _run(tmp_path, "cli", "--plugin", str(tmp_path / "ops" / "example_ops.py"),
               "--perm-crossover", "one_point_order", "--selection", "truncation",
               "--pc-upper", "1.0")
    by_run = {int(r["run"]): float(r["length"]) for r in mine}
    assert [by_run[r["run"]] for r in doc["per_run"]] == pytest.approx(
        [r["length"] for r in doc["per_run"]], rel=1e-12)


def test_a_ga_file_names_its_plugins_relative_to_itself(tmp_path, plugins, capsys):
    (tmp_path / "ga").mkdir()
    shutil.copy(EXAMPLE, tmp_path / "ga" / "ops.py")
    ga = tmp_path / "ga" / "mine.toml"
    ga.write_text('plugins = ["ops.py"]\nselection = "truncation"\n')
    assert main(["check", ROBOCUP, "--ga", str(ga)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[1:] == [f"{ga}: ok (GA settings: selection = truncation)",
                       f"plugins: {tmp_path / 'ga' / 'ops.py'}: ok (imported)"]
    assert "truncation" in registry.names("selection")


BAD = {
    "missing file": ("nope.py", None, "cannot import nope.py: no such file"),
    "error at import": ("bad.py", "x = 1 / 0\n",
                        "cannot import bad.py: ZeroDivisionError: division by zero"),
    "syntax error": ("bad.py", "def f(:\n", "cannot import bad.py: SyntaxError: "),
    "built-in name": ("bad.py", "from hga_jax.search import registry\n"
                      "registry.register('perm_crossover', 'cx', lambda k, a, b: (a, b))\n",
                      "cannot import bad.py: ValueError: perm_crossover 'cx' is built in"),
    "missing module": ("no_such_module_of_hga", None, "cannot import no_such_module_of_hga: "
                       "ModuleNotFoundError: No module named 'no_such_module_of_hga'"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_plugin_is_one_line_naming_it(tmp_path, monkeypatch, capsys, plugins, case):
    name, text, problem = BAD[case]
    monkeypatch.chdir(tmp_path)
    if text is not None:
        (tmp_path / name).write_text(text)
    assert main(["run", ROBOCUP, "--plugin", name, "--out", "o"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith(f"hga-jax: error: command line: --plugin: {problem}")
    assert not (tmp_path / "o").exists()


def test_an_operator_no_plugin_registered_is_refused_in_one_line(tmp_path, capsys, plugins):
    assert main(["run", ROBOCUP, "--perm-crossover", "one_point_order",
                 "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == ("hga-jax: error: command line: --perm-crossover: must "
                                       "be one of cx, pmx, ox1, got 'one_point_order'\n")


def test_a_study_plugin_that_fails_names_the_study_and_the_file(tmp_path, capsys, plugins):
    (tmp_path / "ops").mkdir()
    (tmp_path / "ops" / "example_ops.py").write_text("import no_such_module_of_hga\n")
    cfg = tmp_path / "plugged.toml"
    cfg.write_text(STUDY.replace("{scene}", ROBOCUP))
    assert main(["study", str(cfg), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err == (f"hga-jax: error: {cfg}: plugins[1]: cannot import "
                   f"{tmp_path / 'ops' / 'example_ops.py'}: ModuleNotFoundError: No module "
                   "named 'no_such_module_of_hga'\n")
    assert not (tmp_path / "out").exists()


def test_the_documented_plugin_is_the_shipped_file():
    page = (ROOT / "docs" / "operators.md").read_text()
    (listing,) = re.findall(r"^```py\n(.*?)^```$", page, flags=re.S | re.M)
    assert listing == EXAMPLE.read_text()
