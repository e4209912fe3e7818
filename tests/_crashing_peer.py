"""Peers that end their process as a segmentation fault would, for the test of
:mod:`hga_jax.peers.isolated`. A module of their own, importing nothing heavy: the
worker process that calls them imports this module, not the test's (JAX, the package)."""
import os
import signal


def crash_once(marker: str) -> int:
    """Ends its process the first time (it leaves ``marker`` behind); then its pid."""
    if not os.path.exists(marker):
        open(marker, "w").close()
        os.kill(os.getpid(), signal.SIGSEGV)
    return os.getpid()


def crash_always() -> None:
    os.kill(os.getpid(), signal.SIGSEGV)
