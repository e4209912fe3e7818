"""The free-turn car model (``turns = "free"``): turns on circles of radius rho in free space too.

:mod:`~hga_jax.model.cars.free_turns.model` holds the car model and its optimum beside the
tight rope's; :mod:`~hga_jax.model.cars.free_turns.turns` the tangent graph over the free
circles and its exact shortest path; :mod:`~hga_jax.model.cars.free_turns.circles` the free
circles an optimum needs, pinned by two contacts; :mod:`~hga_jax.model.cars.free_turns.legs`
the free legs a chromosome with one gene per leg expresses, and their tables for the GA;
:mod:`~hga_jax.model.cars.free_turns.leg_space` the best path of that chromosome space,
found exactly.
"""
