"""hadal.cluster: reaching a Dask cluster (Debian's python3-distributed) for hadal.campaign and
hadal.env.DaskVectorEnv: a scheduler's address, or a LocalCluster on this machine."""

import os


class SchedulerUnreachable(ConnectionError):
    """No Dask scheduler answered at the address given."""


def connect(scheduler=None, workers=None, connect_timeout_s=10.0):
    """A distributed.Client: to the scheduler at `scheduler` (tcp://HOST:PORT), else to a new LocalCluster of
    `workers` single-threaded worker processes (default: one per CPU this process may use). Returns (client,
    cluster or None). Raises SchedulerUnreachable."""
    from distributed import Client, LocalCluster

    if scheduler:
        try:
            return Client(scheduler, timeout=connect_timeout_s), None
        except (OSError, TimeoutError) as e:
            raise SchedulerUnreachable(f"no Dask scheduler answered at {scheduler} within {connect_timeout_s:g} s "
                                       f"({type(e).__name__}: {e})") from None
    count = workers or len(os.sched_getaffinity(0))
    cluster = LocalCluster(n_workers=count, threads_per_worker=1, processes=True, dashboard_address=None,
                           silence_logs=40)
    return Client(cluster), cluster
