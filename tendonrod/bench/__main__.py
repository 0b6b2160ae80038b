"""``python -m tendonrod.bench ...``: the same as ``python -m tendonrod bench ...``."""

import sys

from .cli import main

sys.exit(main())
