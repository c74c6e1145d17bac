"""``python -m symkin.cli``: the same as the ``symkin`` command."""

import sys

from symkin.cli import main

sys.exit(main())
