"""Every CPU core as a device of its own, so a batch of runs is spread over all of them.

On the CPU, JAX shows a process one device, and XLA runs one compiled program
mostly on one core: a 2-core machine searched 10,000 paper-runs at about 5.6
million evaluations/s with one device and 8.6 million/s with two (n = 100:
0.47 -> 0.62-0.66 million/s). With several devices, :mod:`hga_jax.running.runner`
splits each batch's runs over them; run ``k`` of seed ``s`` still depends on
``(s, k)`` alone, so results are bit for bit the same for any device count.

The device count of JAX's CPU runtime is fixed when the runtime starts (at the
first JAX operation), so :func:`use_cpu_cores` must come first: ``hga-jax run``
and ``hga-jax study`` call it before anything else (``--cpu-devices``); in
Python, call it right after ``import hga_jax``. It does nothing to other
platforms' devices (a GPU stays one device). Host code.
"""
from __future__ import annotations

import math
import os

from hga_jax.errors import ConfigError

_FLAG = "xla_force_host_platform_device_count"


_QUOTAS = (("/sys/fs/cgroup/cpu.max", None),  # cgroup v2: "QUOTA PERIOD" or "max PERIOD"
           ("/sys/fs/cgroup/cpu/cpu.cfs_quota_us", "/sys/fs/cgroup/cpu/cpu.cfs_period_us"))


def cores() -> int:
    """CPU cores this process may run on: its affinity mask (e.g. what SLURM gave the
    task; all of the machine's where the mask is unknown), fewer where a container's
    CPU quota (cgroup ``cpu.max``, or ``cpu.cfs_quota_us`` in cgroup v1) allows less."""
    try:
        count = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        count = os.cpu_count() or 1
    quota = cpu_quota()
    return max(1, min(count, math.ceil(quota))) if quota else count


def cpu_quota(paths=_QUOTAS) -> float | None:
    """The container's CPU quota in cores (quota / period), None where there is none."""
    for first, second in paths:
        try:
            with open(first) as fh:
                words = fh.read().split()
            if second is not None:
                with open(second) as fh:
                    words = words[:1] + fh.read().split()[:1]
            quota, period = float(words[0]), float(words[1])
        except (OSError, ValueError, IndexError):  # absent, "max" or unreadable
            continue
        if quota > 0 and period > 0:
            return quota / period
    return None


def use_cpu_cores(count: int | None = None, *, source: str = "use_cpu_cores") -> bool:
    """Ask JAX's CPU runtime for ``count`` devices (None: one per core, :func:`cores`).

    Returns whether the count was set. ``None`` leaves alone a count already
    chosen (``XLA_FLAGS=--xla_force_host_platform_device_count=N`` or the
    ``jax_num_cpu_devices`` option) and a runtime that has already started
    (its devices are kept; nothing else changes). A ``count`` given explicitly
    that can no longer take effect, or that is not an integer >= 1, is a
    :class:`~hga_jax.errors.ConfigError` naming ``source`` (e.g. ``"command
    line: --cpu-devices"``).
    """
    import jax

    if count is not None and (isinstance(count, bool) or not isinstance(count, int)
                              or count < 1):
        raise ConfigError(f"{source}: must be an integer >= 1, got {count!r}")
    if count is None and (_FLAG in os.environ.get("XLA_FLAGS", "")
                          or jax.config.jax_num_cpu_devices != -1):
        return False
    want = cores() if count is None else count
    try:
        jax.config.update("jax_num_cpu_devices", want)
    except RuntimeError:  # the runtime has started: its device count stays
        if count is None or len(jax.devices("cpu")) == count:
            return False
        raise ConfigError(f"{source}: {count} CPU devices asked for, but JAX's runtime "
                          f"already started with {len(jax.devices('cpu'))}; set it before "
                          f"the first JAX operation") from None
    return True


def add_option(parser) -> None:
    """The ``--cpu-devices N`` option of a command that runs the GA (argparse)."""
    parser.add_argument("--cpu-devices", type=int, metavar="N", help="CPU devices the runs are "
                        "spread over (default: one per core this process may use); results "
                        "are the same for any N")


def from_option(args) -> bool:
    """:func:`use_cpu_cores` with the parsed ``--cpu-devices`` (None: one per core)."""
    return use_cpu_cores(args.cpu_devices, source="command line: --cpu-devices")
