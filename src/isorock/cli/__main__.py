"""``python -m isorock.cli``: the ``isorock`` command."""

import sys

from isorock.cli import main

sys.exit(main())
