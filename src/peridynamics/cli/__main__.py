"""``python -m peridynamics.cli`` = the ``peridynamics`` command."""

import sys

from peridynamics.cli import main

sys.exit(main())
