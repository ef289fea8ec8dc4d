"""The Dask client a computation runs on: one given, a scheduler's address, or a local cluster.

``client="local"`` or ``workers=N`` starts a `distributed.LocalCluster` on the
loopback interface (worker processes, one thread each, no dashboard) for the
duration of the call and closes it afterwards; a `distributed.Client` is used
as it is; a string ``"tcp://host:port"`` connects to a running scheduler.
"""

from __future__ import annotations

import contextlib
import numbers
import re

__all__ = ["connect", "check_client", "local_cluster"]

_ADDRESS = re.compile(r"^(tcp|tls|inproc|ucx|ws|wss)://\S+$")


def check_client(client, workers):
    """Validate the ``client=`` / ``workers=`` pair before any work; returns ``(client, workers)``."""
    if workers is not None:
        if isinstance(workers, bool) or not isinstance(workers, numbers.Integral):
            raise TypeError(f"workers: expected a positive number of worker processes, got {workers!r}")
        if workers < 1:
            raise ValueError(f"workers: expected a positive number of worker processes, got {workers}")
        workers = int(workers)
    if client is None or (isinstance(client, str) and client == "local"):
        return client, workers
    if isinstance(client, str):
        if not _ADDRESS.match(client):
            raise ValueError(f"client: expected 'local', a scheduler address such as 'tcp://10.0.0.5:8786' or a "
                             f"distributed.Client, got {client!r}")
        if workers is not None:
            raise ValueError("workers: only for a local cluster (client='local' or no client), not with a "
                             "scheduler's address")
        return client, workers
    from distributed import Client

    if not isinstance(client, Client):
        raise TypeError(f"client: expected 'local', a scheduler address or a distributed.Client, "
                        f"got {type(client).__name__}")
    if workers is not None:
        raise ValueError("workers: only for a local cluster, not with a given distributed.Client")
    return client, workers


def local_cluster(workers=2, *, memory_limit="auto"):
    """A `distributed.LocalCluster` of `workers` processes (one thread each) on 127.0.0.1, no dashboard."""
    import warnings

    from distributed import LocalCluster

    with warnings.catch_warnings():
        # the scheduler's health routes (no dashboard) listen on 127.0.0.1, on port 8787 when it is free and
        # on another when a second cluster holds it: nothing to warn about
        warnings.filterwarnings("ignore", message="Port 8787 is already in use", category=UserWarning)
        return LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True, host="127.0.0.1",
                            dashboard_address=None, memory_limit=memory_limit, silence_logs=40)


@contextlib.contextmanager
def connect(client=None, workers=None):
    """The client to use, as a context: a cluster or connection started here is closed on exit."""
    client, workers = check_client(client, workers)
    from distributed import Client

    if isinstance(client, Client):
        yield client
        return
    if isinstance(client, str) and client != "local":
        with Client(client) as remote:
            yield remote
        return
    with local_cluster(workers or 2) as cluster, Client(cluster) as local:
        yield local
