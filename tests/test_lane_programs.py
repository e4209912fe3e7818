"""The default lane builds its programs at XLA's backend optimisation level 0 and with
XLA's loop emitters (conftest.py), for a shorter compile; a user's programs are built at
XLA's default level, with the loop emitters below 15 obstacles and XLA's fusion emitters
from 15 on (hga_jax.running.runner). The searches must be the same bits: here the
recommended and the paper preset, run in this process and in a fresh one without the
lane's flags: 60 runs each on the bundled scene (the programs of the held-out floors'
jobs at 9 obstacles, so that this process's programs are theirs), and 8 runs of the
recommended preset's program on the 28 obstacles of configs/scenarios/cluttered.toml
(40 generations: the program does not depend on the count)."""
import dataclasses
import json
import os
import subprocess
import sys

import _xla
import numpy as np

import hga_jax as hg
from hga_jax.host.config import load_scenario
from hga_jax.search.settings import preset

ROBOCUP = "configs/scenarios/robocup_paper.toml"
CLUTTERED = "configs/scenarios/cluttered.toml"
# scenario, preset, runs, generations (None: the preset's): test_held_out_floors.py's RUNS
JOBS = [(ROBOCUP, "recommended", 60, None), (ROBOCUP, "paper", 60, None),
        (CLUTTERED, "recommended", 8, 40)]
RUNS = """
import dataclasses, json, sys
import numpy as np
import hga_jax as hg
from hga_jax.host.config import load_scenario
from hga_jax.search.settings import preset as named
out = []
for scenario, preset, runs, generations in json.loads(sys.argv[1]):
    s = named(preset)
    if generations is not None:
        s = dataclasses.replace(s, generations=generations, generations_per_obstacle=0)
    r = hg.run_many(load_scenario(scenario), s, seed=3, runs=runs, exact=False)
    out.append({"perm": r.perm.tolist(), "labels": r.labels.tolist(),
                   "generation": r.generation.tolist(), "violations": r.violations.tolist(),
                   "best": np.asarray(r.history["best_so_far_fitness"]).view(np.uint32).tolist(),
                   "length": r.length.tolist()})
print(json.dumps(out))
"""


def _runs(env=None):
    proc = subprocess.run([sys.executable, "-c", RUNS, json.dumps(JOBS)],
                          capture_output=True, text=True, env=env, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_the_lanes_programs_search_as_a_users_do():
    user = _runs({**os.environ, "XLA_FLAGS": _xla.without_lane_flags(), "HGA_JAX_CACHE_DIR": "off"})
    for (scenario, name, runs, generations), theirs in zip(JOBS, user, strict=True):
        s = preset(name)
        if generations is not None:
            s = dataclasses.replace(s, generations=generations, generations_per_obstacle=0)
        r = hg.run_many(load_scenario(scenario), s, seed=3, runs=runs, exact=False)
        assert np.array_equal(r.perm, theirs["perm"]) and np.array_equal(r.labels, theirs["labels"])
        assert np.array_equal(r.generation, theirs["generation"])
        assert np.array_equal(r.violations, theirs["violations"])
        best = np.asarray(r.history["best_so_far_fitness"]).view(np.uint32)
        assert np.array_equal(best, theirs["best"])  # every generation's best, bit for bit
        np.testing.assert_allclose(r.length, theirs["length"], rtol=0, atol=1e-12)
