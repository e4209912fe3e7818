"""The replanning loop: a frame's arrays on the device, a warm-started replanner, episodes.

- :mod:`hga_jax.loop.frame`: what the car observes each frame, padded to a bound, and its
  scenario arrays built inside the compiled program;
- :mod:`hga_jax.loop.replanner`: :class:`Replanner`, one compiled program per frame;
- :mod:`hga_jax.loop.episode`: episodes of frames every ``dt`` among robots that move.
"""
from .frame import Car, Observation, observation
from .replanner import LOOP, Plan, Replanner

__all__ = ["Car", "LOOP", "Observation", "Plan", "Replanner", "observation"]
