"""XLA flags of the test lanes. The default lane builds its programs at XLA's backend
optimisation level 0 and with XLA's loop emitters (``LANE_FLAGS``, set by conftest.py:
both shorten a compile); a test's subprocess that sets flags of its own keeps them
(:func:`flags`), and one that must build as a user's program does drops them
(:func:`without_lane_flags`)."""
import os

LEVEL = "--xla_backend_optimization_level"
LANE_LEVEL = f"{LEVEL}=0"
# The option a user's small-scene search is compiled with (hga_jax.jax_compat's
# SEARCH_COMPILER_OPTIONS), here as a flag for every program of the lane.
LOOP_EMITTERS = "--xla_cpu_use_fusion_emitters"
LANE_FLAGS = (LANE_LEVEL, f"{LOOP_EMITTERS}=false")


def _lane(flag: str) -> bool:
    return flag.startswith((LEVEL, LOOP_EMITTERS))


def _split() -> tuple[list[str], list[str]]:
    given = os.environ.get("XLA_FLAGS", "").split()
    return [f for f in given if _lane(f)], [f for f in given if not _lane(f)]


def flags(extra: str = "") -> str:
    """The lane's flags (where set) and ``extra``."""
    return " ".join(_split()[0] + ([extra] if extra else []))


def without_lane_flags() -> str:
    """``XLA_FLAGS`` without the lane's flags: a user's program."""
    return " ".join(_split()[1])
