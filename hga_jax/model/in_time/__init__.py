"""Robots that move: the car's time along its path among robots that move.

:mod:`~hga_jax.model.in_time.clearance` holds the clearance tests in time (the decoder's
violations, the float64 check of result paths, closest approaches);
:mod:`~hga_jax.model.in_time.windows` the turn table's windows in time (when a piece of
fixed geometry meets a moving robot); :mod:`~hga_jax.model.in_time.optimum` the exact
solver's optimum in time (a lower bound, a certificate, the best path known).
"""
