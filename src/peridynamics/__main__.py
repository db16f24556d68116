"""``python -m peridynamics`` = the ``peridynamics`` command."""

import sys

from peridynamics.cli import main

sys.exit(main())
