"""Torch's thread count for a small network's forward pass: one thread, set per call.

The shipped networks are small (a few hundred thousand weights): one observation's forward pass
takes about half a millisecond on one core. With torch's default (a thread per core), each call
also wakes the other threads of torch's pool, and when another process keeps a core busy those
threads wait for it: a median of about 0.5 ms becomes a p90 of several milliseconds
(``benchmarks/bench_policy_threads.py``). So a loaded policy computes a small batch with one
thread and gives the caller back its own setting after the call; a large batch (many robots at
once) keeps the caller's setting, where the threads pay for themselves.

Torch's thread count is process-wide: two threads of one process calling ``predict`` at once
may see each other's setting during a call (never a wrong action, only another speed). This is
not thread-safe in that sense, as torch's own setting is not.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["SMALL_BATCH", "threads_for"]

#: batches of fewer rows than this run on one thread (measured: at 64 rows two threads start to
#: pay on a 2-core box, ``benchmarks/bench_policy_threads.py``)
SMALL_BATCH = 64


@contextmanager
def threads_for(rows: int) -> Iterator[int]:
    """Run the block with one torch thread if ``rows < SMALL_BATCH``; restore the setting after.

    Parameters
    ----------
    rows
        The observations computed together (1 for one robot).

    Yields
    ------
    int
        The thread count the block runs with.
    """
    import torch  # here: importing the model files' helpers loads no torch

    caller = torch.get_num_threads()
    wanted = 1 if rows < SMALL_BATCH else caller
    if wanted == caller:
        yield caller
        return
    torch.set_num_threads(wanted)
    try:
        yield wanted
    finally:
        torch.set_num_threads(caller)
