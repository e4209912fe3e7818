"""Evaluations per second of the GA among robots that move, against the same scene standing.

The scene: ``robocup_paper.toml`` (nine robots) with five of them moving at 0.3-0.6 m/s
(:data:`VELOCITIES`; the car at 1 m/s), against the same scene with every velocity 0
(the static scene, bit for bit). Both fitnesses look turns up in a turn table; the
moving scene's table carries each turn's windows in time as more columns
(:mod:`hga_jax.model.in_time.windows`). For the paper's and the recommended preset, both
scenes are searched in one process, alternately (moving, standing, moving, ...), after a
run of each that compiles, and the median of ``--repeats`` search times gives
evaluations/s (``res.evaluations / res.search_s``); the first (compiling) call's
``compile_s`` and the time to build the arrays before it are printed too (the placement
of the moving robots' circles solves the scene in time first, ``wrap_moving =
"at-best"``, then the turn table and its windows are built). A fixed pure-Python loop
is timed before and after (calibration: the machine is shared).

``--held-out K``: the same for the paper preset on ``K`` scenes of 9 robots from each of
the study's families ``crossing``, ``leaving`` and ``random_moving``
(:mod:`hga_jax.study.moving_scenes`, seed 2026; 3-5 of the robots move), each against
itself with every velocity 0; one line per scene and the worst ratio.

``--profile`` also times the fitness alone (jitted, on one batch of random tight-rope
chromosomes, best of 7): the standing scene's turn-table look-ups, the moving scene's
(with the windows), the decoder alone on either scene, the decoder with the tests in time
(what chromosomes with leg genes run), and :func:`hga_jax.model.in_time.clearance.violations` alone
at 8 (the search's), 4, 2 and 1 sub-arcs.

Usage (from the repository root)::

    python3 experiments/bench_moving.py [--runs 200] [--repeats 3] [--presets paper recommended]
        [--held-out 0] [--profile] [--batch 10000]
"""
from __future__ import annotations

import argparse
import statistics
import time

from calibration import calibration

from hga_jax import load_scenario, run_many
from hga_jax.model.scenario import scenario_to_dict

VELOCITIES = {0: (-0.3, -0.1), 3: (0.3, -0.45), 6: (0.0, 0.3), 7: (-0.13, 0.55), 8: (0.4, 0.0)}
"""Obstacle index (from 0): velocity (m/s), the five robots of the scene that move:
those of ``moving_robots.toml`` and robot 4 (1.20, 0.84) drifting down and right."""


def scenes():
    """``(moving, standing)``: the same nine robots, five moving in the first."""
    from hga_jax import scenario_from_dict

    base = load_scenario("configs/scenarios/robocup_paper.toml")
    d = scenario_to_dict(base)
    for k, (vx, vy) in VELOCITIES.items():
        d["obstacles"][k].update(vx=vx, vy=vy)
    moving = scenario_from_dict(d, "robocup_paper, five moving")
    standing = scenario_from_dict(scenario_to_dict(base), "robocup_paper")
    assert moving.has_motion and int(moving.moving.sum()) == 5 and not standing.has_motion
    return moving, standing


def held_out(count: int):
    """``[(name, moving, standing)]``: ``count`` scenes of 9 robots per moving family."""
    from hga_jax import scenario_from_dict
    from hga_jax.study import moving_scenes

    out = []
    for kind in ("crossing", "leaving", "random_moving"):
        for i in range(count):
            name = f"{kind}_n009_{i:03d}"
            d = moving_scenes.generate(kind, 9, 2026, i, name)
            moving = scenario_from_dict(d, name)
            for o in d["obstacles"]:
                o.pop("vx", None)
                o.pop("vy", None)
            out.append((name, moving, scenario_from_dict(d, name)))
    return out


def measure(scs: dict, preset: str, runs: int, repeats: int) -> dict:
    """Per scene name: first call (build + compile) seconds, the arrays' build alone,
    compile_s, and the median evaluations/s over ``repeats`` alternated searches."""
    import numpy as np

    from hga_jax.search.settings import preset as preset_of

    out = {}
    for name, sc in scs.items():  # compile (and, for the moving scene, place its circles)
        t0 = time.perf_counter()
        st = preset_of(preset)
        st.model.search_arrays(sc, np.float32, st.collision, st.uses_legs)
        built = time.perf_counter() - t0
        res = run_many(sc, preset, seed=0, runs=runs, exact=False)
        out[name] = {"first_s": time.perf_counter() - t0, "compile_s": res.compile_s,
                     "build_s": built, "rates": []}
    for k in range(repeats):
        for name, sc in scs.items():
            res = run_many(sc, preset, seed=1 + k, runs=runs, exact=False)
            out[name]["rates"].append(res.evaluations / res.search_s)
            out[name]["evaluations"] = res.evaluations
    for v in out.values():
        v["rate"] = statistics.median(v["rates"])
    return out


