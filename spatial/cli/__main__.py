"""``python -m spatial.cli``: the `implicad` command."""

from . import console

console()
