"""A single path, re-evaluated exactly: float64 length, violations and segments.

Host-side: runs the same decoder as the search (:func:`hga_jax.decode.decode_batch`)
in float64 and turns its slots into MODEL.md's segment list. Every length that
hga-jax reports comes from here, whatever precision the search used.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Sequence

import jax
import numpy as np

from .decode import decode_batch
from .errors import ConfigError
from .scenario import Scenario

_decode = jax.jit(decode_batch, static_argnames="collision")
BLOCK = 64  # float64 decoding always runs on blocks of this many rows


def decode64(scenario: Scenario, perm, labels, collision: str = "full"):
    """Float64 decoding of a batch, as numpy arrays (a :class:`Decoded` of them).

    Rows go through one compiled shape of ``BLOCK`` rows (the last block padded), so
    a chromosome gets bit-identical values alone or in a batch of any size.
    """
    labels = np.asarray(labels, np.int32).reshape(-1, scenario.n + 2)
    rows = labels.shape[0]
    perm = np.asarray(perm, np.int32).reshape(rows, scenario.n)
    pad = -rows % BLOCK
    perm = np.concatenate([perm, np.repeat(perm[:1], pad, axis=0)])
    labels = np.concatenate([labels, np.repeat(labels[:1], pad, axis=0)])
    parts = []
    with jax.enable_x64(True):
        sa = scenario.arrays(np.float64)
        for i in range(0, rows + pad, BLOCK):
            d = _decode(sa, perm[i:i + BLOCK], labels[i:i + BLOCK], collision=collision)
            parts.append(jax.tree.map(np.asarray, d))
    return jax.tree.map(lambda *xs: np.concatenate(xs)[:rows], *parts)


@dataclass
class Path:
    """An evaluated path.

    length: metres (arcs + lines, no penalty). violations: count per MODEL.md.
    upper, lower: the chromosome (upper ``[0, ..., n+1]``, lower labels).
    segments: MODEL.md segment dicts in travel order (zero-length pieces left out).
    touched: ``(obstacle index 0-based, label)`` in travel order.
    """

    length: float
    violations: int
    upper: list[int]
    lower: list[int]
    segments: list[dict[str, Any]] = field(default_factory=list)
    touched: list[tuple[int, int]] = field(default_factory=list)

    @property
    def feasible(self) -> bool:
        return self.violations == 0

    def to_dict(self) -> dict[str, Any]:
        return {
            "length": self.length,
            "feasible": self.feasible,
            "violations": self.violations,
            "upper": self.upper,
            "lower": self.lower,
            "touched": [{"obstacle": i, "label": s} for i, s in self.touched],
            "segments": self.segments,
        }


def chromosome(perm: Sequence[int], labels: Sequence[int]) -> tuple[list[int], list[int]]:
    """(upper, lower) of MODEL.md from the internal ``perm`` (0-based) and ``labels``."""
    n = len(perm)
    return [0] + [int(p) + 1 for p in perm] + [n + 1], [int(v) for v in labels]


def from_chromosome(upper: Sequence[int], lower: Sequence[int], n: int,
                    source: str = "<chromosome>") -> tuple[np.ndarray, np.ndarray]:
    """Internal ``(perm, labels)`` from an (upper, lower) chromosome, checked."""
    upper, lower = [int(u) for u in upper], [int(v) for v in lower]
    if len(upper) != n + 2 or upper[0] != 0 or upper[-1] != n + 1 or sorted(upper[1:-1]) != list(
            range(1, n + 1)):
        raise ConfigError(f"{source}: upper: must be 0, a permutation of 1..{n}, {n + 1}")
    if len(lower) != n + 2 or any(v not in (-1, 1) for v in (lower[0], lower[-1])) or any(
            v not in (-1, 0, 1) for v in lower):
        raise ConfigError(f"{source}: lower: must be {n + 2} labels, ends in {{-1, 1}}, "
                          "others in {-1, 0, 1}")
    return np.asarray(upper[1:-1], np.int32) - 1, np.asarray(lower, np.int32)


def evaluate_path(scenario: Scenario, perm: Sequence[int], labels: Sequence[int],
                  collision: str = "full") -> Path:
    """Decode one chromosome in float64 and describe its path."""
    perm = np.asarray(perm, np.int32).reshape(scenario.n)
    labels = np.asarray(labels, np.int32).reshape(scenario.n + 2)
    d = jax.tree.map(lambda a: a[0], decode64(scenario, perm, labels, collision))
    upper, lower = chromosome(perm, labels)
    segments: list[dict[str, Any]] = []
    count = int(d.count)
    for s in range(count):
        cx, cy, r, sign = (float(v) for v in d.circles[s])
        ax, ay, bx, by, swp = (float(v) for v in d.arcs[s])
        if swp > 0.0:
            segments.append({
                "type": "arc", "center": [cx, cy], "radius": r,
                "start_angle": float(np.arctan2(ay - cy, ax - cx)), "sweep": -sign * swp,
            })
        if s < count - 1:
            p1x, p1y, p2x, p2y, _ = (float(v) for v in d.lines[s])
            if np.hypot(p2x - p1x, p2y - p1y) > 0.0:
                segments.append({"type": "line", "start": [p1x, p1y], "end": [p2x, p2y]})
    touched = [(int(d.obstacle[s]), int(d.circles[s][3])) for s in range(1, count - 1)]
    return Path(float(d.length), int(d.violations), upper, lower, segments, touched)


def segments_length(segments: Sequence[dict[str, Any]]) -> float:
    """Total length of a MODEL.md segment list (m): ``radius*|sweep|`` plus line lengths."""
    total = 0.0
    for seg in segments:
        if seg["type"] == "arc":
            total += seg["radius"] * abs(seg["sweep"])
        else:
            total += float(np.hypot(seg["end"][0] - seg["start"][0], seg["end"][1] - seg["start"][1]))
    return total
