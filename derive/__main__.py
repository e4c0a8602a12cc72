"""``python -m rocking.derive``: see :mod:`rocking.derive.cli`."""

import sys

from .cli import main

if __name__ == "__main__":
    sys.exit(main())
