"""``python -m rocking``: the ``rocking`` command line, the same as the installed ``rocking`` script."""

import sys

from .cli.main import main

if __name__ == "__main__":
    sys.exit(main())
