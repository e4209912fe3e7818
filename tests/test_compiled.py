"""Compiled programs kept on disk (hga_jax.compiled): found again, never trusted blindly."""
import json
import os
import subprocess
import sys

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax import compiled

ROBOCUP = os.path.join(os.path.dirname(__file__), "..", "configs", "scenarios", "robocup_paper.toml")


class Counted:
    """``lower()`` for a small program, counting how often it was asked to compile."""

    def __init__(self, scale: float):
        self.calls, self.scale = 0, scale

    def __call__(self):
        self.calls += 1
        return jax.jit(lambda x: jnp.sin(x) * self.scale).lower(np.zeros(5, np.float32))


@pytest.fixture
def folder(tmp_path):
    before = compiled.folder()
    compiled.use_folder(str(tmp_path))
    compiled.forget()
    yield tmp_path
    compiled.forget()
    compiled.use_folder(before)


def _files(where):
    return sorted(p.name for p in where.iterdir() if p.suffix == ".jaxprog")


def test_a_stored_program_is_loaded_instead_of_compiled(folder):
    x = np.linspace(0, 1, 5, dtype=np.float32)
    first = Counted(3.0)
    want = np.asarray(compiled.program(("test", 3.0), first)(x))
    assert first.calls == 1 and len(_files(folder)) == 1
    compiled.forget()  # a new process: nothing in memory
    again = Counted(3.0)
    got = np.asarray(compiled.program(("test", 3.0), again)(x))
    assert again.calls == 0
    np.testing.assert_array_equal(got, want)
    np.testing.assert_allclose(got, np.sin(x) * 3.0, rtol=1e-6)
    other = Counted(2.0)  # another key is another program
    np.testing.assert_allclose(np.asarray(compiled.program(("test", 2.0), other)(x)),
                               np.sin(x) * 2.0, rtol=1e-6)
    assert other.calls == 1 and len(_files(folder)) == 2


def test_the_tally_counts_each_way_a_program_was_found(folder):
    before = compiled.tally()
    x = np.ones(5, np.float32)
    compiled.program(("tally", 1.0), Counted(1.0))(x)  # compiled
    compiled.program(("tally", 1.0), Counted(1.0))(x)  # in memory
    compiled.forget()
    compiled.program(("tally", 1.0), Counted(1.0))(x)  # from the folder
    compiled.program(("tally", 2.0), Counted(2.0), disk=False)(x)  # compiled
    assert compiled.tally_since(before) == {"tally": {"compiled": 2, "loaded": 1, "reused": 1}}
    assert compiled.tally_since(compiled.tally()) == {}
    from hga_jax.study.cli import programs_line

    assert programs_line({"ga-block": {"compiled": 19, "loaded": 0, "reused": 561}}) == (
        "programs: GA: 19 compiled, 0 loaded from the program folder, 561 reused")


def test_a_damaged_file_is_compiled_again_and_replaced(folder):
    x = np.ones(5, np.float32)
    compiled.program(("damaged",), Counted(1.0))
    (path,) = folder.iterdir()
    path.write_bytes(b"not a program")
    compiled.forget()
    again = Counted(1.0)
    np.testing.assert_allclose(np.asarray(compiled.program(("damaged",), again)(x)), np.sin(x),
                               rtol=1e-6)
    assert again.calls == 1 and path.stat().st_size > 100
    compiled.forget()
    third = Counted(1.0)
    compiled.program(("damaged",), third)
    assert third.calls == 0  # the replacement loads


def test_keys_naming_objects_and_memory_only_programs_stay_off_disk(folder):
    compiled.program(("object", object()), Counted(1.0))  # repr holds an address
    compiled.program(("plugin",), Counted(1.0), disk=False)
    assert _files(folder) == []


def test_programs_of_user_operators_are_not_stored(registries):
    from hga_jax.search import registry
    from hga_jax.search.settings import GASettings

    assert registry.builtin_only(GASettings())
    assert registry.builtin_only(GASettings(perm_crossover="pmx", selection="tournament"))
    registry.register("perm_mutation", "my_swap", registry.get("perm_mutation", "exchange"))
    assert not registry.builtin_only(GASettings(perm_mutation="my_swap"))


