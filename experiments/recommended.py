"""The recommended HGA against the paper's: hit rate, gap, evaluations and time per run
on the studies' scene families, ablations, other path moves and budgets from 500 to
10,000 evaluations (``configs/studies/recommended.toml``).

Usage: ``python3 experiments/recommended.py [--quick] [--scenes N] [--out DIR]``
(the same as ``hga-jax study configs/studies/recommended.toml``).
"""

import sys

from hga_jax.study.cli import script


def main(argv=None) -> int:
    return script(__file__, argv, __doc__)


if __name__ == "__main__":
    sys.exit(main())
