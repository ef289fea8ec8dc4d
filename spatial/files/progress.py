"""Progress bars for long work: a tqdm bar on a terminal, silence otherwise."""

from __future__ import annotations

import sys

__all__ = ["progress_bar", "wants_progress"]


def wants_progress(progress=None) -> bool:
    """Resolve a `progress` option: True/False as given, None -> stderr is a terminal."""
    if progress is None:
        try:
            return bool(sys.stderr.isatty())
        except (AttributeError, ValueError):
            return False
    if not isinstance(progress, bool):
        raise TypeError(f"progress: expected True, False or None, got {progress!r}")
    return progress


class _Quiet:
    """Stand-in for a tqdm bar that shows nothing."""

    def update(self, n=1):
        pass

    def set_description(self, desc=None, refresh=True):
        pass

    def set_postfix_str(self, s="", refresh=True):
        pass

    def close(self):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def progress_bar(total=None, desc: str = "", progress=None, unit: str = "it"):
    """A tqdm bar on stderr when `progress` resolves to True, else a silent stand-in.

    Parameters
    ----------
    total : int, optional
        Number of steps.
    desc : str
        Label shown before the bar.
    progress : bool or None
        True: always show; False: never; None: show only when stderr is a terminal.

    Examples
    --------
    >>> with progress_bar(3, "blocks", progress=False) as bar:
    ...     for _ in range(3):
    ...         bar.update()
    """
    if not wants_progress(progress):
        return _Quiet()
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit=unit, leave=False, file=sys.stderr, dynamic_ncols=True)
