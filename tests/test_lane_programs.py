"""The default lane builds its programs at XLA's backend optimisation level 0
(conftest.py), for a shorter compile; a user's programs are built at XLA's default
level. The searches must be the same bits: here the recommended and the paper preset,
run in this process and in a fresh one at the default level (60 runs each on the
bundled scene: the programs of the held-out floors' jobs at 9 obstacles, so that this
process's programs are theirs)."""
import json
import os
import subprocess
import sys

import _xla
import numpy as np

import hga_jax as hg
from hga_jax.host.config import load_scenario

ROBOCUP = "configs/scenarios/robocup_paper.toml"
JOBS = {"recommended": 60, "paper": 60}  # test_held_out_floors.py's RUNS
RUNS = """
import json, sys
import numpy as np
import hga_jax as hg
from hga_jax.host.config import load_scenario
sc = load_scenario(sys.argv[1])
out = {}
for preset, runs in json.loads(sys.argv[2]).items():
    r = hg.run_many(sc, preset, seed=3, runs=runs, exact=False)
    out[preset] = {"perm": r.perm.tolist(), "labels": r.labels.tolist(),
                   "generation": r.generation.tolist(), "violations": r.violations.tolist(),
                   "best": np.asarray(r.history["best_so_far_fitness"]).view(np.uint32).tolist(),
                   "length": r.length.tolist()}
print(json.dumps(out))
"""


def _runs(env=None):
    proc = subprocess.run([sys.executable, "-c", RUNS, ROBOCUP, json.dumps(JOBS)],
                          capture_output=True, text=True, env=env, check=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_the_lanes_programs_search_as_a_users_do():
    user = _runs({**os.environ, "XLA_FLAGS": _xla.without_level(), "HGA_JAX_CACHE_DIR": "off"})
    sc = load_scenario(ROBOCUP)
    for preset, runs in JOBS.items():
        r = hg.run_many(sc, preset, seed=3, runs=runs, exact=False)
        theirs = user[preset]
        assert np.array_equal(r.perm, theirs["perm"]) and np.array_equal(r.labels, theirs["labels"])
        assert np.array_equal(r.generation, theirs["generation"])
        assert np.array_equal(r.violations, theirs["violations"])
        best = np.asarray(r.history["best_so_far_fitness"]).view(np.uint32)
        assert np.array_equal(best, theirs["best"])  # every generation's best, bit for bit
        np.testing.assert_allclose(r.length, theirs["length"], rtol=0, atol=1e-12)
