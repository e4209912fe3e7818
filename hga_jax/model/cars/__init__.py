"""Car models: one folder per car model's own modules.

:mod:`~hga_jax.model.cars.tight_rope` (the paper's model), :mod:`~hga_jax.model.cars.free_turns`
and :mod:`~hga_jax.model.cars.reeds_shepp`; each folder's ``model`` module holds the model's
:class:`~hga_jax.model.car_model.CarModel` and registers it. The shared model (geometry,
collision, tangents, turn tables, decoder, fitness, exact solver, scenario) stays in
:mod:`hga_jax.model`.
"""
