"""``python -m redik``: the command-line interface (:mod:`redik.apps.cli`)."""

import sys

from redik.apps.cli import main

sys.exit(main())
