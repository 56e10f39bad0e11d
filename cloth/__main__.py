"""``python -m cloth`` runs the command-line interface."""

import sys

from cloth.cli import main

sys.exit(main())
