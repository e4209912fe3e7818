"""Host side of many seeded runs: batches, blocks, sharding, timing, float64 re-evaluation.

``run_many`` sizes the job (:mod:`hga_jax.running.budget`), compiles one batch shape (a
chunk of runs) as one program, a block of generations (generation 0 included), feeds
it chunks of run indices (the last one padded), loops over the blocks on the
host carrying the state (progress and Ctrl-C between blocks), shards each chunk
over the process's devices when there are several, and re-evaluates every run's
best chromosome in float64 before anything is reported. In a multi-process job
each process does this for its share of the runs, and the runs are gathered to
every process (:mod:`hga_jax.running.distributed`).
"""
from __future__ import annotations

import dataclasses
import functools
import sys
import time
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from hga_jax import compiled, jax_compat, validation
from hga_jax.running import budget
from hga_jax.errors import Interrupted
from hga_jax.model.exact import solve
from hga_jax.model.fitness import turn_table
from hga_jax.search import ga, registry, rng, run_keys
from hga_jax.search.ga import Record
from hga_jax.running.progress import bar as bar_of, tick
from hga_jax.words import count
from hga_jax.model.path import decode64, evaluate_path
from hga_jax.running.results import BestPath, RunsResult, best_run
from hga_jax.model.scenario import Scenario
from hga_jax.search.settings import GASettings
from hga_jax.search.settings import preset as presets

DEFAULT_PRESET = "recommended"
"""The preset :func:`run_many` and :func:`settings_for` start from when given none: the
command line's (``hga-jax run --preset``'s default). Name ``"paper"`` for the paper's
HGA (roulette selection, no elites)."""


def settings_for(scenario: Scenario, base: GASettings | str | None = None) -> GASettings:
    """The scenario's ``[ga]`` table on top of ``base``: settings, or a preset's name
    (default: :data:`DEFAULT_PRESET`, the recommended preset, as ``hga-jax run``)."""
    if base is None or isinstance(base, str):
        base = presets(DEFAULT_PRESET if base is None else base, "settings_for")
    return GASettings.from_mapping(scenario.ga, scenario.source, base=base)


def _sharding():
    """Split the run axis over this process's devices when there are several (None: one)."""
    devices = jax.local_devices()
    if len(devices) < 2:
        return None
    mesh = jax.sharding.Mesh(np.asarray(devices), (_DEVICES,))
    return jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec(_DEVICES))


_DEVICES = "devices"  # the mesh axis the runs of a batch are split over


