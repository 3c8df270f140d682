"""Each env's pixel noise drawn ahead in blocks: the same bits as one draw a step, fewer calls.

An imperfect camera's pixel noise comes from its env's own generator, one
``rng.standard_normal((L, 2))`` a step, so that a vector env gives what ``SyncVectorEnv`` of
scalar envs gives. For ``N`` robots that is ``N`` generator calls a step (about 1.4 us each),
a tenth of the batched step through an imperfect camera at ``N = 256``.

:class:`NoiseBlocks` draws ``block`` steps of one env's noise in one call,
``rng.standard_normal((block, L, 2))``, which fills its array from the same stream in the same
order as ``block`` calls of shape ``(L, 2)``: step ``t`` of the block gets the bits the ``t``-th
call would. The generator then stands ``block`` steps ahead of what one draw a step would
leave. Its other reader, the env's reset (the next episode is drawn from the same generator),
must find it where ``SyncVectorEnv`` leaves it: :meth:`NoiseBlocks.sync` puts back the state
saved before the block and draws exactly the steps used, so the generator moves on as if drawn
step by step. The env calls it before anything else reads that generator.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["NOISE_BLOCK_BYTES", "NoiseBlocks"]

#: The blocks' memory bound, bytes, all envs together (a block is at least one step).
NOISE_BLOCK_BYTES = 4 * 2**20
#: Steps a block holds at most.
MAX_BLOCK = 32


class NoiseBlocks:
    """Standard normal draws ``(L, 2)`` a step for each of ``n`` envs, drawn ``block`` at a time.

    Parameters
    ----------
    n
        Number of envs.
    landmarks
        ``L``, the landmark slots of one image (each step draws ``(L, 2)``).
    block
        Steps drawn per generator call; default: :data:`MAX_BLOCK`, fewer where ``n`` envs'
        blocks would exceed :data:`NOISE_BLOCK_BYTES`; ``1``: one draw a step.
    """

    def __init__(self, n: int, landmarks: int, block: int | None = None) -> None:
        per_step = max(n * landmarks * 2 * 8, 1)
        if block is None:
            block = min(MAX_BLOCK, max(NOISE_BLOCK_BYTES // per_step, 1))
        if block < 1:
            raise ValueError(f"block must be >= 1, got {block!r}")
        self.block = int(block)
        self.landmarks = int(landmarks)
        self._draws = np.zeros((n, self.block, self.landmarks, 2))
        self._used = np.full(n, self.block, dtype=np.intp)  # steps used of each env's block
        self._saved: list[dict[str, Any] | None] = [None] * n  # the state before the block

    def draw(
        self, indices: NDArray[np.intp], rngs: Sequence[np.random.Generator | None]
    ) -> NDArray[np.float64]:
        """Return the next step's draws of the envs ``indices``, ``(k, L, 2)``.

        Parameters
        ----------
        indices
            ``(k,)`` the envs.
        rngs
            Every env's generator, by env (``rngs[i]`` is env ``i``'s; only those whose block
            is used up are read).

        Returns
        -------
        numpy.ndarray
            ``(k, L, 2)``: row ``j`` is what ``rngs[j].standard_normal((L, 2))`` would give.
        """
        used = self._used[indices]
        for i in indices[used >= self.block].tolist():  # a new block: one call, `block` steps
            rng = rngs[i]
            if rng is None:
                raise ValueError(f"env {i} has no generator: reset it first")
            self._saved[i] = rng.bit_generator.state
            rng.standard_normal(out=self._draws[i])  # (block, L, 2), in place
            self._used[i] = 0
        used = self._used[indices]
        rows = self._draws[indices, used]
        self._used[indices] = used + 1
        return rows

    def sync(self, i: int, rng: np.random.Generator | None) -> None:
        """Leave env ``i``'s generator where one draw a step would have; drop its block.

        Parameters
        ----------
        i
            The env.
        rng
            Its generator (the one its block was drawn from); ``None``: the block is dropped.
        """
        saved = self._saved[i]
        if saved is not None and rng is not None:
            rng.bit_generator.state = saved
            used = int(self._used[i])
            if used:
                rng.standard_normal((used, self.landmarks, 2))
        self._saved[i] = None
        self._used[i] = self.block

    def drop(self, i: int) -> None:
        """Forget env ``i``'s block (its generator is replaced, not read again)."""
        self._saved[i] = None
        self._used[i] = self.block
