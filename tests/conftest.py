"""Test configuration. Hypothesis runs derandomized in CI so a run is repeatable;
locally it explores new examples each time (``HYPOTHESIS_PROFILE=deep`` for many more)."""
import atexit
import os
import shutil
import tempfile

import _xla
import pytest
from hypothesis import settings

# One folder of compiled programs for the whole test session, in a temporary folder
# removed at the end: tests that compile the same program (in this process, in
# pytest-xdist's workers or in command-line subprocesses, which inherit
# HGA_JAX_CACHE_DIR) compile it once. Nothing is kept between sessions, so every session still compiles each program
# once. The tests of the cache itself give their subprocesses folders of their own.
# HGA_JAX_TEST_CACHE=off runs the session without one.
if "HGA_JAX_TEST_CACHE" not in os.environ:  # the first process of the session makes it
    os.environ["HGA_JAX_TEST_CACHE"] = tempfile.mkdtemp(prefix="hga-jax-test-programs-")
    atexit.register(shutil.rmtree, os.environ["HGA_JAX_TEST_CACHE"], ignore_errors=True)
os.environ["HGA_JAX_CACHE_DIR"] = os.environ["HGA_JAX_TEST_CACHE"]


# The default lane (not the slow studies or the benchmarks, which search far more than
# they compile) builds its programs with XLA's backend optimisation level 0 (LLVM then
# skips its optimisation passes) and XLA's loop emitters (as a user's search at fewer
# than 15 obstacles is built, hga_jax.jax_compat.SEARCH_COMPILER_OPTIONS): together they
# cut the lane's XLA compiles from about 210 to about 95 s of its workers' time, and the
# lane's programs search more slowly. The searches are the same bits, as measured (no
# float32 step of a run changed; a float64 re-evaluated length may differ in its last
# bit): test_lane_programs.py checks it against the programs a user's process builds.
# HGA_JAX_TEST_XLA_LEVEL=default (or XLA_FLAGS naming either flag) keeps the defaults.


def _default_lane(config) -> bool:
    return "not slow" in (config.option.markexpr or "")


def pytest_configure(config):
    flags = os.environ.get("XLA_FLAGS", "")
    if (_default_lane(config) and os.environ.get("HGA_JAX_TEST_XLA_LEVEL") != "default"
            and _xla.LEVEL not in flags and _xla.LOOP_EMITTERS not in flags):
        os.environ["XLA_FLAGS"] = " ".join([flags, *_xla.LANE_FLAGS]).strip()  # before JAX starts
    from hga_jax.compiled import enable_compilation_cache

    enable_compilation_cache()  # as the command line does


settings.register_profile("dev", max_examples=150, deadline=None)
settings.register_profile("ci", max_examples=150, deadline=None, derandomize=True, print_blob=True)
settings.register_profile("deep", max_examples=3000, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI") else "dev"))


@pytest.fixture
def registries():
    """Restore the operator and car-model registries after a test that registers its own."""
    from hga_jax.model import car_model
    from hga_jax.search import registry

    with registry.isolated(), car_model.isolated():
        yield
