"""Genetic operators on the lower module: turning-direction labels.

Conventions:

- Labels are a 1-D ``int32`` array of length ``L = n + 2``: position 0 is the
  start circle, ``L - 1`` the goal circle, the others belong to the obstacles
  at the same positions of the upper module (docs/model.md).
- Allowed values: ``+1`` clockwise, ``-1`` counter-clockwise, ``0`` obstacle
  not touched. The two end positions take ``{-1, +1}``; the others
  ``{-1, 0, +1}``.
- As in :mod:`hga_jax.search.perm_crossover`, every operator works on ONE individual or
  ONE pair, is split into a random ``*_draw`` and a deterministic ``*_apply``
  step, has shapes that depend on ``L`` only, and jits and vmaps.
- Cut points: ``0 <= lo < hi <= L``, uniform over all such pairs; the segment
  is the half-open position range ``[lo, hi)``.

The settings' names are those of :mod:`hga_jax.search.registry` (``label_crossover``:
``two_point``; ``label_mutation``: ``redraw``).
"""
from __future__ import annotations

import jax
import jax.numpy as jnp
from jax import Array

from .permutation import cut_draw, int_from_words
from .rng import unit

def _is_end(L: int) -> Array:
    """True at the start and goal positions (0 and ``L - 1``)."""
    pos = jnp.arange(L, dtype=jnp.int32)
    return (pos == 0) | (pos == L - 1)


def random_labels(key: Array, L: int, shape: tuple[int, ...] = ()) -> Array:
    """Labels uniform over each position's allowed set (``int32``, shape ``shape + (L,)``).

    One draw ``r`` uniform in ``0..5`` per position: ends take
    ``2 * (r % 2) - 1``, the others ``r % 3 - 1``; both are uniform.
    """
    return labels_from_words(jax.random.bits(key, tuple(shape) + (L,), dtype=jnp.uint32))


def labels_from_words(words: Array) -> Array:
    """:func:`random_labels` from given uint32 words (one per gene, last axis ``L``)."""
    r = int_from_words(words, 0, 6)
    L = words.shape[-1]
    return jnp.where(_is_end(L), 2 * (r % 2) - 1, r % 3 - 1)


# --- Two-point crossover -------------------------------------------------------

def two_point_draw(key: Array, L: int) -> tuple[Array, Array]:
    """Segment ``[lo, hi)``, uniform over ``0 <= lo < hi <= L``."""
    return cut_draw(key, L)


def two_point_apply(a: Array, b: Array, lo: Array, hi: Array) -> tuple[Array, Array]:
    """Two-point crossover: the children swap the segment ``[lo, hi)``.

    ``c1`` is ``a`` with ``b``'s segment, ``c2`` is ``b`` with ``a``'s. Labels
    stay at their positions, so every allowed set is respected.
    """
    pos = jnp.arange(a.shape[-1], dtype=jnp.int32)
    seg = (pos >= lo) & (pos < hi)
    return jnp.where(seg, b, a), jnp.where(seg, a, b)


def two_point(key: Array, a: Array, b: Array) -> tuple[Array, Array]:
    """Two-point crossover with a random segment (see :func:`two_point_apply`)."""
    return two_point_apply(a, b, *two_point_draw(key, a.shape[-1]))


# --- Per-gene redraw mutation ----------------------------------------------------

def redraw_draw(key: Array, L: int, pm: float | Array) -> tuple[Array, Array]:
    """``(mask, choice)``: ``mask[k]`` True with probability ``pm``, independently
    per gene; ``choice[k]`` a fair random bit (which other value a middle gene
    takes)."""
    return redraw_mask(jax.random.bits(key, (L,), dtype=jnp.uint32), pm)


def redraw_mask(bits: Array, pm: float | Array) -> tuple[Array, Array]:
    """``(mask, choice)`` of :func:`redraw_draw` from one uint32 word per gene.

    The top 24 bits give u uniform on a grid in [0, 1) (exact in float32, so
    pm = 1 always fires and pm = 0 never); the lowest bit is the choice.
    """
    return unit(bits) < pm, (bits & 1) == 1


def redraw_apply(labels: Array, mask: Array, choice: Array) -> Array:
    """Change every masked gene to a DIFFERENT value of its allowed set.

    Ends flip sign; a middle gene ``v`` moves 1 or 2 steps (``1 + choice``)
    along the cycle ``-1 -> 0 -> +1 -> -1``, i.e. to one of its two other
    values. Unmasked genes are kept.
    """
    return _redrawn(labels, mask, choice, _is_end(labels.shape[-1]))


def _redrawn(labels: Array, mask: Array, choice: Array, ends: Array) -> Array:
    """:func:`redraw_apply`'s rule, ``ends`` marking the end genes (broadcast)."""
    shift = 1 + choice.astype(labels.dtype)
    middle = (labels + 1 + shift) % 3 - 1
    return jnp.where(mask, jnp.where(ends, -labels, middle), labels)


def redraw(key: Array, labels: Array, pm: float | Array) -> Array:
    """Per-gene mutation: each gene, with probability ``pm``, always changes its
    value (ends flip; middle genes take one of their two other values,
    uniformly)."""
    return redraw_apply(labels, *redraw_draw(key, labels.shape[-1], pm))


def redraw_from_words(words: Array, labels: Array, pm: float | Array) -> Array:
    """:func:`redraw` of labels ``(..., L)`` from one given uint32 word per gene.

    A batch is mutated with its genes as the leading axis (the same values): the GA's
    words come gene by gene, and XLA on the CPU then fuses the mutation without
    transposing them element by element (the recommended preset's search 0.89 -> 0.78 s
    and the paper's 0.215 -> 0.20 s per 1,000 runs at 9 obstacles)."""
    if labels.ndim == 1:
        return redraw_apply(labels, *redraw_mask(words, pm))
    first = jnp.moveaxis(labels, -1, 0)
    mask, choice = redraw_mask(jnp.moveaxis(words, -1, 0), pm)
    ends = _is_end(first.shape[0]).reshape((-1,) + (1,) * (first.ndim - 1))
    return jnp.moveaxis(_redrawn(first, mask, choice, ends), 0, -1)
