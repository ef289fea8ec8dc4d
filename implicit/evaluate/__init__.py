"""The fast evaluator of `Solid` trees: tapes, per-kind rules, pruning, numba kernels.

A tree is flattened into a tape of operations (`tape`), each node kind
contributing its operations through a rule (`rules`); points are binned in
space and every bin runs a tape pruned to the operands that can matter there
(`prune`); numba kernels run the tapes (`compile`).

The node classes never import this package: importing it registers
`fast_evaluate` and `compile_solid` with `implicit.solid`, which is the one
seam between the two (`implicit/__init__.py` imports it last).

Examples
--------
>>> from implicit import sphere
>>> from implicit.evaluate import compile_solid
>>> f = compile_solid(sphere(1.0))
"""

from ..solid import register_evaluator
from .numba_start import install as _install_numba_start
from .tape import OPS, PRUNE_MODES, RULES, KernelSource, Tape, Unsupported, register_rule  # noqa: F401
from . import rules  # noqa: F401  (the node kinds' rules register themselves)
from .compile import compile_solid, fast_evaluate  # noqa: F401

register_evaluator(fast_evaluate=fast_evaluate, compile_solid=compile_solid)
_install_numba_start()  # cached kernels load without numba's 0.3 s target refresh

__all__ = ["compile_solid", "fast_evaluate", "Tape", "KernelSource", "Unsupported", "register_rule", "RULES", "OPS",
           "PRUNE_MODES"]
