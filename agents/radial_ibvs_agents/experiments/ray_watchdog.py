"""Kill a private Ray instance's processes once the driver that started them is gone.

Run by :func:`radial_ibvs_agents.experiments.backends.watch_ray_processes` as
``python -m radial_ibvs_agents.experiments.ray_watchdog DRIVER_PID PID...``: it polls every half
second; when ``DRIVER_PID`` has died (even by SIGKILL, which runs no clean-up), it kills the listed
processes and all their descendants, then exits. It also exits, killing nothing, once none of the
listed processes is left (the driver shut Ray down itself).
"""

from __future__ import annotations

import sys
import time

__all__ = ["main"]

#: seconds between two checks
INTERVAL_S = 0.5


def _alive(process: object) -> bool:
    """Whether a ``psutil.Process`` still runs (the same process: not a reused pid, no zombie)."""
    import psutil

    try:
        return bool(process.is_running()) and process.status() != psutil.STATUS_ZOMBIE  # type: ignore[attr-defined]
    except psutil.NoSuchProcess:
        return False


def main(argv: list[str]) -> int:
    """Watch ``argv = [driver, pid, ...]``; return 0 once done (see the module docstring)."""
    import psutil

    driver_pid, *pids = (int(a) for a in argv)
    try:
        driver = psutil.Process(driver_pid)
    except psutil.NoSuchProcess:
        driver = None
    watched = []
    for pid in pids:
        try:
            watched.append(psutil.Process(pid))
        except psutil.NoSuchProcess:
            continue
    while True:
        alive = [p for p in watched if _alive(p)]
        if not alive:
            return 0
        if driver is None or not _alive(driver):
            break
        time.sleep(INTERVAL_S)
    doomed = {p.pid: p for p in alive}
    for process in alive:  # the whole tree first: orphans would be reparented out of reach
        try:
            doomed.update({c.pid: c for c in process.children(recursive=True)})
        except psutil.NoSuchProcess:
            continue
    for process in doomed.values():
        try:
            process.kill()
        except psutil.NoSuchProcess:
            continue
    psutil.wait_procs(list(doomed.values()), timeout=5)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