def profile(moving, standing, batch: int) -> None:
    """The fitness's parts, per ``batch`` chromosomes (module doc)."""
    import jax
    import jax.numpy as jnp
    import numpy as np

    from hga_jax.model.decode import decode_batch
    from hga_jax.model.fitness import evaluate
    from hga_jax.model.in_time import clearance as mv

    rng = np.random.default_rng(0)
    n = moving.n
    perm = np.argsort(rng.random((batch, n)), axis=1).astype(np.int32)
    u = rng.random((batch, n + 2))  # each position touched with probability 0.3
    labels = np.where(u < 0.15, -1, np.where(u < 0.3, 1, 0)).astype(np.int32)
    labels[:, [0, -1]] = rng.choice(np.array([-1, 1], np.int32), (batch, 2))
    sa_m = moving.search_arrays(np.float32, "full")
    sa_s = standing.search_arrays(np.float32, "full")

    def best(f, *args) -> float:
        f = jax.jit(f)
        jax.block_until_ready(f(*args))
        times = []
        for _ in range(7):
            t0 = time.perf_counter()
            jax.block_until_ready(f(*args))
            times.append(time.perf_counter() - t0)
        return min(times)

    def decoded(sa, p, lab):
        return decode_batch(sa, p, lab, "full")

    rows = [("standing: fitness (turn-table lookups)",
             best(lambda sa, p, lab: evaluate(sa, p, lab, "full"), sa_s, perm, labels)),
            ("moving: fitness (lookups with windows)",
             best(lambda sa, p, lab: evaluate(sa, p, lab, "full"), sa_m, perm, labels)),
            ("standing: decoder alone", best(lambda sa, p, lab: decoded(sa, p, lab).violations,
                                             sa_s._replace(turns_full=None), perm, labels)),
            ("moving: decoder alone (no test in time)",
             best(lambda sa, p, lab: decoded(sa, p, lab).violations,
                  sa_m._replace(motion=None), perm, labels)),
            ("moving: decoder + tests in time",
             best(lambda sa, p, lab: evaluate(sa, p, lab, "full"), sa_m._replace(turns_full=None),
                  perm, labels))]
    d = jax.jit(decoded)(sa_m._replace(motion=None), perm, labels)
    motion = jax.tree.map(jnp.asarray, sa_m.motion)
    for k in (8, 4, 2, 1):
        rows.append((f"moving.violations alone, {k} sub-arcs",
                     best(lambda d, m, k=k: mv.violations(d, m, n, k), d, motion)))
    print(f"profile: {batch} random tight-rope chromosomes, best of 7 (ms; M evaluations/s)")
    for name, t in rows:
        print(f"  {name:<44} {t * 1e3:8.2f} ms {batch / t / 1e6:8.2f} M/s")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=200,
                    help="runs per timed search (the recommended preset: a tenth)")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--presets", nargs="+", default=["paper", "recommended"])
    ap.add_argument("--held-out", type=int, default=0,
                    help="scenes per moving family of the study also measured (paper preset)")
    ap.add_argument("--profile", action="store_true", help="also time the fitness's parts")
    ap.add_argument("--batch", type=int, default=10000, help="chromosomes per profiled call")
    args = ap.parse_args(argv)
    moving, standing = scenes()
    print(f"calibration: pure-Python loop of 10^6 multiply-adds: {calibration() * 1e3:.1f} ms")
    print(f"{'preset':<12} {'scene':<9} {'runs':>5} {'evals/run':>9} {'k evals/s':>10} "
          f"{'each repeat (k/s)':>26} {'build s':>8} {'first call s':>12} {'compile s':>9}"
          "  moving/standing")
    for preset in args.presets:
        runs = max(10, args.runs // (10 if preset == "recommended" else 1))
        got = measure({"moving": moving, "standing": standing}, preset, runs, args.repeats)
        ratio = got["moving"]["rate"] / got["standing"]["rate"]
        for name, v in got.items():
            each = " ".join(f"{r / 1e3:.1f}" for r in v["rates"])
            print(f"{preset:<12} {name:<9} {runs:>5} {v['evaluations'] // runs:>9} "
                  f"{v['rate'] / 1e3:>10.1f} {each:>26} {v['build_s']:>8.2f} {v['first_s']:>12.1f} "
                  f"{v['compile_s']:>9.1f}  " + (f"{ratio:.3f}" if name == "moving" else ""),
                  flush=True)
    if args.held_out:
        print(f"held-out scenes of 9 robots, the paper's preset, {args.runs} runs, "
              f"{args.repeats} repeats (k evaluations/s; arrays' build s)")
        worst = None
        for name, mv, st in held_out(args.held_out):
            got = measure({"moving": mv, "standing": st}, "paper", args.runs, args.repeats)
            ratio = got["moving"]["rate"] / got["standing"]["rate"]
            worst = ratio if worst is None else min(worst, ratio)
            print(f"  {name:<22} {int(mv.moving.sum())} moving  "
                  f"moving {got['moving']['rate'] / 1e3:8.1f} ({got['moving']['build_s']:.2f} s)  "
                  f"standing {got['standing']['rate'] / 1e3:8.1f}  ratio {ratio:.3f}", flush=True)
        print(f"  worst ratio {worst:.3f}")
    if args.profile:
        profile(moving, standing, args.batch)
    print(f"calibration again: {calibration() * 1e3:.1f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
