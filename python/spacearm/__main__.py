"""``python -m spacearm`` is the ``spacearm`` command."""

import sys

from .cli import main

sys.exit(main())