def run_many(scenario: Scenario, settings: GASettings | str | None = None, *, seed: int = 0,
             runs: int = 1, first_run: int = 0, chunk: int | None = None,
             exact: bool = True, progress: bool = False,
             preset: str | None = None, turns: str | None = None) -> RunsResult:
    """Runs ``first_run .. first_run + runs - 1`` of ``seed`` on ``scenario``.

    ``settings``: a preset's name (``"recommended"``, ``"paper"``) puts the scenario's
    ``[ga]`` table over the preset's settings and records the name; None (the default)
    is ``preset`` if given, else ``"recommended"`` (:data:`DEFAULT_PRESET`, the command
    line's default; ``"paper"`` gives the paper's HGA); :class:`GASettings` are used as
    they are. ``exact`` also solves the model's optimum and reports the gap.
    ``chunk``: runs per compiled batch (None: sized by :mod:`hga_jax.running.budget`, which
    also lowers a ``chunk`` that would not fit in memory and refuses a job whose
    results cannot fit). Each batch runs in blocks of generations, so Ctrl-C stops
    the job within a block (:class:`~hga_jax.errors.Interrupted`); ``progress``
    shows a bar of generations on stderr. ``preset``: the name of the preset the
    settings were built on (:data:`hga_jax.search.settings.PRESETS`), recorded in the
    result; without ``settings``, the preset run.
    ``turns``: the car model the optimum is solved in, the yardstick of the gaps
    (:mod:`hga_jax.model.car_model`): ``"tight-rope"`` (the paper's) or ``"free"`` (the
    car's shortest path; the full collision test only); None: the model the GA searches
    (``settings.turns``). A tight-rope GA measured against the free-turn
    optimum shows how far its paths are from the car's shortest.

    In a multi-process job (after :func:`hga_jax.running.distributed.initialize`) every
    process makes the same call: each searches its share of the runs on its own
    devices (:func:`hga_jax.running.distributed.share`), the runs are gathered to every
    process in run order, and every process returns the whole job's result, the
    one a single process gives; ``compile_s`` and ``search_s`` are then the
    slowest process's, and only process 0 shows progress.
    """
    if settings is None:  # the command line's default preset (or the one named)
        settings = preset or DEFAULT_PRESET
    if isinstance(settings, str):  # a preset's name: its settings under the scenario's [ga]
        preset = settings
        settings = settings_for(scenario, presets(settings, "run_many"))
    validation.car(scenario, settings)
    settings = settings.for_car(scenario.car)
    if settings.model.car != scenario.car:  # turns named another car's model: that car's run
        scenario = dataclasses.replace(scenario, car=settings.model.car)
    turns = settings.turns if turns is None else turns
    validation.turns(turns, settings.collision if exact else "full", "run_many")
    budget_rule = settings.budget(scenario.n)
    settings = settings.for_obstacles(scenario.n)
    validation.run_range(seed, runs, first_run, chunk, "run_many")
    procs, me = jax.process_count(), jax.process_index()
    if procs == 1:
        try:
            found = _search(scenario, settings, seed, first_run, runs, chunk, progress)
        except Interrupted as e:  # the batches that finished, as a result of their own
            if getattr(e, "found", None) is not None:
                e.partial = _result(scenario, settings, seed, first_run, e.found, exact, turns,
                                    preset, budget_rule)
            raise
    else:
        from hga_jax.running import distributed

        # Every process holds the merged result: the whole job must fit each one.
        distributed.together(lambda: budget.plan(
            scenario.n, settings, runs, chunk, jax.local_device_count(), source="run_many"))
        start, size = distributed.share(first_run, runs, me, procs)
        if progress and me == 0:
            print(f"process 0 of {procs}: runs {start:,}..{start + size - 1:,} of "
                  f"{first_run:,}..{first_run + runs - 1:,}", file=sys.stderr, flush=True)
        found = _search(scenario, settings, seed, start, size, chunk, progress and me == 0)
        found = _gathered(found, runs)
    return _result(scenario, settings, seed, first_run, found, exact, turns, preset, budget_rule)


def _result(scenario: Scenario, settings: GASettings, seed: int, first_run: int, found,
            exact: bool, turns: str, preset: str | None, budget_rule) -> RunsResult:
    """The :class:`RunsResult` of searched runs: the best run's path in float64, the optimum."""
    t0 = time.perf_counter()
    runs = len(found.length)
    length, violations = found.length, found.violations
    top = best_run(length, violations)
    best_path = evaluate_path(scenario, found.perm[top], found.labels[top], settings.collision,
                              None if found.legs is None else found.legs[top])
    optimum = solve(scenario, settings.collision, turns=turns) if exact else None
    return RunsResult(
        scenario=scenario, settings=settings, seed=seed,
        run_ids=np.arange(first_run, first_run + runs),
        perm=found.perm, labels=found.labels, legs=found.legs, length=length,
        violations=violations,
        generation=found.generation, history=found.history,
        best=BestPath.of(best_path, scenario), best_run=first_run + top, optimum=optimum,
        compile_s=found.compile_s, search_s=found.search_s,
        finish_s=found.finish_s + time.perf_counter() - t0,
        evaluations=runs * settings.population * (settings.generations + 1),
        preset=preset, devices=jax.device_count(), budget=budget_rule,
    )


