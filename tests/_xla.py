"""XLA flags of the test lanes. The default lane builds its programs at XLA's backend
optimisation level 0 (``LANE_LEVEL``, set by conftest.py); a test's subprocess that sets
flags of its own keeps that level (:func:`flags`), and one that must build as a user's
program does drops it (:func:`without_level`)."""
import os

LEVEL = "--xla_backend_optimization_level"
LANE_LEVEL = f"{LEVEL}=0"


def _split() -> tuple[list[str], list[str]]:
    given = os.environ.get("XLA_FLAGS", "").split()
    return [f for f in given if f.startswith(LEVEL)], [f for f in given if not f.startswith(LEVEL)]


def flags(extra: str = "") -> str:
    """The lane's level (if set) and ``extra``."""
    return " ".join(_split()[0] + ([extra] if extra else []))


def without_level() -> str:
    """``XLA_FLAGS`` without a backend optimisation level: XLA's default."""
    return " ".join(_split()[1])
