"""One JAX device per CPU core (hga_jax.running.devices, --cpu-devices): counts, refusals, same runs."""
import json
import math
import os
import subprocess
import sys

import _xla
import pytest

from hga_jax.running import devices
from hga_jax.host.cli import main
from hga_jax.running.devices import cores, use_cpu_cores
from hga_jax.errors import ConfigError

ROBOCUP = "configs/scenarios/robocup_paper.toml"
JOB = ["--preset", "paper", "--runs", "7", "--seed", "3", "--generations", "4",
       "--population", "12", "--json", "--quiet", "--no-exact", "--no-cache"]

# In a fresh process: what each call returns and the devices JAX then has.
COUNTS = """
import json, sys, jax
from hga_jax.running.devices import use_cpu_cores
from hga_jax.errors import ConfigError
out = {"first": use_cpu_cores(*json.loads(sys.argv[1]))}
out["devices"] = jax.local_device_count()  # the runtime starts here
out["again"] = use_cpu_cores()  # too late, and not asked for: nothing happens
try:
    use_cpu_cores(out["devices"] + 1)
except ConfigError as e:
    out["late"] = str(e)
print(json.dumps(out))
"""


def _fresh(args, xla_flags=""):
    env = {**os.environ, "JAX_PLATFORMS": "cpu", "XLA_FLAGS": _xla.flags(xla_flags)}
    proc = subprocess.run([sys.executable, "-c", COUNTS, json.dumps(args)], capture_output=True,
                          text=True, env=env, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_cores_is_this_process_s_affinity_within_its_quota():
    quota = devices.cpu_quota()
    mask = len(os.sched_getaffinity(0))
    assert cores() == (max(1, min(mask, math.ceil(quota))) if quota else mask) >= 1


@pytest.mark.parametrize("files, quota", [
    ({"cpu.max": "150000 100000\n"}, 1.5),  # cgroup v2: 1.5 cores
    ({"cpu.max": "max 100000\n"}, None),  # no limit
    ({"quota": "50000\n", "period": "100000\n"}, 0.5),  # cgroup v1
    ({"quota": "-1\n", "period": "100000\n"}, None),  # v1, no limit
    ({"cpu.max": "garbage\n"}, None),
    ({}, None),  # no cgroup files at all
])
def test_cpu_quota_of_a_container(tmp_path, files, quota):
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    paths = ((str(tmp_path / "cpu.max"), None), (str(tmp_path / "quota"), str(tmp_path / "period")))
    assert devices.cpu_quota(paths) == quota


def test_cores_are_capped_by_the_quota(monkeypatch):
    monkeypatch.setattr(devices.os, "sched_getaffinity", lambda pid: set(range(64)))
    monkeypatch.setattr(devices, "cpu_quota", lambda: 2.5)
    assert cores() == 3  # a container allowed 2.5 of 64 cores: 3 devices
    monkeypatch.setattr(devices, "cpu_quota", lambda: 0.2)
    assert cores() == 1
    monkeypatch.setattr(devices, "cpu_quota", lambda: None)
    assert cores() == 64


@pytest.mark.parametrize("args, flags, first, devices", [
    ([3], "", True, 3),  # asked for: three devices, whatever the core count
    ([], "", True, None),  # one per core
    ([], "--xla_force_host_platform_device_count=5", False, 5),  # the user's choice stays
])
def test_device_counts_in_a_fresh_process(args, flags, first, devices):
    out = _fresh(args, flags)
    assert out["first"] is first
    assert out["devices"] == (cores() if devices is None else devices)
    assert out["again"] is False
    assert out["late"] == (f"use_cpu_cores: {out['devices'] + 1} CPU devices asked for, but "
                           f"JAX's runtime already started with {out['devices']}; set it "
                           "before the first JAX operation")


@pytest.mark.parametrize("bad", [0, -2, 1.5, True, "2"])
def test_a_bad_count_is_refused_with_one_line(bad):
    with pytest.raises(ConfigError, match=r"^use_cpu_cores: must be an integer >= 1, got "):
        use_cpu_cores(bad)


def test_cli_refuses_a_bad_device_count(tmp_path, capsys):
    assert main(["run", ROBOCUP, "--cpu-devices", "0", "--out", str(tmp_path / "r"),
                 "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "command line: --cpu-devices: must be an integer >= 1, got 0" in err
    assert not (tmp_path / "r").exists()


def test_runs_are_the_same_on_one_and_on_three_devices(tmp_path):
    """7 runs on 3 devices: batches padded to a multiple of 3 and split; every run,
    history line and summary figure equals the one-device job's."""
    env = {**os.environ, "JAX_PLATFORMS": "cpu", "XLA_FLAGS": _xla.flags()}
    docs, histories = [], []
    for devices in (1, 3):
        out = tmp_path / f"d{devices}"
        proc = subprocess.run([sys.executable, "-m", "hga_jax", "run", ROBOCUP, *JOB,
                               "--cpu-devices", str(devices), "--out", str(out)],
                              capture_output=True, text=True, env=env, check=True)
        assert "Traceback" not in proc.stderr
        docs.append(json.loads((out / "result.json").read_text()))
        histories.append((out / "history.csv").read_text())
    assert [d["summary"]["devices"] for d in docs] == [1, 3]
    for d in docs:
        for key in ("compile_s", "search_s", "evaluations_per_s", "devices"):
            d["summary"].pop(key)
    assert docs[0] == docs[1]
    assert histories[0] == histories[1]
    assert len(docs[0]["per_run"]) == 7
