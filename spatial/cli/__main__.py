"""``python -m spatial.cli``: the `implicad` command."""

import sys

from . import main

sys.exit(main())
