"""Test configuration. Hypothesis runs derandomized in CI so a run is repeatable;
locally it explores new examples each time (``HYPOTHESIS_PROFILE=deep`` for many more)."""
import os

import pytest
from hypothesis import settings

# In-process command-line tests keep no compiled programs on disk (one test
# checks the cache in subprocesses with a folder of its own).
os.environ["HGA_JAX_CACHE_DIR"] = "off"

settings.register_profile("dev", max_examples=150, deadline=None)
settings.register_profile("ci", max_examples=150, deadline=None, derandomize=True, print_blob=True)
settings.register_profile("deep", max_examples=3000, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE") or ("ci" if os.environ.get("CI") else "dev"))


@pytest.fixture
def registries():
    """Restore the operator registries after a test that registers its own operators."""
    from hga_jax.search import registry

    with registry.isolated():
        yield
