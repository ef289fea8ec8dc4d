"""Warnings pointed at the caller's line: `user_warnings`, `user_stacklevel`.

The work of a public call runs several frames deep inside the package
(`spatial.mesh` -> `spatial.distributed.mesh` -> the planner -> the
mesher's checks), so a fixed ``stacklevel`` points at some wrapper,
depending on the way in.  `user_warnings` records the warnings a public
function raises and re-emits each one at the first frame outside the
package: the user's call, whichever way it came in.  Kept in the bottom
room so that `spatial.mesh` and `spatial.mass_properties` use it without
importing the cluster room (`spatial.distributed` and what it loads: 20 to
40 ms of a whole process).

Examples
--------
>>> import warnings
>>> @user_warnings
... def noisy():
...     warnings.warn("careful")
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter("always")
...     noisy()
>>> str(caught[0].message)
'careful'
"""

from __future__ import annotations

import functools
import os
import sys
import warnings

__all__ = ["user_warnings", "user_stacklevel"]

_PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep


def user_stacklevel(skip=1):
    """The ``stacklevel`` that makes `warnings.warn`, called by the function `skip` frames up from here
    (1: the caller), name the first frame outside the package."""
    frame = sys._getframe(skip)
    level = 1
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(_PACKAGE):
        frame = frame.f_back
        level += 1
    return level


def user_warnings(function):
    """Decorator: the warnings `function` raises come out at its caller's first frame outside the package."""

    @functools.wraps(function)
    def reemitting(*args, **kwargs):
        pending = []
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    return function(*args, **kwargs)
                finally:
                    pending = list(caught)
        finally:
            for w in pending:
                warnings.warn(w.message, w.category, stacklevel=user_stacklevel())

    return reemitting
