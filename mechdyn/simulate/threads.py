"""One BLAS thread while a run steps: small dense linear algebra inside a step (Radau's
and the constrained equations' LU, the stiffness tests' eigenvalues, the mass solve of
large models) is slower threaded, and far slower when the threads outnumber the cores
(OpenBLAS's default on 2 cores: a 100x100 solve 2.3 ms instead of 0.23 ms).
Parallelism comes from running points side by side (:func:`mechdyn.sweep`), not from
threads inside one step.

:func:`single_threaded_blas` limits every loaded BLAS to one thread with threadpoolctl
and restores the user's setting afterwards. It may be nested and entered from several
threads at once: the first to enter sets the limit, the last to leave restores it.

>>> import numpy as np
>>> with single_threaded_blas():
...     x = np.linalg.solve(np.eye(3), np.ones(3))
>>> x.tolist()
[1.0, 1.0, 1.0]
"""
from __future__ import annotations

import threading
from contextlib import contextmanager

__all__ = ["single_threaded_blas"]

_lock = threading.Lock()
_state = {"depth": 0, "limiter": None, "controller": None}


@contextmanager
def single_threaded_blas():
    """Run the block with one BLAS thread (numpy's and scipy's libraries)."""
    with _lock:
        if _state["depth"] == 0:
            _state["limiter"] = _controller().limit(limits=1, user_api="blas")
        _state["depth"] += 1
    try:
        yield
    finally:
        with _lock:
            _state["depth"] -= 1
            if _state["depth"] == 0:
                _state["limiter"].restore_original_limits()
                _state["limiter"] = None


def _controller():
    """threadpoolctl's view of the loaded libraries, made once after scipy.linalg has
    loaded its own BLAS (3 ms; each limit then costs about 20 us)."""
    if _state["controller"] is None:
        import scipy.linalg  # noqa: F401  (its BLAS must be loaded to be seen)
        from threadpoolctl import ThreadpoolController
        _state["controller"] = ThreadpoolController()
    return _state["controller"]
