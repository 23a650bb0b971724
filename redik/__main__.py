import sys

from redik.cli import main

sys.exit(main())