def resumed(scenario: Scenario, settings: GASettings, seed: int, first_run: int,
            arrays: dict[str, np.ndarray], like: RunsResult) -> RunsResult:
    """The result of runs kept from an interrupted job (the arrays of
    :func:`hga_jax.host.report.write_partial`), with ``like``'s optimum and options."""
    history = {k[len("history."):]: v for k, v in arrays.items() if k.startswith("history.")}
    found = _Found(arrays["perm"], arrays["labels"], arrays["generation"], arrays["length"],
                   arrays["violations"], history, float(arrays["compile_s"]),
                   float(arrays["search_s"]), 0.0, arrays.get("legs"))
    res = _result(scenario, like.settings, seed, first_run, found, False, like.settings.turns,
                  like.preset, like.budget)
    res.optimum, res.devices = like.optimum, like.devices
    return res


def joined(parts: list[RunsResult]) -> RunsResult:
    """Results of consecutive run ranges of one job (the same scenario, settings and seed)
    as the one result of the whole range: the same runs, best and figures as if they had
    been searched at once (times add up)."""
    first = parts[0]
    cat = lambda name: np.concatenate([getattr(p, name) for p in parts])  # noqa: E731
    found = _Found(cat("perm"), cat("labels"), cat("generation"), cat("length"),
                   cat("violations"),
                   {k: np.concatenate([p.history[k] for p in parts], axis=1) for k in first.history},
                   sum(p.compile_s for p in parts), sum(p.search_s for p in parts),
                   sum(p.finish_s for p in parts), None if first.legs is None else cat("legs"))
    res = _result(first.scenario, first.settings, first.seed, int(first.run_ids[0]), found,
                  False, first.settings.turns, first.preset, first.budget)
    res.optimum, res.devices, res.plugins = first.optimum, first.devices, first.plugins
    return res


class _Found(NamedTuple):
    """The searched runs (one row per run, in run order) with their float64 lengths."""

    perm: np.ndarray  # (R, n) int32
    labels: np.ndarray  # (R, n + 2) int32
    generation: np.ndarray  # (R,) int64
    length: np.ndarray  # (R,) float64 metres
    violations: np.ndarray  # (R,) int64
    history: dict[str, np.ndarray]  # name -> (G + 1, R)
    compile_s: float
    search_s: float
    finish_s: float  # the float64 re-evaluation
    legs: np.ndarray | None = None  # (R, n + 2) int32 positional leg genes (free turns)


