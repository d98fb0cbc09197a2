"""``python -m linkage_fmu``: the command line."""

import sys

from .cli import main

sys.exit(main())
