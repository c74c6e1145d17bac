"""``python -m symkin.cli``: the same as the ``symkin`` command."""

import sys

from symkin.cli import main

if __name__ == "__main__":
    sys.exit(main())
