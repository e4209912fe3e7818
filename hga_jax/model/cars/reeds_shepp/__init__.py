"""The Reeds-Shepp car (``car = "reeds-shepp"``): the car that also drives backward.

:mod:`~hga_jax.model.cars.reeds_shepp.model` holds the car model and its optimum beside the
free-turn and tight-rope ones; :mod:`~hga_jax.model.cars.reeds_shepp.closed_form` the
shortest path between two poses in closed form, from the 48 words of
:mod:`~hga_jax.model.cars.reeds_shepp.words`; :mod:`~hga_jax.model.cars.reeds_shepp.graph`
the tangent graph of free turns travelled both ways, with cusps, and its exact shortest
path; :mod:`~hga_jax.model.cars.reeds_shepp.legs` the chromosomes (free-turn legs driven in
either gear) and their tables; :mod:`~hga_jax.model.cars.reeds_shepp.reversing` the gear
rule of those chromosomes.
"""
