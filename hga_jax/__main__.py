"""``python -m hga_jax`` is the ``hga-jax`` command."""
import sys

from .cli import main

sys.exit(main())
