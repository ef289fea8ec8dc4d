"""What the start-up import hooks share: a spec found by the finders behind one, and a loader that wraps a run.

`frozen_imports`, `deferred_imports` and `vtk_listing` each put a finder at the
head of ``sys.meta_path`` that finds nothing by itself: it asks the finders
behind it for a module's spec and hands the module a loader of its own.  The
two pieces they all need live here, so that the rules they must keep (a copy
of ``sys.meta_path``, since a finder may remove itself when asked; the module
left with its original loader, for resource readers and ``get_source``) are
written once.

Examples
--------
>>> import sys
>>> class Plain:
...     def find_spec(self, name, path=None, target=None):
...         return spec_behind(self, name, path, target)
>>> spec_behind(Plain(), "json").name
'json'
>>> spec_behind(Plain(), "no_such_module_here") is None
True
"""

from __future__ import annotations

import sys

__all__ = ["spec_behind", "WrappingLoader"]


def spec_behind(finder, name, path=None, target=None):
    """The spec of `name` from the first finder of ``sys.meta_path`` other than `finder` that has one, or None."""
    for other in list(sys.meta_path):  # a copy: a finder may remove itself when asked
        if other is finder or not hasattr(other, "find_spec"):
            continue
        spec = other.find_spec(name, path, target)
        if spec is not None:
            return spec
    return None


class WrappingLoader:
    """A loader that runs the original one through `run`; the module keeps the original as its loader.

    Subclasses override `run` (by default the original loader's ``exec_module``).
    Only this one run is wrapped: ``module.__loader__`` and ``module.__spec__.loader``
    are the original loader again before the module's code runs.
    """

    def __init__(self, loader):
        self.loader = loader

    @classmethod
    def wrap(cls, spec):
        """`spec` with its loader wrapped, when it has one that executes modules; the spec itself."""
        if spec is not None and spec.loader is not None and hasattr(spec.loader, "exec_module"):
            spec.loader = cls(spec.loader)
        return spec

    def create_module(self, spec):
        return self.loader.create_module(spec)

    def exec_module(self, module):
        module.__loader__ = self.loader
        if module.__spec__ is not None:
            module.__spec__.loader = self.loader
        self.run(module)

    def run(self, module):
        self.loader.exec_module(module)
