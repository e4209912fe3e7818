"""Scaling: 5 to 100 obstacles at a fixed density; GA hit rate and gap at fixed budgets,
GA time per run against the exact solver's time (``configs/studies/scaling.toml``).

Usage: ``python3 experiments/scaling.py [--quick] [--out DIR]``
(the same as ``hga-jax study configs/studies/scaling.toml``).
"""

import sys

from hga_jax.study.cli import script


def main(argv=None) -> int:
    return script(__file__, argv, __doc__)


if __name__ == "__main__":
    sys.exit(main())
