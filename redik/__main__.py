import sys

from redik.apps.cli import main

sys.exit(main())
