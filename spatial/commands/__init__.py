"""Sub-commands of `implicad`, one module each (see `spatial.cli`)."""
