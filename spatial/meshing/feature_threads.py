"""The feature pass's walks over every vertex and triangle cut into contiguous chunks, run on two threads.

Each compiled walk of `feature_cells` and `feature_collapse` takes a span of
vertices, triangles or runs; the chunks' results are put together in order, so
that the mesh is the same bit for bit whatever the number of chunks (one chunk is
the serial walk).  The kernels release the interpreter's lock, so the chunks of one
step run side by side.
"""

from __future__ import annotations

import threading

__all__ = ["CHUNKS", "on_threads", "spans"]

#: Chunks of each walk over every vertex or triangle (one per core of a two-core machine).
CHUNKS = 2


def spans(n, chunks=CHUNKS):
    """`chunks` contiguous spans ``(a, b)`` covering ``range(n)`` in order, their sizes differing by
    at most one (some empty when ``n < chunks``).

    Examples
    --------
    >>> spans(7, 3)
    [(0, 2), (2, 4), (4, 7)]
    """
    n, chunks = int(n), int(chunks)
    if n < 0:
        raise ValueError(f"n: expected a count >= 0, got {n}")
    if chunks < 1:
        raise ValueError(f"chunks: expected a count >= 1, got {chunks}")
    edges = [n * i // chunks for i in range(chunks + 1)]
    return list(zip(edges[:-1], edges[1:]))


def on_threads(calls, threads=None):
    """The results of the zero-argument `calls`, in order: the first half run on this thread, the rest
    one after another on a second thread (when there are several calls and `threads` is not 1).  An
    exception of either thread is raised here once both are done."""
    calls = list(calls)
    threads = min(CHUNKS, 2) if threads is None else int(threads)
    if threads < 2 or len(calls) < 2:
        return [call() for call in calls]
    out = [None] * len(calls)
    half = (len(calls) + 1) // 2
    failed = []

    def rest():
        try:
            for i in range(half, len(calls)):
                out[i] = calls[i]()
        except BaseException as exc:  # raised on the caller's thread below
            failed.append(exc)

    helper = threading.Thread(target=rest, name="implicad-features", daemon=True)
    helper.start()
    try:
        for i in range(half):
            out[i] = calls[i]()
    finally:
        helper.join()
    if failed:
        raise failed[0]
    return out
