"""Everything of the search that depends on JAX's version, in one place.

hga-jax pins ``jax>=0.10.2,<0.11`` because a seed's random stream is part of
what the seed means. Moving to another JAX release (0.11 and later need
Python 3.12) is a change of this file, checked by ``tests/test_rng.py``
(the stream against ``jax.random``) and the seeded result tests:

- :func:`define_prng_impl`: JAX's hook for a PRNG implementation of our own
  (``jax.extend.random``, an API JAX may move), used by :mod:`hga_jax.search.rng`;
- :func:`fixed_stream`: the threefry layout a seed was defined with
  (``jax_threefry_partitionable`` off, whatever the caller's setting);
- :func:`any_run`: a flag over the runs of a vmapped batch (a collective over the
  named ``vmap`` axis, or the run's own flag when there is no batch);
- :func:`static_pytree`: a hashable settings class as a pytree without leaves;
- :func:`save_executable` / :func:`load_executable`: a compiled program as bytes and
  back (``jax.experimental.serialize_executable``), for :mod:`hga_jax.compiled`;
- :func:`search_compiler_options`: the XLA options the GA's search is compiled with
  (an option of this XLA's CPU backend), and :func:`compile_with_options`, which
  compiles with XLA's defaults where this XLA does not know an option (JAX's error text).
"""
from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
from jax.extend.random import define_prng_impl

__all__ = ["RUNS", "SEARCH_COMPILER_OPTIONS", "any_run", "compile_with_options",
           "define_prng_impl", "fixed_stream",
           "load_executable", "save_executable", "search_compiler_options", "static_pytree"]

RUNS = "runs"
"""The name of the ``vmap`` axis over the runs of a batch (``jax.vmap(..., axis_name=RUNS)``)."""


def fixed_stream(fn):
    """``fn`` drawing its random bits with ``jax_threefry_partitionable`` off (the
    original threefry layout, the one a seed means; it also compiles faster on CPU)."""

    @functools.wraps(fn)
    def wrapped(*args, **kwargs):
        with jax.threefry_partitionable(False):
            return fn(*args, **kwargs)

    return wrapped


def any_run(flag):
    """Whether ``flag`` (a bool scalar of one run) holds for any run of the batch.

    Under ``jax.vmap(..., axis_name=RUNS)`` this is one value for the whole batch
    (not batched), so a ``lax.cond`` on it stays a branch and is not turned into a
    select of both sides; outside such a ``vmap`` it is the run's own flag.
    """
    try:
        return jax.lax.psum(jnp.asarray(flag, jnp.int32), RUNS) > 0
    except NameError:  # no vmapped batch of runs around this call: JAX's "unbound axis name"
        return jnp.asarray(flag)


def static_pytree(cls):
    """Register the frozen, hashable class ``cls`` as a pytree with no leaves: an
    instance inside a state is static (part of the compiled program's identity)."""
    jax.tree_util.register_static(cls)
    return cls


def save_executable(compiled) -> tuple:
    """``compiled`` (a ``jax.stages.Compiled``) as a picklable tuple: the executable's
    bytes, its input and output tree structures and the ids of the devices it runs on."""
    from jax.experimental import serialize_executable

    devices = compiled._executable.xla_executable.local_devices()
    return (*serialize_executable.serialize(compiled), tuple(d.id for d in devices))


def load_executable(payload, in_tree, out_tree, device_ids):
    """The ``jax.stages.Compiled`` that :func:`save_executable` gave the tuple for,
    loaded onto the same devices of this process's backend."""
    import jax
    from jax.experimental import serialize_executable

    by_id = {d.id: d for d in jax.local_devices()}
    return serialize_executable.deserialize_and_load(
        payload, in_tree, out_tree, execution_devices=[by_id[i] for i in device_ids])


SEARCH_COMPILER_OPTIONS = {"xla_cpu_use_fusion_emitters": False}
"""XLA options of the GA's compiled search on the CPU where the runner asks for them
(``_compiler_options`` of :mod:`hga_jax.running.runner`: small scenes): XLA's older loop
emitters instead of its fusion emitters, which compile the bundled scene's program in
about 1 s less. An option of this XLA; where it is unknown the program compiles with
the defaults (:func:`hga_jax.compiled.program`)."""


def search_compiler_options() -> dict:
    """:data:`SEARCH_COMPILER_OPTIONS` on the CPU backend, none on others (for
    :func:`hga_jax.compiled.program`, which compiles without them where this XLA
    does not know them)."""
    return dict(SEARCH_COMPILER_OPTIONS) if jax.default_backend() == "cpu" else {}


def compile_with_options(lower, options: dict):
    """``lower().compile()`` with the XLA compiler ``options``; where this XLA does not
    know one of them (JAX's runtime error "No such compile option"), without them."""
    if not options:
        return lower().compile()
    try:
        return lower().compile(compiler_options=options)
    except Exception as e:  # JAX's runtime error of an unknown option
        if "No such compile option" not in str(e):
            raise
        return lower().compile()
