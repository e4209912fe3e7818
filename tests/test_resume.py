"""An interrupted run keeps its finished batches, and --resume finishes the job with the
results of an uninterrupted one, run for run (Ctrl-C and SIGTERM alike)."""
import json
import os
import signal

import pytest

from hga_jax.host.cli import main
from hga_jax.running import runner

SCENE = os.path.abspath("configs/scenarios/robocup_paper.toml")
JOB = ["--runs", "6", "--chunk", "2", "--preset", "paper", "--generations", "3",
       "--population", "10", "--seed", "5", "--quiet", "--no-cache"]


def _run(out, *extra):
    return main(["run", SCENE, *JOB, "--out", str(out), *extra])


def _stop_at(monkeypatch, call, how):
    """Make the ``call``-th block of generations end with Ctrl-C (or SIGTERM).

    SIGTERM is the handler the command installed, called here: a signal sent to this
    process (``os.kill``) runs its handler at the next bytecode, which may be inside a
    garbage collector callback (hypothesis installs one), where the KeyboardInterrupt it
    raises is "unraisable": pytest then warns with its traceback after the session."""
    real, calls = runner.tick, []

    def tick(bar, k):
        calls.append(k)
        if len(calls) == call:
            if how == "sigterm":
                handler = signal.getsignal(signal.SIGTERM)
                assert callable(handler)  # the command's own (hga_jax.host.cli._terminated)
                handler(signal.SIGTERM, None)  # raises KeyboardInterrupt("terminated")
            raise KeyboardInterrupt
        real(bar, k)

    monkeypatch.setattr(runner, "tick", tick)
    return calls


def _result(folder):
    return json.loads((folder / "result.json").read_text())


@pytest.mark.parametrize("how", ["ctrl-c", "sigterm"])
def test_an_interrupted_run_keeps_its_batches_and_resume_gives_the_same_runs(
        tmp_path, monkeypatch, capsys, how):
    ref, out = tmp_path / "ref", tmp_path / "out"
    assert _run(ref) == 0
    whole = _result(ref)
    blocks = 1  # blocks of generations per batch (4 generations: one block)
    with monkeypatch.context() as m:
        _stop_at(m, 2 * blocks if how == "ctrl-c" else 2 * blocks + 1, how)
        assert _run(out) == 130
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "finished runs of 6 are written in" in err and "--resume" in err
    part = _result(out)
    done = part["partial"]["runs_done"]
    assert done in (2, 4) and part["partial"]["runs_requested"] == 6
    assert (out / "partial.npz").is_file()
    assert [r["length"] for r in part["per_run"]] == [r["length"] for r in whole["per_run"][:done]]
    # the same folder without --resume is refused, in one line
    assert _run(out) == 2
    assert "holds an interrupted run" in capsys.readouterr().err
    # interrupted again while resuming: the kept runs grow
    if done == 2:
        with monkeypatch.context() as m:
            _stop_at(m, 2 * blocks, "ctrl-c")
            assert _run(out, "--resume") == 130
        assert _result(out)["partial"]["runs_done"] == 4
    capsys.readouterr()
    assert _run(out, "--resume") == 0
    final = _result(out)
    kept = final["summary"]["resumed"]
    assert kept["runs"] == _result_runs_before(done)
    assert 0 < kept["search_s"] <= final["summary"]["search_s"]
    said = capsys.readouterr().out
    assert (f"; compile and search include the {kept['runs']} runs kept from the interrupted "
            f"command ({kept['compile_s']:.2f} s and {kept['search_s']:.2f} s there; ") in said
    assert "partial" not in final and not (out / "partial.npz").exists()
    for key in ("per_run", "best", "runs", "seed", "settings"):
        assert final[key] == whole[key], key
    timeless = lambda d: {k: v for k, v in d.items() if k != "seconds"}  # noqa: E731
    assert timeless(final["optimum"]) == timeless(whole["optimum"])
    assert "resumed" not in whole["summary"]
    for key in ("best_length", "runs_found_best", "median_generation_found_best"):
        assert final["summary"][key] == whole["summary"][key], key
    assert (out / "history.csv").read_text() == (ref / "history.csv").read_text()


def _result_runs_before(done: int) -> int:
    """Runs kept before the last resume: 4 when the first resume was interrupted too."""
    return 4 if done == 2 else done


def test_resume_refuses_another_job(tmp_path, capsys, monkeypatch):
    out = tmp_path / "out"
    assert _run(out, "--resume") == 2
    assert "no partial result there to resume" in capsys.readouterr().err
    with monkeypatch.context() as m:
        _stop_at(m, 2, "ctrl-c")
        assert _run(out) == 130
    capsys.readouterr()
    assert main(["run", SCENE, *JOB[:-4], "--seed", "6", "--quiet", "--no-cache", "--out",
                 str(out), "--resume"]) == 2
    line = capsys.readouterr().err.strip()
    assert ("--resume: the partial result was not made by this command: its seed is 5, this "
            "command's is 6;") in line
    # a setting: named, with both values
    assert _run(out, "--resume", "--pc-upper", "0.5") == 2
    line = capsys.readouterr().err.strip()
    assert "its settings.pc_upper is 0.4, this command's is 0.5;" in line
    assert main(["run", SCENE, *JOB[:1], "8", *JOB[2:], "--out", str(out), "--resume"]) == 2
    assert "its runs is 6, this command's is 8;" in capsys.readouterr().err