def test_a_run_with_stored_programs_is_the_same_run(tmp_path):
    """A command-line run with an empty program folder, then one reading it: the same
    runs, and the second stores nothing new (it found both programs)."""
    env = {**os.environ, "JAX_PLATFORMS": "cpu", "HGA_JAX_CACHE_DIR": str(tmp_path / "cache")}
    cmd = [sys.executable, "-m", "hga_jax", "run", ROBOCUP, "--runs", "3", "--preset", "paper",
           "--generations", "4", "--quiet", "--no-exact"]
    outs = []
    for i in range(2):
        subprocess.run(cmd + ["--out", str(tmp_path / f"r{i}")], env=env, check=True,
                       capture_output=True)
        outs.append(json.loads((tmp_path / f"r{i}" / "result.json").read_text()))
        if i == 0:
            stored = {p.name: p.stat().st_mtime_ns for p in (tmp_path / "cache").iterdir()}
    # the GA batch and the float64 decoder
    assert len(stored) == 2
    assert {p.name: p.stat().st_mtime_ns for p in (tmp_path / "cache").iterdir()}.keys() == stored.keys()
    assert outs[0]["per_run"] == outs[1]["per_run"]
    assert outs[0]["best"]["length"] == outs[1]["best"]["length"]


def test_the_folder_keeps_its_size_by_dropping_the_least_recently_used(folder, monkeypatch):
    name = {}
    for k in range(3):
        before = set(_files(folder))
        compiled.program(("size", k), Counted(float(k + 1)))
        (name[k],) = set(_files(folder)) - before
        os.utime(folder / name[k], (1000.0 * (k + 1), 1000.0 * (k + 1)))  # 0 oldest, 2 newest
    compiled.forget()
    compiled.program(("size", 0), Counted(1.0))  # loaded from disk: now the most recent
    biggest = max((folder / f).stat().st_size for f in name.values())
    monkeypatch.setattr(compiled, "_KEEP_BYTES", 2 * biggest + 1)
    before = set(_files(folder))
    compiled.program(("size", 3), Counted(4.0))  # a fourth program: over the size
    (name[3],) = set(_files(folder)) - before
    assert sorted(_files(folder)) == sorted([name[0], name[3]])  # 1 and 2 went first


def test_configurations_differing_in_rates_run_one_program(folder, monkeypatch):
    """Rates, the penalty weight, the seeding share and the restart interval are data of
    the compiled GA (GASettings.rates), and settings the car model does not read are not
    part of it: a second configuration that differs only in them compiles nothing, and
    its runs are those it makes with a program of its own."""
    from hga_jax.host.config import load_scenario
    from hga_jax.running import runner
    from hga_jax.search.settings import PAPER

    lowered = []
    real = compiled.program

    def counting(key, lower, **kw):
        def counted():
            lowered.append(key[0])
            return lower()
        return real(key, counted, **kw)

    monkeypatch.setattr(runner.compiled, "program", counting)
    sc = load_scenario(ROBOCUP)
    a = PAPER.replace(generations=6, path_mutation="flip", pm_path=0.3, seeding=0.5,
                      restart_after=2, elites=1)
    b = a.replace(pc_upper=0.9, pm_upper=0.3, pc_lower=0.1, pm_lower=0.2, pm_path=0.8,
                  penalty_weight=4.0, seeding=1.0, restart_after=3)
    ra = runner.run_many(sc, a, runs=6, seed=3, exact=False)
    rb = runner.run_many(sc, b, runs=6, seed=3, exact=False)
    assert lowered.count("ga-block") == 1  # one GA program for both
    # the end move's settings belong to the reversing car: under the tight rope they
    # change nothing, so the program is a's and so are the runs
    rc = runner.run_many(sc, a.replace(end_mutation="none", ends_of_best=3), runs=6, seed=3,
                         exact=False)
    assert lowered.count("ga-block") == 1
    np.testing.assert_array_equal(rc.labels, ra.labels)
    compiled.forget()
    compiled.use_folder(None)  # b compiled for itself, nothing found again
    alone = runner.run_many(sc, b, runs=6, seed=3, exact=False)
    assert lowered.count("ga-block") == 2
    for x, y in ((rb.perm, alone.perm), (rb.labels, alone.labels), (rb.length, alone.length)):
        np.testing.assert_array_equal(x, y)
    assert not np.array_equal(ra.labels, rb.labels)  # and b's rates were b's


def test_compiler_options_make_another_program_and_an_unknown_one_is_dropped(folder):
    x = np.linspace(0, 1, 5, dtype=np.float32)
    plain, emitters = Counted(3.0), Counted(3.0)
    compiled.program(("options", 3.0), plain)
    got = compiled.program(("options", 3.0), emitters,
                           options={"xla_cpu_use_fusion_emitters": False})(x)
    assert plain.calls == 1 and emitters.calls == 1  # options are part of the key
    np.testing.assert_allclose(np.asarray(got), np.sin(x) * 3.0, rtol=1e-6)
    unknown = Counted(2.0)  # an XLA without the option: compiled with its defaults
    got = compiled.program(("options", 2.0), unknown, options={"xla_cpu_no_such_option": True})(x)
    assert unknown.calls == 2
    np.testing.assert_allclose(np.asarray(got), np.sin(x) * 2.0, rtol=1e-6)
