"""Floors under the recommended preset's hit rates on small held-out families: walled
scenes (the field's edges kept) and hard scenes, with the paper's preset beside it.

The scenes come from generators and seeds that no tuning has seen (``scattered`` with
the walled scenes picked out, ``clusters``, ``corridors`` and the forward car's
parking-like poses at 9 obstacles, and ``obstructed`` at 15, whose guided move turns a
neighbour too (``pairs_from = 10``), in the default lane; ``obstructed`` at 25 obstacles
and ``corridors`` at 25 on demand, ``-m slow``: larger programs); each
floor sits a little under the rate measured when it was set (the runs are seeded, so
a change that moves a floor changed the search). The recommended preset may not end
worse than the paper's on any scene, and every run of it ends on a collision-free
path (each scene's optimum is feasible). Measured when set (100 runs per scene, seed
11; the tests run the first 60): hga-jax 0.6 and 0.7 hit in every run on every scene
of the four families (and 0.7 on ``parking9``'s three) (0.5: walled 100 %, obstructed at 15 obstacles 99.3 %, worst scene
98 %); every run feasible. ``corridors`` (set with hga-jax 0.7.4, the tests' 60 runs):
every run on both 9-obstacle scenes; at 25 obstacles 97.8 %, worst scene 93 %, every
run feasible. 60 runs at 9 obstacles: the paper's program is the one
tests/test_recommended.py compiles. ``parking25`` (on demand) holds two development
scenes of the forward car's parking-like poses (not held out: the two that hga-jax
0.6 missed most, 93 % and 72 %), which 0.7's end arcs in the legs lifted to 100 %.
"""
from __future__ import annotations

import numpy as np
import pytest

import hga_jax as hg
from hga_jax.host.config import scenario_from_dict
from hga_jax.study.scenes import generate

RUNS = 60
SEED = 11


def _walled(n: int, seed: int, count: int) -> list[dict]:
    """The first ``count`` scattered scenes of ``seed`` whose field is kept."""
    out, i = [], 0
    while len(out) < count:
        d = generate("scattered", n, seed, i, f"walled_{i}")
        if d["field"]["keep_inside"]:
            out.append(d)
        i += 1
    return out


FAMILIES = {
    "walled": lambda: _walled(9, 151, 3),
    "clusters9": lambda: [generate("clusters", 9, 154, i, f"c9_{i}") for i in range(2)],
    "obstructed15": lambda: [generate("obstructed", 15, 152, i, f"o15_{i}") for i in range(3)],
    "obstructed25": lambda: [generate("obstructed", 25, 153, i, f"o25_{i}") for i in range(2)],
    # barriers across the field with a gap or two each (held out, seed 204; the study's
    # corridors are seed 201)
    "corridors9": lambda: [generate("corridors", 9, 204, i, f"co9_{i}") for i in range(2)],
    "corridors25": lambda: [generate("corridors", 25, 204, i, f"co25_{i}") for i in range(3)],
    # the forward car's parking-like poses, held out (seed 174): one scene of each kind
    "parking9": lambda: [generate(k, 9, 174, 0, f"p9_{k}", car="dubins")
                         for k in ("behind", "slot", "wall")],
    # the forward car's parking-like development scenes that 0.6 missed most (93 % and
    # 72 % of 100 runs; a goal arc through an obstacle, a loop round the wrong robot)
    "parking25": lambda: [generate("behind", 25, 161, i, f"b25_{i}", car="dubins")
                          for i in (1, 5)],
}

FLOORS = {  # family: (pooled hit rate, worst scene's hit rate, feasible share)
    "walled": (0.99, 0.97, 1.0),
    "clusters9": (0.98, 0.95, 1.0),
    "obstructed15": (0.98, 0.95, 1.0),
    "obstructed25": (0.98, 0.95, 1.0),
    "corridors9": (0.99, 0.97, 1.0),
    "corridors25": (0.95, 0.90, 1.0),
    "parking9": (0.99, 0.97, 1.0),
    "parking25": (0.98, 0.95, 1.0),
}


@pytest.mark.parametrize("families", [
    ("walled", "clusters9", "corridors9", "parking9"),  # one size: they share two programs
    pytest.param(("obstructed15",), marks=pytest.mark.slow),  # 36 s of the default lane's
    pytest.param(("obstructed25",), marks=pytest.mark.slow),
    pytest.param(("corridors25",), marks=pytest.mark.slow),
    pytest.param(("parking25",), marks=pytest.mark.slow)], ids=lambda f: "+".join(f))
def test_recommended_holds_its_floor_and_never_trails_the_paper(families):
    rec, paper = hg.preset("recommended"), hg.preset("paper")
    for family in families:
        hits, feasible, worst = [], [], 1.0
        for d in FAMILIES[family]():
            sc = scenario_from_dict(d)
            r = hg.run_many(sc, rec, runs=RUNS, seed=SEED)
            p = hg.run_many(sc, paper, runs=RUNS, seed=SEED)
            hits.append(np.mean(r.hit))
            feasible.append(np.mean(r.feasible))
            worst = min(worst, float(np.mean(r.hit)))
            # never worse than the paper's preset on the scene (a binomial margin of 2 sd)
            sd = np.sqrt(max(np.mean(p.hit) * (1 - np.mean(p.hit)), 0.01) / RUNS)
            assert np.mean(r.hit) >= np.mean(p.hit) - 2 * sd, d["name"]
        rate, floor, share = FLOORS[family]
        print(f"{family}: hit {np.mean(hits):.3f}, worst scene {worst:.2f}, "
              f"feasible {np.mean(feasible):.3f}")
        assert np.mean(hits) >= rate, family
        assert worst >= floor, family
        assert np.mean(feasible) >= share, family
