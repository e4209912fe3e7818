"""How a scenario's oriented circles are numbered: the one rule every module reads.

``0`` start CCW (sign ``-1``), ``1`` start CW (``+1``), ``2`` goal CCW, ``3`` goal CW,
then ``4 + 2i`` obstacle ``i``'s model circle CW and ``5 + 2i`` CCW: ``C = 2n + 4``
circles (:func:`count`). Circles that a car model adds (free circles of radius rho)
are numbered from ``C`` on. A label ``l`` (``+1`` CW, ``-1`` CCW) picks the side
``(1 + l) // 2`` (1 CW, 0 CCW) of a pose's pair of circles, and circle
:func:`obstacle` of an obstacle's pair.

The nodes of a tangent graph (:mod:`hga_jax.model.tangent_graph`) begin with the
start point on circles 0 and 1 and the goal point on circles 2 and 3, so nodes
``0..3`` are numbered as their circles are.

Every function works on Python integers, numpy and JAX arrays alike.
"""
from __future__ import annotations

import numpy as np

START = (0, 1)
"""The start's turning circles: CCW, CW."""
GOAL = (2, 3)
"""The goal's turning circles: CCW, CW."""
POSES = 4
"""Circles (and graph nodes) of the two poses; the obstacles' circles follow."""


def count(n: int) -> int:
    """Circles of a scenario with ``n`` obstacles: ``2n + 4``."""
    return 2 * n + POSES


def side(label):
    """The side of a label's circle within its pair: 1 for CW (``+1``), 0 for CCW
    (``-1``) and for an untouched position (``0``). A shift, not ``// 2``: equal for
    every integer (an arithmetic shift floors), without the sign fix-ups of a floor
    division, on every gene of every evaluation."""
    return (1 + label) >> 1


def obstacle(i, side_):
    """The circle of obstacle ``i`` on ``side_`` (1 CW, 0 CCW): ``4 + 2i + 1 - side``."""
    return POSES + 2 * i + (1 - side_)


def obstacle_of(ids):
    """The obstacle whose circle ``ids`` is (the inverse of :func:`obstacle`, either
    side; obstacle circles only): ``(id - 4) >> 1``."""
    return (ids - POSES) >> 1


def is_start(ids):
    """Whether circle (or node) ``ids`` is a start circle (the start point)."""
    return ids < GOAL[0]


def is_goal(ids):
    """Whether circle (or node) ``ids`` is a goal circle (the goal point)."""
    return (ids >= GOAL[0]) & (ids < POSES)


def is_pose(ids):
    """Whether circle (or node) ``ids`` belongs to the start or the goal."""
    return ids < POSES


def sources(c: int) -> np.ndarray:
    """The circles a tight-rope leg can leave, of ``c`` scenario circles: the start's
    and the obstacles'."""
    return np.r_[START, POSES:c]


def targets(c: int) -> np.ndarray:
    """The circles a tight-rope leg can arrive on: the obstacles' and the goal's."""
    return np.r_[POSES:c, GOAL]


def one_per_obstacle(values):
    """``values`` (one per scenario circle) at one circle of each obstacle (its CW
    circle: both share centre and radius)."""
    return values[POSES::2]
