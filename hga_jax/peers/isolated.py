"""A peer's runs in a worker process: a crash in the peer's native code ends the
worker, not the study.

OMPL's BIT* ends its process with a segmentation fault now and then under repeated
planning requests (an open OMPL report, ompl/ompl#1317; here once in two runs of
``configs/studies/reeds_shepp.toml``). A study calls its OMPL cells through
:func:`call`: one worker process, spawned (a fresh interpreter: no JAX threads forked
into it) and kept for the calls that follow. Where the worker dies, the call is made
again in a fresh worker; after ``retries`` such deaths it raises
:class:`~hga_jax.errors.PeerCrashed`, whose one-line message names the peer. The
study's finished cells are on disk already, so running the study again resumes it.

Host code. ``fn`` and its arguments must pickle (a module-level function, plain data
and scenarios).
"""
from __future__ import annotations

import atexit
import concurrent.futures as cf
import multiprocessing
from typing import Any, Callable

from hga_jax.errors import PeerCrashed

_worker: cf.ProcessPoolExecutor | None = None


def call(fn: Callable[..., Any], *args: Any, what: str = "a peer", retries: int = 1) -> Any:
    """``fn(*args)`` in the worker process; made again in a fresh worker after the
    worker dies, at most ``retries`` times (``what``: the peer, for the message)."""
    global _worker
    for _ in range(retries + 1):
        if _worker is None:
            _worker = cf.ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
        try:
            return _worker.submit(fn, *args).result()
        except cf.process.BrokenProcessPool:
            _worker.shutdown(wait=False, cancel_futures=True)
            _worker = None
    raise PeerCrashed(f"{what} crashed {retries + 1} times in a row (its process died; "
                      "the finished cells are kept: run the study again to resume)")


def close() -> None:
    """Ends the worker process, if one runs (also at exit: an executor left to the
    interpreter's shutdown prints an ignored exception from its clean-up thread)."""
    global _worker
    if _worker is not None:
        _worker.shutdown(wait=True, cancel_futures=True)
        _worker = None


atexit.register(close)
