"""Where jobs run: a local process pool (the default) or a Ray cluster.

Both backends take a module-level function and a list of arguments and yield ``(index,
result)`` pairs as the jobs finish, so the caller can persist each result at once (a stop
then loses at most the jobs in flight).

Ray is optional (``pip install 'radial_ibvs_gym[ray]'``). Without ``--address`` the Ray
backend starts a private single-machine instance whose servers listen on 127.0.0.1 only, with
no dashboard and no usage statistics; with ``--address`` it joins the cluster at that address
(``auto``: the one ``ray start`` left on this machine). Each job is a Ray task of one CPU that
Ray retries when its worker dies (``max_retries``).
"""

from __future__ import annotations

import multiprocessing
import os
import subprocess
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from typing import Any

__all__ = [
    "BACKENDS",
    "RAY_EXTRA",
    "LocalBackend",
    "RayBackend",
    "import_ray",
    "make_backend",
    "start_worker",
]

BACKENDS = ("local", "ray")
#: what to install for the Ray backend
RAY_EXTRA = "pip install 'radial_ibvs_gym[ray]'"


def import_ray(local: bool = True) -> Any:
    """Import Ray, configured as this project runs it.

    Parameters
    ----------
    local
        A private single-machine instance: its servers bind 127.0.0.1 only (Ray's own
        single-machine mode, ``RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=0``, set whatever the
        environment held), with token authentication (``RAY_AUTH_MODE=token``; any other
        value is refused).

    Notes
    -----
    Ray reads these settings when it is first imported. If this process imported Ray
    before without ``RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=0``, a private instance would listen
    on every interface: that is refused, never done silently.

    Raises
    ------
    ValueError
        When Ray is not installed (the message names the extra to install), or was imported
        first without the loopback setting, or ``RAY_AUTH_MODE`` turns authentication off
        (for a private instance).
    """
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")  # nothing leaves the machine
    auth = os.environ.get("RAY_AUTH_MODE", "token")
    if local and auth != "token":
        raise ValueError(
            f"RAY_AUTH_MODE={auth[:40]!r} turns Ray's token authentication off; a private "
            "instance runs only with it on: unset RAY_AUTH_MODE (or set it to 'token')"
        )
    if "ray" not in sys.modules:
        # token authentication on, and said so explicitly: Ray's documented way to keep it
        # on without its warning (https://docs.ray.io/en/latest/ray-security/token-auth.html)
        os.environ.setdefault("RAY_AUTH_MODE", "token")
        if local:  # forced, whatever the environment held: the loopback only
            os.environ["RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"] = "0"
    elif (
        local
        and sys.modules["ray"] is not None
        and os.environ.get("RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER") != "0"
    ):
        raise ValueError(
            "Ray was imported before the benchmark could configure it, so a private Ray "
            "instance would listen on every network interface; refusing. Start the command "
            "without importing ray first, or set RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=0 before "
            "importing ray (its servers then bind 127.0.0.1 only), or join a cluster you "
            "started yourself with --address"
        )
    try:
        import ray
    except ImportError:
        raise ValueError(f"--backend ray needs Ray, which is not installed: {RAY_EXTRA}") from None
    return ray


#: how often a worker checks that its parent is alive, seconds
WATCHDOG_INTERVAL_S = 0.5


def start_worker(parent: int, initializer: Callable[[], None] | None = None) -> None:
    """Initialise a worker process that dies with its parent, then run ``initializer``.

    A daemon thread checks every :data:`WATCHDOG_INTERVAL_S` that the process's parent is
    still ``parent``; once the parent is gone (even killed with SIGKILL, which runs no clean-up
    of its own), the worker exits at once, instead of living on holding memory.
    """

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(WATCHDOG_INTERVAL_S)
        os._exit(1)

    threading.Thread(target=watch, name="parent-watchdog", daemon=True).start()
    if initializer is not None:
        initializer()


def watch_ray_processes(driver: int) -> subprocess.Popen[bytes] | None:
    """Start a watchdog that kills this private Ray instance's processes if ``driver`` dies.

    Ray's own clean-up runs only when the driver exits normally; after a SIGKILL its raylet,
    dashboard and runtime-env agents live on for a minute or more, one still listening. The watchdog
    (a small process of its own session, :mod:`radial_ibvs_agents.experiments.ray_watchdog`) records
    the driver's children now, polls every :data:`WATCHDOG_INTERVAL_S`, and once the driver is gone
    kills them and everything under them; it exits by itself once they are gone (after
    :meth:`RayBackend.close`).

    Returns
    -------
    subprocess.Popen or None
        The watchdog, or ``None`` when the driver has no child processes to watch.
    """
    import psutil  # a dependency of Ray

    children = [p.pid for p in psutil.Process(driver).children(recursive=True)]
    if not children:
        return None
    command = [sys.executable, "-m", "radial_ibvs_agents.experiments.ray_watchdog", str(driver)]
    return subprocess.Popen(
        [*command, *map(str, children)],
        start_new_session=True,  # a Ctrl-C to the driver's group does not stop it first
        stdin=subprocess.DEVNULL,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )


