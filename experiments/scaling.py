"""Scaling: 5 to 100 obstacles at a fixed density; GA hit rate and gap at fixed budgets,
GA time per run against the exact solver's time (``configs/studies/scaling.toml``).

Usage: ``python3 experiments/scaling.py [--quick] [--out DIR]``
(the same as ``hga-jax study configs/studies/scaling.toml``).
"""
import os
import sys

from hga_jax.study.cli import script

CONFIG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "configs", "studies",
                      "scaling.toml")


def main(argv=None) -> int:
    return script(CONFIG, argv, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
