"""What a user meets at the edges of the command line: one-line usage errors, empty
files named as empty, a study's whole grid checked by --quick, a study's output
folder rules, and the study command's help."""
import json
import os

import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.cli import main
from hga_jax.study.config import load_study

PAPER_SCENE = os.path.abspath("configs/scenarios/robocup_paper.toml")


def _err_lines(capsys):
    return [line for line in capsys.readouterr().err.splitlines() if line.strip()]


@pytest.mark.parametrize("argv, words", [
    (["run", PAPER_SCENE, "--seed", "abc"], "argument --seed: invalid int value: 'abc'"),
    (["run", PAPER_SCENE, "--preset", "fast"], "argument --preset: invalid choice: 'fast'"),
    (["study"], "the following arguments are required: config"),
    (["exact"], "the following arguments are required: scenario"),
    (["nonsense"], "invalid choice: 'nonsense'"),
])
def test_usage_errors_are_one_line_with_exit_2(argv, words, capsys):
    with pytest.raises(SystemExit) as e:
        main(argv)
    assert e.value.code == 2
    lines = _err_lines(capsys)
    assert len(lines) == 1, lines
    assert lines[0].startswith("hga-jax: error: hga-jax") and words in lines[0]
    assert "--help" in lines[0]


def test_empty_files_are_named_as_empty(tmp_path, capsys):
    empty = tmp_path / "empty.toml"
    empty.write_text("# nothing here\n")
    assert main(["check", str(empty)]) == 2
    assert _err_lines(capsys) == [f"hga-jax: error: {empty}: file: is empty (a scenario needs "
                                  "name, robot, start and goal)"]
    with pytest.raises(ConfigError, match=r": file: is empty \(a study needs"):
        load_study(str(empty))


def _study_file(tmp_path, second='perm_crossover = "pmx"'):
    """A study of the paper's GA whose full grid adds a configuration (``second``) to
    the quick one's."""
    path = tmp_path / "s.toml"
    path.write_text(f'name = "s"\nruns = 2\nscenarios = ["{PAPER_SCENE}"]\n[ga]\ngenerations = 2\n'
                    '[[configs]]\nlabel = "paper"\n'
                    f'[[configs]]\n{second}\n'
                    '[quick]\nruns = 2\nconfigs = [{ label = "paper" }]\n')
    return str(path)


def test_quick_checks_the_whole_grid_before_anything_runs(tmp_path):
    path = _study_file(tmp_path, second='perm_crossover = "ox9"')
    with pytest.raises(ConfigError) as e:
        load_study(path, quick=True)
    assert str(e.value).startswith(f"{path}: configs[2].perm_crossover: must be one of")
    assert not os.path.exists(tmp_path / "results")
    assert len(load_study(_study_file(tmp_path), quick=True).configs) == 1


def test_study_output_folder_rules(tmp_path, capsys):
    # the full grid's second configuration runs the same program (a rate is data: one compile)
    path = _study_file(tmp_path, second='label = "paper, pc 0.5"\npc_upper = 0.5')
    run_folder = tmp_path / "a_run"
    assert main(["exact", PAPER_SCENE, "--out", str(run_folder), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["study", path, "--quick", "--out", str(run_folder), "--quiet"]) == 2
    (line,) = _err_lines(capsys)
    assert line.startswith(f"hga-jax: error: {run_folder}: output folder: holds a run's result")
    a_file = tmp_path / "a_file"
    a_file.write_text("x")
    assert main(["study", path, "--quick", "--out", str(a_file), "--quiet"]) == 2
    assert "exists and is a file, not a folder" in _err_lines(capsys)[0]
    out = tmp_path / "study_out"
    assert main(["study", path, "--quick", "--out", str(out), "--quiet", "--no-figures"]) == 0
    said = capsys.readouterr().out
    assert "1 run now" in said and "|" not in said and "hit rate" not in said  # no table
    assert said.rstrip().endswith(f"the tests and the notes: {out / 'summary.md'}")
    assert not (out / "figures").exists()  # --no-figures: the tables only, and says so
    assert json.loads((out / "study.json").read_text())["figures"] is False
    assert main(["study", path, "--quick", "--out", str(out), "--quiet"]) == 0  # resumed
    assert "(0 run now, 1 already done)" in capsys.readouterr().out
    assert json.loads((out / "study.json").read_text())["figures"] is True
    assert (out / "figures" / "hit_rate.png").read_bytes()[:4] == b"\x89PNG"  # drawn now
    # the full study is another study: refused, then replaced with --force
    assert main(["study", path, "--out", str(out), "--quiet"]) == 2
    (line,) = _err_lines(capsys)
    assert "holds another study (study 's' (--quick))" in line and "--force" in line
    assert main(["study", path, "--out", str(out), "--quiet", "--force", "--no-figures"]) == 0
    assert "(2 run now, 0 already done)" in capsys.readouterr().out
    assert json.loads((out / "study.json").read_text())["quick"] is False
    assert len(os.listdir(out / "cells")) == 2


def test_study_help_describes_the_command_and_its_defaults(capsys):
    with pytest.raises(SystemExit) as e:
        main(["study", "--help"])
    assert e.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "Run or resume a study" in text and "docs/studies.md" in text
    assert "--force" in text and "(default: results/<study name>" in text


def test_settings_are_checked_after_every_layer_is_merged(tmp_path, capsys):
    """A scenario's tournament_size of 80 is fine with --population 100 (flags over the
    file), and the error without it names both values' sources."""
    from hga_jax.host.cli import _settings
    from hga_jax.host.config import load_scenario
    from hga_jax.search.settings import preset

    text = open(PAPER_SCENE).read() + "\n[ga]\ntournament_size = 80\nselection = \"tournament\"\n"
    path = tmp_path / "s.toml"
    path.write_text(text)
    sc = load_scenario(str(path))  # the file alone is read without complaint
    s = _settings(sc, None, {"population": 100, "tournament_size": 60}, preset("paper"))
    assert (s.population, s.tournament_size) == (100, 60)
    s = _settings(sc, None, {"population": 100}, preset("paper"))
    assert s.tournament_size == 80
    with pytest.raises(ConfigError) as e:
        _settings(sc, None, {}, preset("paper"))
    assert str(e.value) == (f"{path}: ga.tournament_size: must be in 1..population (50, from "
                            "the default), got 80")
    assert main(["check", str(path)]) == 2  # check applies the same rule to the file alone


def test_an_interrupted_study_says_what_it_kept(tmp_path, capsys, monkeypatch):
    """Ctrl-C in the second of two cells: exit 130, one line saying that one cell is
    finished and written; the next start runs only the other."""
    from hga_jax.study import solvers

    path = tmp_path / "two.toml"
    path.write_text(f'name = "two"\nruns = 1\nscenarios = ["{PAPER_SCENE}", '
                    f'"{os.path.abspath("configs/scenarios/open_field.toml")}"]\n'
                    '[[configs]]\nsolver = "exact"\n')
    real, calls = solvers.run_cell, []

    def run_cell(*a):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(*a)

    out = tmp_path / "out"
    with monkeypatch.context() as m:
        m.setattr(solvers, "run_cell", run_cell)
        assert main(["study", str(path), "--out", str(out), "--quiet", "--no-figures"]) == 130
    (line,) = _err_lines(capsys)
    assert line == (f"hga-jax: interrupted; 1 of 2 cells finished and written in {out}/cells "
                    "(1 this time): the same command resumes there")
    assert main(["study", str(path), "--out", str(out), "--quiet", "--no-figures"]) == 0
    assert "(1 run now, 1 already done)" in capsys.readouterr().out
