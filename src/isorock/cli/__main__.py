"""``python -m isorock.cli``: the ``isorock`` command."""

import sys

from . import main

sys.exit(main())
