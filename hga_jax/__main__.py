"""``python -m hga_jax`` is the ``hga-jax`` command."""
import sys

from hga_jax.host.cli import main

sys.exit(main())
