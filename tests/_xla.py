"""XLA flags for a test's subprocess that sets flags of its own: the lane's backend
optimisation level (conftest.py) kept, so the subprocess compiles as the lane does."""
import os


def flags(extra: str = "") -> str:
    level = [f for f in os.environ.get("XLA_FLAGS", "").split()
             if f.startswith("--xla_backend_optimization_level")]
    return " ".join(level + ([extra] if extra else []))
