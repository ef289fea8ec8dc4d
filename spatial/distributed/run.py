"""Running one task per brick: submission, Dask's progress bar, results as they complete."""

from __future__ import annotations

import threading

from ..files.progress import wants_progress

__all__ = ["run_bricks", "show"]


def run_bricks(client, function, spec, bricks, *, progress=None, extra=None, name="brick"):
    """Run ``function(spec, brick, *extra[i])`` for every brick; yield ``(i, result)`` as tasks complete.

    A result is released from its worker as soon as it is read, so the
    workers never hold more than the results not yet read.  On a terminal
    (or with ``progress=True``) Dask's own text progress bar
    (`distributed.progress`) follows the tasks.
    """
    from distributed import as_completed

    spec_f = client.scatter(spec, broadcast=True, hash=False)
    futures = []
    for i, b in enumerate(bricks):
        args = () if extra is None else tuple(extra[i])
        futures.append(client.submit(function, spec_f, tuple(int(v) for v in b), *args, pure=False,
                                     key=f"{name}-{i}-{spec_f.key}"))
    index = {f.key: i for i, f in enumerate(futures)}
    bar, marks = None, []
    if futures and wants_progress(progress):
        from distributed import progress as dask_progress

        # The bar follows one tiny task per brick, run once the brick is done, which this function holds
        # to the end: the bricks' own results are released as soon as read, and a bar that connects late
        # (a loaded machine) would wait forever for keys already forgotten.  It blocks while it draws:
        # it draws from a thread, the results are read here.
        marks = [client.submit(_done, f, pure=False, key=f"{name}-done-{i}-{spec_f.key}")
                 for i, f in enumerate(futures)]
        bar = threading.Thread(target=dask_progress, args=(marks,), kwargs=dict(multi=False, complete=False),
                               daemon=True)
        bar.start()
    finished = False
    try:
        for future in as_completed(futures):
            i = index[future.key]
            result = future.result()
            futures[i] = None
            future.release()
            yield i, result
        finished = True
    finally:
        for f in futures:
            if f is not None:
                f.cancel()
        if finished and marks:
            # Every brick is read, but its mark may still be queued behind it on a loaded machine: let the
            # marks finish so that the bar ends at 100 %, not on a cancellation.
            from distributed import wait

            try:
                wait(marks, timeout=60)
            except TimeoutError:
                pass  # the marks only feed the bar; the results are complete
        for m in marks:
            if not m.done():
                m.cancel()  # (an error above, or a mark stuck past the wait): the bar stops on it
        if bar is not None:
            bar.join(timeout=60)  # every mark is done or cancelled: the bar ends
        for m in marks:
            m.release()


def _done(result):
    """The mark of a finished brick (`run_bricks`'s progress bar counts these)."""
    return None


def show(futures, progress=None):
    """Dask's text progress bar over `futures` until they finish (on a terminal, or with ``progress=True``)."""
    if futures and wants_progress(progress):
        from distributed import progress as dask_progress

        dask_progress(futures, multi=False)
