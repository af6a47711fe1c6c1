"""`python -m tensegrity.cli`: the `tensegrity` command."""

import sys

from . import main

sys.exit(main())
