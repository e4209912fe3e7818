"""One job over several processes, with JAX's own multi-process runtime.

Every process runs the same job (the same command, or the same ``run_many``
call) after :func:`initialize`, which is ``jax.distributed.initialize`` with the
CPU collectives set to Gloo (TCP). Process ``p`` of ``P`` searches its
contiguous :func:`share` of the run indices on its own devices; the per-run
results are then gathered to every process with a JAX collective
(``jax.experimental.multihost_utils.process_allgather``) and put back in run
order, so the merged result is the one a single process computes: run ``k`` of
seed ``s`` depends on ``(s, k)`` alone.

Host code only: nothing here is traced. Gloo announces each connection it
makes on standard output ("[Gloo] Rank 0 is connected to 1 peer ranks ...");
collectives run with file descriptor 1 pointed at ``/dev/null``, so standard
output carries hga-jax's output alone (errors go to standard error as ever).
"""
from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from typing import Any, Callable, TypeVar

import jax
import numpy as np

from hga_jax.errors import ConfigError

MESSAGE_BYTES = 2048  # an error message shared by :func:`together` is cut to this (UTF-8)

T = TypeVar("T")


def initialize(coordinator: str | None = None, num_processes: int | None = None,
               process_id: int | None = None, *, source: str = "initialize") -> tuple[int, int]:
    """Join a multi-process job; call it before any other JAX call. Returns
    ``(process index, process count)``.

    ``coordinator`` is process 0's ``"HOST:PORT"`` (the same for every process;
    process 0 listens on that port), ``num_processes`` the job's process count
    and ``process_id`` this process's number ``0 .. num_processes - 1``. Left
    out (None), they are read from ``JAX_COORDINATOR_ADDRESS`` or detected by
    ``jax.distributed`` from the cluster's environment (SLURM's ``srun``, Open
    MPI's ``mpirun``, ...). Processes wait up to 300 s for each other; one
    that is not joined by then is stopped by JAX's runtime with its own
    message. ``source`` names the caller in a :class:`ConfigError` (one line),
    e.g. ``"command line"``.
    """
    flags = {"coordinator": coordinator, "num_processes": num_processes,
             "process_id": process_id}
    if source == "command line":
        flags = {"--" + k.replace("_", "-"): v for k, v in flags.items()}
    for name, value, low in ((list(flags)[1], num_processes, 1), (list(flags)[2], process_id, 0)):
        if value is not None and not (isinstance(value, (int, np.integer)) and value >= low):
            raise ConfigError(f"{source}: {name}: must be an integer >= {low}, got {value!r}")
    if num_processes is not None and process_id is not None and process_id >= num_processes:
        raise ConfigError(f"{source}: {list(flags)[2]}: must be in 0..{num_processes - 1} "
                          f"(with {num_processes} processes), got {process_id}")
    if not os.environ.get("JAX_CPU_COLLECTIVES_IMPLEMENTATION"):
        jax.config.update("jax_cpu_collectives_implementation", "gloo")
    try:
        jax.distributed.initialize(coordinator, None if num_processes is None else
                                   int(num_processes), None if process_id is None else
                                   int(process_id))
    except ValueError as e:  # a value neither given nor found in the environment
        missing = ", ".join(k for k, v in flags.items() if v is None)
        raise ConfigError(f"{source}: {missing}: not given, and no cluster environment (SLURM, "
                          f"Open MPI) to read them from ({e})") from None
    except RuntimeError as e:
        raise ConfigError(f"{source}: cannot join a multi-process job: "
                          + " ".join(str(e).split())) from None
    return jax.process_index(), jax.process_count()


def share(first_run: int, runs: int, index: int, count: int) -> tuple[int, int]:
    """Process ``index`` of ``count``'s share of runs ``first_run .. first_run + runs - 1``:
    ``(its first run, how many)``. Shares are contiguous and in process order; the
    first ``runs % count`` processes take one run more (a share may be empty)."""
    base, extra = divmod(runs, count)
    return first_run + index * base + min(index, extra), base + (index < extra)


def allgather(tree: Any) -> Any:
    """Every process's ``tree`` of numpy arrays (the same shapes and dtypes on all),
    stacked along a new first axis in process order, on every process. Values
    travel bit for bit (64-bit types stay 64-bit)."""
    from jax.experimental import multihost_utils

    with _stdout_muted(), jax.enable_x64(True):
        return multihost_utils.process_allgather(tree)


def gather_runs(rows: dict[str, np.ndarray], runs: int) -> dict[str, np.ndarray]:
    """The whole job's rows, in run order, on every process.

    ``rows``: this process's arrays, one row per run of its :func:`share` (axis
    0), in run order; ``runs``: the job's run count. Shares are padded to the
    largest for the collective, and the padding dropped after it.
    """
    count, me = jax.process_count(), jax.process_index()
    sizes = [share(0, runs, p, count)[1] for p in range(count)]
    width = sizes[0]
    for name, v in rows.items():
        if len(v) != sizes[me]:
            raise ValueError(f"gather_runs: {name}: {len(v)} rows, share of process {me} is "
                             f"{sizes[me]}")
    padded = {name: np.concatenate([v, np.zeros((width - len(v),) + v.shape[1:], v.dtype)])
              for name, v in rows.items()}
    every = allgather(padded)
    return {name: np.concatenate([v[p, :sizes[p]] for p in range(count)])
            for name, v in every.items()}


def together(check: Callable[[], T]) -> T:
    """``check()`` on every process; if it raises :class:`ConfigError` on any, every
    process raises the first one's (lowest process index), so the job stops as a
    whole, with one message, instead of leaving the others waiting."""
    message, value = "", None
    try:
        value = check()
    except ConfigError as e:
        message = str(e) or "ConfigError"
    data = message.encode()[:MESSAGE_BYTES]
    mine = {"length": np.array([len(data)], np.int32),
            "text": np.frombuffer(data.ljust(MESSAGE_BYTES, b"\0"), np.uint8)}
    every = allgather(mine)
    for length, text in zip(every["length"][:, 0], every["text"]):
        if length:
            raise ConfigError(bytes(text[:length]).decode(errors="replace"))
    return value


@contextlib.contextmanager
def _stdout_muted():
    """File descriptor 1 pointed at ``/dev/null`` meanwhile (C buffers flushed before
    and after), so what a library prints there does not mix with our output."""
    with contextlib.suppress(OSError, ValueError):
        sys.stdout.flush()
    libc = ctypes.CDLL(None)
    libc.fflush(None)
    try:
        saved = os.dup(1)
        null = os.open(os.devnull, os.O_WRONLY)
    except OSError:  # no standard output to mute
        yield
        return
    os.dup2(null, 1)
    os.close(null)
    try:
        yield
    finally:
        libc.fflush(None)
        os.dup2(saved, 1)
        os.close(saved)
