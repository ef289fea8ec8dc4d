"""A function run right after a module is first imported, without importing it.

Start-up work that only matters once a heavy package is loaded (numba's cache
loader, VTK's error output) is hooked onto that package's import instead of
importing it in every process.

Examples
--------
>>> from implicit.after_import import after_import
>>> after_import("json", lambda module: None)   # runs now: json is imported
"""

from __future__ import annotations

import sys

__all__ = ["after_import"]


def after_import(name: str, hook) -> None:
    """Call ``hook(module)`` once module `name` has run: now if it is imported, else right after its import.

    A finder at the head of ``sys.meta_path`` wraps the module's loader; it finds
    nothing itself and removes itself at the first import of `name`.  The same
    hook is not registered twice for one name.
    """
    if name in sys.modules:
        hook(sys.modules[name])
        return
    for finder in sys.meta_path:
        if isinstance(finder, _HookFinder) and finder.name == name:
            if hook not in finder.hooks:
                finder.hooks.append(hook)
            return
    sys.meta_path.insert(0, _HookFinder(name, hook))


class _HookFinder:
    def __init__(self, name, hook):
        self.name, self.hooks = name, [hook]

    def find_spec(self, name, path=None, target=None):
        if name != self.name:
            return None
        from importlib.machinery import PathFinder

        sys.meta_path.remove(self)
        spec = PathFinder.find_spec(name, path, target)
        if spec is not None and spec.loader is not None:
            spec.loader = _HookLoader(spec.loader, self.hooks)
        return spec


class _HookLoader:
    def __init__(self, loader, hooks):
        self.loader, self.hooks = loader, hooks

    def create_module(self, spec):
        return self.loader.create_module(spec)

    def exec_module(self, module):
        self.loader.exec_module(module)
        for hook in self.hooks:
            hook(module)
