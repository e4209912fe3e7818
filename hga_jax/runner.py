"""Host side of many seeded runs: chunking, sharding, timing, float64 re-evaluation.

``run_many`` compiles one batch shape (a chunk of runs), feeds it chunks of run
indices (the last one padded), shards each chunk over the devices when there
are several, and re-evaluates every run's best chromosome in float64 before
anything is reported.
"""
from __future__ import annotations

import math
import os
import sys
import time
from typing import Any

import jax
import numpy as np

from .errors import ConfigError
from .exact import solve
from .fitness import fitness_of
from .ga import run_batch
from .path import decode64, evaluate_path
from .results import RunsResult
from .scenario import Scenario
from .settings import GASettings

CHROMOSOMES_PER_CHUNK = 50_000  # beyond this the working set leaves the cache
_COMPILED: dict[Any, Any] = {}  # recent compiled batches (a study reuses them across scenes)
_COMPILED_KEEP = 16


def enable_compilation_cache(path: str | None = None) -> str | None:
    """Keep compiled GA programs on disk, so a repeated run skips most of its compile.

    ``path`` defaults to ``$HGA_JAX_CACHE_DIR``, else ``$XDG_CACHE_HOME/hga-jax/xla``
    (``~/.cache/hga-jax/xla``); ``HGA_JAX_CACHE_DIR=off`` disables it. Sets JAX's
    global compilation-cache option (the command line does this; notebooks may).
    Returns the folder used, or None. A folder that cannot be created only costs
    compile time.
    """
    where = path if path is not None else os.environ.get("HGA_JAX_CACHE_DIR")
    if where in ("", "off"):
        return None
    if where is None:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        where = os.path.join(base, "hga-jax", "xla")
    try:
        os.makedirs(where, exist_ok=True)
    except OSError:
        return None
    jax.config.update("jax_compilation_cache_dir", where)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
    return where


def settings_for(scenario: Scenario, base: GASettings | None = None) -> GASettings:
    """The scenario's ``[ga]`` table on top of ``base`` (default: the paper's settings)."""
    return GASettings.from_mapping(scenario.ga, scenario.source, base=base)


def _sharding():
    """Split the run axis over all devices when there are several (None: one device)."""
    devices = jax.devices()
    if len(devices) < 2:
        return None
    mesh = jax.sharding.Mesh(np.asarray(devices), ("runs",))
    return jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("runs"))


def run_many(scenario: Scenario, settings: GASettings | None = None, *, seed: int = 0,
             runs: int = 1, first_run: int = 0, chunk: int | None = None,
             exact: bool = True, progress: bool = False) -> RunsResult:
    """Runs ``first_run .. first_run + runs - 1`` of ``seed`` on ``scenario``.

    ``settings`` defaults to the scenario's ``[ga]`` table over the paper's
    settings. ``exact`` also solves the model's optimum and reports the gap.
    """
    settings = settings or settings_for(scenario)
    for key, value, low, high in (("seed", seed, 0, 2**32), ("runs", runs, 1, 2**31),
                                  ("first_run", first_run, 0, 2**31 - runs)):
        if not (isinstance(value, (int, np.integer)) and low <= value < high):
            raise ConfigError(f"run_many: {key}: must be an integer in {low}..{high - 1}, "
                              f"got {value!r}")
    dtype = np.float64 if settings.precision == "float64" else np.float32
    chunk = chunk or max(1, CHROMOSOMES_PER_CHUNK // settings.population)
    chunk = min(chunk, runs)
    devices = jax.device_count()
    chunk = math.ceil(chunk / devices) * devices
    sharding = _sharding()
    ks_all = np.arange(first_run, first_run + math.ceil(runs / chunk) * chunk, dtype=np.int32)

    def fn(ks, sa):
        return run_batch(seed, ks, sa, settings)

    if progress:
        print(f"compiling {chunk} runs x {settings.generations + 1} generations x "
              f"{settings.population} individuals ...", file=sys.stderr, flush=True)
    with jax.enable_x64(dtype == np.float64):
        sa = scenario.arrays(dtype)
        t0 = time.perf_counter()
        ks0 = ks_all[:chunk]
        ks0 = jax.device_put(ks0, sharding) if sharding else ks0
        # The program depends on the seed, settings, chunk and array shapes, not on
        # the scenario's values: scenes of one size share it.
        memo = (seed, settings, chunk, np.dtype(dtype).name, sharding is None,
                tuple(np.shape(a) for a in sa))
        compiled = _COMPILED.pop(memo, None) or jax.jit(fn).lower(ks0, sa).compile()
        _COMPILED[memo] = compiled
        while len(_COMPILED) > _COMPILED_KEEP:
            _COMPILED.pop(next(iter(_COMPILED)))
        compile_s = time.perf_counter() - t0
        t0 = time.perf_counter()
        outs = []
        bar = _progress(runs, progress)
        for start in range(0, len(ks_all), chunk):
            ks = ks_all[start:start + chunk]
            ks = jax.device_put(ks, sharding) if sharding else ks
            best, hist = compiled(ks, sa)
            outs.append(jax.tree.map(np.asarray, (best, hist)))
            if bar is not None:
                bar.update(min(chunk, runs - start))
        if bar is not None:
            bar.close()
        search_s = time.perf_counter() - t0
    best, hist = jax.tree.map(lambda *xs: np.concatenate(xs)[:runs], *outs)

    t0 = time.perf_counter()
    d = decode64(scenario, best.perm, best.labels, settings.collision)
    length, violations = d.length.astype(np.float64), d.violations.astype(np.int64)
    # The best run: the shortest feasible path if any run has one, else the fittest.
    score = fitness_of(length, violations, scenario.delta)
    pool = np.flatnonzero(violations == 0) if np.any(violations == 0) else np.arange(runs)
    top = int(pool[np.argmax(score[pool])])
    best_path = evaluate_path(scenario, best.perm[top], best.labels[top], settings.collision)
    optimum = solve(scenario, settings.collision) if exact else None
    return RunsResult(
        scenario=scenario, settings=settings, seed=seed,
        run_ids=np.arange(first_run, first_run + runs),
        perm=best.perm, labels=best.labels, length=length, violations=violations,
        generation=best.generation.astype(np.int64),
        history={k: np.asarray(v).T for k, v in hist._asdict().items()},  # (G + 1, runs)
        best=best_path, best_run=first_run + top, optimum=optimum,
        compile_s=compile_s, search_s=search_s, finish_s=time.perf_counter() - t0,
        evaluations=runs * settings.population * (settings.generations + 1),
    )


def _progress(total: int, enabled: bool) -> Any:
    if not enabled:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=total, unit="run", desc="runs", leave=False)
