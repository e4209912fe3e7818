"""Sizing a job before it starts: runs per batch, generations per block, memory.

A job of ``runs`` runs is done in batches of ``chunk`` runs (one compiled batch
shape), each batch in blocks of ``block`` generations (one compiled call each, so
the host can report progress and stop on Ctrl-C between blocks). Memory is
estimated before anything is compiled:

- on the device, per batch: the populations and their evaluation's working set
  (``DEVICE_BYTES_PER_GENE`` bytes per gene and individual, measured with XLA's
  memory analysis of the compiled programs: at most 97 at n = 0, 9 and 28, so
  about twice that is planned), the generation keys (8 bytes per run and
  generation) and one block of records;
- once: the scenario's turn table (up to about 200 MB at 100 obstacles);
- on the host, for the whole job: the history (5 figures of 4 bytes per run and
  generation, kept twice while statistics are taken) and the per-run results.

On the CPU the device is the host, so both come out of the same memory. A
batch is shrunk until it fits in ``FILL`` of the memory available; a job whose
results, or a single run, cannot fit is refused with a one-line
:class:`ConfigError` that says what would fit.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

from hga_jax.errors import ConfigError
from hga_jax.search.settings import GASettings

CHROMOSOMES_PER_CHUNK = 50_000  # beyond this the working set leaves the cache
# From 15 obstacles on, a chromosome's genes (and the guided move's view of them) crowd
# the cache sooner. 1,000 runs x 50, the paper's budget, batches of 1,000 runs against
# 200 (2026-12-04): the recommended preset 1.47 -> 1.17 s at n = 15 and 2.9 -> 1.9 s at
# n = 25, the paper's 0.34 -> 0.33 s and 0.70 -> 0.41 s; at n = 9 either size alike.
# Earlier: at n = 100, 0.29 M evaluations/s in batches of 1000 runs, 0.46 M/s in
# batches of 200 (0.26 M/s at 300); n = 50: 0.91 -> 1.10-1.25 M/s.
CHROMOSOMES_PER_CHUNK_LARGE_N = 10_000
LARGE_N = 15
BLOCK_WORK = 10_000_000  # evaluations x obstacles per block: about 0.2 s on one CPU core
DEVICE_BYTES_PER_GENE = 160  # per individual and gene (n + 2 genes); measured: at most 97
DEVICE_BYTES_FIXED = 256  # per individual: selection, records
HOST_BYTES_PER_RUN = 4096  # per run: best chromosome, statistics, its result.json entry
HISTORY_BYTES = 2 * 5 * 4  # per run and generation: the history, twice
FILL = 0.8  # fraction of the available memory a job may plan to use


@dataclass(frozen=True)
class Plan:
    """How a job is cut: ``chunk`` runs per batch, ``batches`` batches, ``block``
    generations per compiled call; the estimated bytes of one batch on the device
    and of the whole job on the host."""

    chunk: int
    batches: int
    block: int
    device_bytes: int
    host_bytes: int


def available_bytes() -> int:
    """Memory the job may use: the device's limit when it reports one, else the host's
    available memory (``MemAvailable``, or physical memory where that is unknown)."""
    try:
        import jax

        stats = jax.local_devices()[0].memory_stats() or {}
        if stats.get("bytes_limit"):
            return int(stats["bytes_limit"]) - int(stats.get("bytes_in_use", 0))
    except Exception:  # noqa: BLE001 - no device statistics: use the host's figure
        pass
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def device_bytes(n: int, settings: GASettings, chunk: int, block: int) -> int:
    """Estimated device memory of one batch of ``chunk`` runs (bytes)."""
    per_individual = DEVICE_BYTES_PER_GENE * (n + 2) + DEVICE_BYTES_FIXED
    per_run = (settings.population * per_individual + 8 * settings.generations
               + 20 * (block + 1))
    return chunk * per_run


def table_bytes(n: int, settings: GASettings) -> int:
    """The scenario's turn table (:mod:`hga_jax.model.turns`), held once: two floats per turn
    in the search precision, and the float64 table it is cast from."""
    from hga_jax.model import turns

    if not turns.fits(n):
        return 0
    size = 8 if settings.precision == "float64" else 4
    return turns.entries(n) * 2 * (size + 8)


def host_bytes(n: int, settings: GASettings, runs: int) -> int:
    """Estimated host memory of the results of ``runs`` runs (bytes)."""
    return runs * (HISTORY_BYTES * (settings.generations + 1) + HOST_BYTES_PER_RUN + 64 * n)


def _size(b: int) -> str:
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if b >= scale:
            return f"{b / scale:.1f} {unit}"
    return f"{b / 1e3:.1f} kB"


def _setting(source: str, key: str, value: int) -> str:
    """``--runs 5`` on the command line, ``runs=5`` in Python."""
    return f"--{key} {value:,}" if source == "command line" else f"{key}={value}"


def block_length(n: int, population: int, chunk: int, generations: int) -> int:
    """Generations per compiled call: about ``BLOCK_WORK`` evaluations x obstacles, and no
    more than the power of two at or above the job's ``generations + 1`` (generation 0
    counts). The length does not follow the generation count further, so jobs that differ
    only in it run one program (a budget sweep, a rerun with more generations): the steps of
    a last block that run past generation G are skipped."""
    work = math.ceil(BLOCK_WORK / max(n, 4) / (chunk * population))
    return max(1, min(work, 1 << max(0, generations).bit_length()))


def plan(n: int, settings: GASettings, runs: int, chunk: int | None, devices: int = 1,
         available: int | None = None, source: str = "command line") -> Plan:
    """Cut a job of ``runs`` runs, or refuse it (one line naming what would fit).

    ``chunk``: runs per batch asked for (None: about ``CHROMOSOMES_PER_CHUNK``
    chromosomes per batch, ``CHROMOSOMES_PER_CHUNK_LARGE_N`` from ``LARGE_N``
    obstacles on); it is lowered to what fits and rounded up to a
    multiple of ``devices``.
    """
    settings = settings.for_obstacles(n)
    avail = int(FILL * (available_bytes() if available is None else available))
    avail -= table_bytes(n, settings)
    p, g = settings.population, settings.generations
    host = host_bytes(n, settings, runs)
    one_run = device_bytes(n, settings, devices, 1) // devices
    if host > avail:
        fit = avail // max(1, host_bytes(n, settings, 1))
        what = (f"{_setting(source, 'runs', fit)} would" if fit else
                "fewer generations would")
        raise ConfigError(
            f"{source}: runs: {runs:,} run{'s' if runs != 1 else ''} of {g:,} generations need "
            f"about {_size(host)} of memory for their results, {_size(avail)} is available; "
            f"{what} fit")
    per_chunk = CHROMOSOMES_PER_CHUNK if n < LARGE_N else CHROMOSOMES_PER_CHUNK_LARGE_N
    want = chunk or max(1, per_chunk // p)
    want = min(want, runs)
    fit_runs = (avail - host) // max(1, one_run)
    if fit_runs < devices:
        per_individual = DEVICE_BYTES_PER_GENE * (n + 2) + DEVICE_BYTES_FIXED
        fit_pop = (avail - host) // devices // per_individual
        raise ConfigError(
            f"{source}: population: one run of population {p:,} needs about "
            f"{_size(one_run)} of memory, {_size(avail - host)} is available; "
            f"{_setting(source, 'population', max(2, fit_pop))} would fit")
    size = min(want, fit_runs)
    size = max(devices, math.ceil(size / devices) * devices)
    if size > fit_runs:
        size -= devices
    block = block_length(n, p, size, g)
    return Plan(chunk=size, batches=math.ceil(runs / size), block=block,
                device_bytes=device_bytes(n, settings, size, block), host_bytes=host)
