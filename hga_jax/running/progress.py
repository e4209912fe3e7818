"""Progress of long jobs on stderr.

The bar counts generations (of every batch of a job); it is drawn by tqdm, on
stderr, so standard output carries only the results.
"""
from __future__ import annotations

import sys
from typing import Any


def bar(total: int, enabled: bool, what: str) -> Any:
    """A bar on stderr counting generations (``what`` says of what); None if not ``enabled``."""
    if not enabled:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=total, unit="gen", desc=what, leave=False, file=sys.stderr)


def tick(progress: Any, k: int) -> None:
    """``k`` more generations done (nothing without a bar)."""
    if progress is not None:
        progress.update(k)