def _search(scenario: Scenario, settings: GASettings, seed: int, first_run: int, runs: int,
            chunk: int | None, progress: bool) -> _Found:
    """Search runs ``first_run .. first_run + runs - 1`` on this process's devices and
    re-evaluate their best chromosomes in float64 (``runs`` may be 0: an empty share)."""
    dtype = np.float64 if settings.precision == "float64" else np.float32
    gens, n = settings.generations, scenario.n
    if runs == 0:
        return _Found(np.zeros((0, n), np.int32), np.zeros((0, n + 2), np.int32),
                      np.zeros(0, np.int64), np.zeros(0, np.float64), np.zeros(0, np.int64),
                      {name: np.zeros((gens + 1, 0), dt)
                       for name, dt in _record_dtypes(dtype).items()}, 0.0, 0.0, 0.0,
                      np.zeros((0, n + 2), np.int32) if settings.model.genes else None)
    cut = budget.plan(n, settings, runs, chunk, jax.local_device_count(), source="run_many")
    size = cut.chunk
    sharding = _sharding()
    ks_all = np.arange(first_run, first_run + cut.batches * size, dtype=np.int32)
    if progress:
        job = _job_words(size, settings.population, gens, cut.block, cut.batches, runs)
        print(f"compiling: {job} ...", file=sys.stderr, flush=True)
    hist = {name: np.zeros((gens + 1, runs), dt) for name, dt in _record_dtypes(dtype).items()}
    bests, bar = [], None
    b = done = 0  # batch, generations done in it (for the interrupt message)
    compiling = True
    try:
        bar = bar_of(cut.batches * (gens + 1), progress,
                        f"generations of {count(runs, 'run')}" if cut.batches == 1 else
                        f"generations of {cut.batches} batches of {count(size, 'run')}")
        with jax.enable_x64(dtype == np.float64):
            sa = settings.model.search_arrays(scenario, dtype, settings.collision,
                                              settings.uses_legs)
            t0 = time.perf_counter()
            shapes = (size, cut.block, np.dtype(dtype).name, sharding is None,
                      tuple(np.shape(leaf) for leaf in jax.tree.leaves(sa)))
            data = run_keys.host_generation_key_data(seed, ks_all[:size], settings)
            keys0 = _put(_block_keys(data, 0, cut.block), sharding)
            blank = _put_tree(_blank_batch(size, sa, settings), sharding)
            last = np.int32(gens)
            block = compiled.program(("ga-block", settings.structure()) + shapes, lambda: jax.jit(
                _per_device(functools.partial(_block, steps=cut.block), sharding)
            ).lower(keys0, blank, np.int32(0), last, sa), disk=registry.builtin_only(settings),
                options=_compiler_options(settings, sa))
            compile_s, search_s = time.perf_counter() - t0, 0.0
            compiling = False
            for b, lo in enumerate(range(0, len(ks_all), size)):
                done = 0
                t0 = time.perf_counter()
                real = min(size, runs - lo)
                data = run_keys.host_generation_key_data(seed, ks_all[lo:lo + size], settings)
                state = blank
                for first in range(0, gens + 1, cut.block):
                    keys = _put(_block_keys(data, first, cut.block), sharding)
                    state, recs = block(keys, state, np.int32(first), last, sa)
                    steps = min(cut.block, gens + 1 - first)
                    _store(hist, recs, first, steps, lo, real)
                    done += steps
                    tick(bar, steps)
                bests.append(jax.tree.map(lambda a: np.asarray(a)[:real], state.best))
                search_s += time.perf_counter() - t0
    except KeyboardInterrupt:
        e = Interrupted("interrupted while compiling" if compiling else
                        f"interrupted in batch {b + 1} of {cut.batches} after {done} of "
                        f"{gens + 1} generations")
        if bests:  # the batches that finished are kept (run_many makes them a result)
            kept = sum(len(x.perm) for x in bests)
            e.found = _finished(scenario, settings, bests,
                                {k: v[:, :kept] for k, v in hist.items()}, compile_s, search_s)
        raise e from None
    finally:
        if bar is not None:
            bar.close()
    return _finished(scenario, settings, bests, hist, compile_s, search_s)


