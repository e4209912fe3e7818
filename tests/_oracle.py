"""An independent clearance check of decoded paths, by dense sampling (test helper).

It shares no code with :mod:`hga_jax.model.geometry`: each arc is sampled at ``K`` angles
from ``atan2`` of its arrival point, plus, for each obstacle, the circle's point
towards it when that angle lies within the arc (angle arithmetic modulo 2*pi, not
cross products), plus the four axis-extreme points within the arc; each line at
``K`` points plus the projection of each obstacle centre. The clearance of a path
is the smallest ``|p - c_i| - R_i`` over its points and obstacles, and the smallest
distance inside the kept field's box (negative: outside). Metres.
"""
from __future__ import annotations

import numpy as np

TWO_PI = 2.0 * np.pi


def _within(angle, start, signed_sweep):
    """Whether ``angle`` lies on the arc from ``start`` sweeping ``signed_sweep``."""
    direction = np.where(signed_sweep < 0, -1.0, 1.0)
    off = np.mod(direction * (angle - start), TWO_PI)
    return off <= np.abs(signed_sweep) + 1e-12


def clearance(sa, d, k: int = 64, chunk: int = 4096) -> tuple[np.ndarray, np.ndarray]:
    """Per path of the float64 :class:`~hga_jax.model.decode.Decoded` ``d`` (numpy arrays)
    against scenario arrays ``sa``: ``(obstacle_clearance, field_clearance)`` (m)."""
    rows = d.length.shape[0]
    obs = np.full(rows, np.inf)
    fld = np.full(rows, np.inf)
    for lo in range(0, rows, chunk):
        o, f = _clearance_chunk(sa, [np.asarray(a)[lo:lo + chunk] for a in d[:7]], k)
        obs[lo:lo + chunk], fld[lo:lo + chunk] = o, f
    return obs, fld


def _clearance_chunk(sa, d, k):
    _, _, count, circles, _, arcs, lines = d
    centres = np.asarray(sa.centres, np.float64)
    radii = np.asarray(sa.model_radii, np.float64)
    bounds = np.asarray(sa.bounds, np.float64)
    b, s = circles.shape[:2]
    slot = np.arange(s)[None]
    t = np.linspace(0.0, 1.0, k)

    # Arc points: K samples, the points towards each obstacle, axis extremes.
    cx, cy, r, sign = (circles[..., i] for i in range(4))
    ax, ay, swp = arcs[..., 0], arcs[..., 1], arcs[..., 4]
    a0 = np.arctan2(ay - cy, ax - cx)
    signed = -sign * swp
    ang = a0[..., None] + signed[..., None] * t  # (B, S, K)
    extremes = np.array([0.0, 0.5, 1.0, 1.5]) * np.pi
    ext_ok = _within(extremes, a0[..., None], signed[..., None])
    ext_ok &= (swp > 0)[..., None]
    if centres.size:
        qa = np.arctan2(centres[:, 1] - cy[..., None], centres[:, 0] - cx[..., None])  # (B, S, n)
        q_ok = _within(qa, a0[..., None], signed[..., None]) & (swp > 0)[..., None]
    else:
        qa = np.zeros((b, s, 0))
        q_ok = np.zeros((b, s, 0), bool)
    arc_real = slot < count[:, None]
    all_ang = np.concatenate([ang, qa, np.broadcast_to(extremes, (b, s, 4))], axis=-1)
    ok = np.concatenate([np.broadcast_to(arc_real[..., None], ang.shape),
                         q_ok & arc_real[..., None], ext_ok & arc_real[..., None]], axis=-1)
    px = cx[..., None] + r[..., None] * np.cos(all_ang)
    py = cy[..., None] + r[..., None] * np.sin(all_ang)

    # Line points: K samples and the projection of each obstacle centre.
    p1x, p1y, p2x, p2y = (lines[..., i] for i in range(4))
    vx, vy = p2x - p1x, p2y - p1y
    vv = np.where(vx * vx + vy * vy > 0, vx * vx + vy * vy, 1.0)
    proj = ((centres[:, 0] - p1x[..., None]) * vx[..., None]
            + (centres[:, 1] - p1y[..., None]) * vy[..., None]) / vv[..., None]
    lt = np.concatenate([np.broadcast_to(t, p1x.shape + (k,)), np.clip(proj, 0.0, 1.0)], axis=-1)
    lx = p1x[..., None] + lt * vx[..., None]
    ly = p1y[..., None] + lt * vy[..., None]
    line_real = np.broadcast_to((slot[:, :-1] < (count - 1)[:, None])[..., None], lx.shape)

    xs = np.concatenate([px.reshape(b, -1), lx.reshape(b, -1)], axis=1)
    ys = np.concatenate([py.reshape(b, -1), ly.reshape(b, -1)], axis=1)
    real = np.concatenate([ok.reshape(b, -1), line_real.reshape(b, -1)], axis=1)

    field = np.minimum.reduce([xs - bounds[0], bounds[1] - xs, ys - bounds[2], bounds[3] - ys])
    field = np.where(real, field, np.inf).min(axis=1)
    if not centres.size:
        return np.full(b, np.inf), field
    gap = np.hypot(xs[..., None] - centres[:, 0], ys[..., None] - centres[:, 1]) - radii
    return np.where(real[..., None], gap, np.inf).min(axis=(1, 2)), field