class LocalBackend:
    """Run jobs here (``workers=1``) or in a pool of ``workers`` spawned processes.

    The workers die with the process that started them (:func:`start_worker`).

    Parameters
    ----------
    workers
        Parallel processes (>= 1).
    """

    name = "local"

    def __init__(self, workers: int = 1) -> None:
        if workers < 1:
            raise ValueError(f"workers must be >= 1, got {workers!r}")
        self.workers = workers

    def __repr__(self) -> str:
        return f"LocalBackend(workers={self.workers})"

    def imap_unordered(
        self,
        fn: Callable[[Any], Any],
        items: Sequence[Any],
        initializer: Callable[[], None] | None = None,
    ) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(items[index]))`` as the jobs finish.

        On an exception or Ctrl-C the jobs not started are cancelled and the error raised.
        """
        if self.workers == 1 or len(items) <= 1:
            for i, item in enumerate(items):
                yield i, fn(item)
            return
        # spawn, not fork: torch (loaded here to check the models) hangs in forked children
        context = multiprocessing.get_context("spawn")
        pool = ProcessPoolExecutor(
            self.workers,
            mp_context=context,
            initializer=start_worker,
            initargs=(os.getpid(), initializer),
        )
        try:
            futures: dict[Future[Any], int] = {pool.submit(fn, x): i for i, x in enumerate(items)}
            pending = set(futures)
            while pending:
                done, pending = wait(pending, return_when=FIRST_COMPLETED)
                for future in done:
                    yield futures[future], future.result()
        finally:
            pool.shutdown(wait=True, cancel_futures=True)

    def close(self) -> None:
        """Nothing to release."""


class RayBackend:
    """Run each job as a Ray task (one CPU, retried when its worker dies).

    Parameters
    ----------
    address
        A running cluster (``"auto"`` or ``"HOST:PORT"``); ``None`` starts a private
        single-machine instance listening on 127.0.0.1 only (and stops it on :meth:`close`).
        Ignored when Ray is already initialised in this process.
    num_cpus
        CPUs of the private instance (default: all of this machine's).
    max_retries
        Retries of a task whose worker process died.
    """

    name = "ray"

    def __init__(
        self, address: str | None = None, num_cpus: int | None = None, max_retries: int = 3
    ) -> None:
        if max_retries < 0:
            raise ValueError(f"max_retries must be >= 0, got {max_retries!r}")
        self.ray = import_ray(local=address is None)
        self.max_retries = max_retries
        self._owner = not self.ray.is_initialized()
        if self._owner:
            if address is None:
                self.ray.init(
                    num_cpus=num_cpus,
                    include_dashboard=False,
                    log_to_driver=False,
                    configure_logging=False,
                    _node_ip_address="127.0.0.1",
                )
                watch_ray_processes(os.getpid())
            else:
                self.ray.init(address=address, log_to_driver=False, configure_logging=False)

    def __repr__(self) -> str:
        return f"RayBackend(max_retries={self.max_retries})"

    def imap_unordered(
        self,
        fn: Callable[[Any], Any],
        items: Sequence[Any],
        initializer: Callable[[], None] | None = None,
    ) -> Iterator[tuple[int, Any]]:
        """Yield ``(index, fn(items[index]))`` as the tasks finish.

        On an exception or Ctrl-C the tasks not finished are cancelled and the error raised.
        """
        ray = self.ray
        task = ray.remote(num_cpus=1, max_retries=self.max_retries)(_call)
        refs = {task.remote(fn, initializer, item): i for i, item in enumerate(items)}
        pending = list(refs)
        try:
            while pending:
                done, pending = ray.wait(pending, num_returns=1)
                for ref in done:
                    yield refs[ref], ray.get(ref)
        finally:
            for ref in pending:
                ray.cancel(ref, force=True)

    def close(self) -> None:
        """Stop the private instance, if this backend started it."""
        if self._owner and self.ray.is_initialized():
            self.ray.shutdown()


def _call(fn: Callable[[Any], Any], initializer: Callable[[], None] | None, item: Any) -> Any:
    """Run a Ray task: the pool's initializer, then the job."""
    if initializer is not None:
        initializer()
    return fn(item)


def make_backend(
    name: str, workers: int = 1, address: str | None = None
) -> LocalBackend | RayBackend:
    """Build a backend by name.

    Parameters
    ----------
    name
        ``"local"`` or ``"ray"``.
    workers
        Local processes; for a private Ray instance, its CPUs.
    address
        Ray cluster address (``"auto"`` or ``"HOST:PORT"``); only with ``"ray"``.

    Raises
    ------
    ValueError
        For an unknown name, an address without Ray, or Ray not installed (the message
        names the extra).
    """
    if name not in BACKENDS:
        raise ValueError(f"unknown backend {name!r}; valid: {list(BACKENDS)}")
    if name == "local":
        if address is not None:
            raise ValueError("--address needs --backend ray")
        return LocalBackend(workers)
    return RayBackend(address, num_cpus=workers if address is None else None)