def _job_words(size: int, population: int, gens: int, block: int, batches: int,
               runs: int) -> str:
    """How a job is cut, in the numbers the user chose: ``batches of 1,000 runs x 50
    individuals, generations 0..150 in 7 steps of up to 23 each (1 batch for 1,000
    runs)``. A step is one compiled call (progress and Ctrl-C come between steps); the
    generations are those the run makes (the budget's, ``gens``), not the program's
    block length, which may be longer (its steps past ``gens`` are skipped)."""
    per = min(block, gens + 1)
    steps = -(-(gens + 1) // per)
    cut = "one step" if steps == 1 else f"{steps} steps of up to {per} each"
    return (f"batches of {count(size, 'run')} x {count(population, 'individual')}, "
            f"generations 0..{gens:,} in {cut} ({count(batches, 'batch', 'batches')} for "
            f"{count(runs, 'run')})")


def _finished(scenario: Scenario, settings: GASettings, bests, hist, compile_s: float,
              search_s: float) -> "_Found":
    """The finished batches' best chromosomes, re-evaluated in float64."""
    best = jax.tree.map(lambda *xs: np.concatenate(xs), *bests)
    t0 = time.perf_counter()
    legs = None if best.legs is None else np.asarray(best.legs, np.int32)
    d = decode64(scenario, best.perm, best.labels, settings.collision, legs)
    return _Found(np.asarray(best.perm, np.int32), np.asarray(best.labels, np.int32),
                  best.generation.astype(np.int64), d.length.astype(np.float64),
                  d.violations.astype(np.int64), hist, compile_s, search_s,
                  time.perf_counter() - t0, legs)


def _gathered(found: _Found, runs: int) -> _Found:
    """Every process's share of the runs, in run order, on every process (JAX
    collectives); the timings are the slowest process's."""
    from hga_jax.running import distributed

    t0 = time.perf_counter()
    rows = {name: getattr(found, name)
            for name in ("perm", "labels", "generation", "length", "violations")}
    if found.legs is not None:
        rows["legs"] = found.legs
    rows.update({"history." + name: h.T for name, h in found.history.items()})
    every = distributed.gather_runs(rows, runs)
    times = distributed.allgather(np.array([found.compile_s, found.search_s], np.float64))
    compile_s, search_s = (float(t) for t in times.max(axis=0))
    history = {name: np.ascontiguousarray(every.pop("history." + name).T) for name in found.history}
    return _Found(**every, history=history, compile_s=compile_s, search_s=search_s,
                  finish_s=found.finish_s + time.perf_counter() - t0)


def _compiler_options(settings, sa) -> dict:
    """XLA options of a batch's program (:func:`hga_jax.jax_compat.search_compiler_options`):
    on fewer than ``budget.LARGE_N`` obstacles where the fitness reads a turn table, the
    car only drives forward and every operator and the car model are built in (the
    measurements below are theirs); none otherwise.

    Measured (2026-12-06, 2 cores, 1,000 runs, the same evaluations, programs timed
    alternately in one process): the bundled scene's recommended program compiles in
    2.2-2.6 s of XLA's time instead of 3.2-3.8 s and searches alike (1.13 against 1.10 s;
    the paper's 0.25 against 0.28 s); from 15 obstacles on the older emitters' search
    was slower (the recommended preset's 11 % at 15, 11-20 % at 25 and 40; the paper's
    up to 60 % at 40), and there the search outweighs the compile. Runs are the same
    bits with and without them (runs and histories side by side on 284 scene, preset and
    car-model cases at 9 to 40 obstacles); a path decoded leg by leg, or a reversing
    car's, computes lengths the two emitters round differently in the last bit."""
    table, reversing = turn_table(sa, settings.collision, bool(settings.model.genes))
    if (table is None or reversing or sa.centres.shape[0] >= budget.LARGE_N
            or not registry.builtin_only(settings)):
        return {}
    return jax_compat.search_compiler_options()


def _block_keys(data: np.ndarray, first: int, steps: int):
    """The keys of generations ``first .. first + steps - 1`` of a batch, ``(R, steps)``, from
    the batch's key data ``(R, G + 1, 2)``; past generation G the last key stands in (its
    step is skipped)."""
    cols = np.minimum(np.arange(first, first + steps), data.shape[1] - 1)
    return rng.wrap(data[:, cols])


def _block(keys, core, first, last, sa, steps: int):
    """Generations ``first .. first + steps - 1`` of a batch of runs, one compiled
    program for every block: a scan over the generations whose body is
    :func:`hga_jax.search.ga.step` vmapped over the runs (axis ``ga.RUNS``), each run
    on its generation keys ``keys`` (R, steps) (as :func:`hga_jax.search.ga.steps`
    for one run; the same bits. Traced under the vmap at once, the generation is
    traced once: a vmap around the scan traced it, then batched the trace again,
    0.5 s of a 3.1 s compile). ``core`` is the batch's state without its problem
    (``sa`` is passed apart, not carried) and with one generation count for all its
    runs (not batched, so that "some run restarts" in generation 0 needs no
    collective between devices). ``last`` is the run's last generation G, data (not
    the program's structure, so jobs that differ only in G share the program); the
    steps past it are skipped (a branch: the state as it was)."""
    idx = first + jnp.arange(steps, dtype=jnp.int32)
    axes = _run_axes(core)

    def one(k, st):
        return ga.step(k, st._replace(problem=sa))._replace(problem=None)

    batch = jax.vmap(one, in_axes=(0, axes), out_axes=axes, axis_name=ga.RUNS)
    records = jax.vmap(ga.record, in_axes=(axes,))

    def body(st, xs):
        k, on = xs
        st = jax.lax.cond(on, batch, lambda _, c: c, k, st) if steps > 1 else batch(k, st)
        return st, records(st)

    ks = jnp.moveaxis(keys, 1, 0)  # (steps, R, ...)
    core, recs = jax.lax.scan(body, core, (ks, idx <= last))
    return core, jax.tree.map(lambda r: jnp.moveaxis(r, 0, 1), recs)


def _run_axes(core):
    """The run axis of each leaf of a batch's state: 0, but none for the generation count and
    the rates (one for the batch)."""
    return jax.tree.map(lambda a: None if np.ndim(a) == 0 else 0, core)


def _per_device(block, sharding):
    """``block`` as the compiled batch program: split over the devices by the sharded
    ``jit`` itself in a single process; in a multi-process job, run by each device on
    its own share of the runs (``shard_map``), so that a generation's "some run
    restarts" (:func:`~hga_jax.jax_compat.any_run`) is asked of the device's
    runs, with no collective between the devices (on the CPU those go through Gloo,
    which prints on standard output). The runs are the same either way; ``shard_map``
    measured about 20% slower on one process's two devices."""
    if sharding is None or jax.process_count() == 1:
        return block
    runs, whole = jax.sharding.PartitionSpec(_DEVICES), jax.sharding.PartitionSpec()

    def program(keys, core, first, last, sa):
        specs = jax.tree.map(lambda a: whole if a is None else runs, _run_axes(core),
                             is_leaf=lambda a: a is None)
        return jax.shard_map(block, mesh=sharding.mesh,
                             in_specs=(runs, specs, whole, whole, whole),
                             out_specs=(specs, runs), check_vma=False)(keys, core, first, last, sa)

    return program


def _blank_batch(size: int, sa, settings: GASettings) -> Any:
    """:func:`hga_jax.search.ga.blank` for ``size`` runs (a leading run axis), without
    its problem, as numpy arrays: no device program runs to make it."""
    one = ga.blank(sa, settings)._replace(problem=None)
    batch = jax.tree.map(lambda a: np.broadcast_to(a, (size,) + np.shape(a)), one)
    # one generation count and one set of rates for the batch
    return batch._replace(generation=one.generation, rates=one.rates)


def _put(ks: np.ndarray, sharding: Any) -> Any:
    return jax.device_put(ks, sharding) if sharding else ks


def _put_tree(tree: Any, sharding: Any) -> Any:
    """``tree``'s leaves split over the devices by runs; a scalar (the generation
    count) replicated."""
    if not sharding:
        return tree
    every = jax.sharding.NamedSharding(sharding.mesh, jax.sharding.PartitionSpec())
    return jax.tree.map(lambda a: jax.device_put(a, every if np.ndim(a) == 0 else sharding), tree)


def _record_dtypes(dtype: Any) -> dict[str, Any]:
    """The history's arrays: one per field of :class:`~hga_jax.search.ga.Record`."""
    return {name: (np.int32 if name.endswith("violations") else dtype) for name in Record._fields}


def _store(hist: dict[str, np.ndarray], rec: Any, first: int, steps: int, lo: int,
           real: int) -> None:
    """Copy records of ``steps`` generations from ``first`` of the batch's ``real`` runs."""
    for name, value in rec._asdict().items():
        v = np.asarray(value)[:real]
        hist[name][first:first + steps, lo:lo + real] = v.reshape(real, -1)[:, :steps].T
