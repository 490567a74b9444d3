"""numba's one-time start-up in a process, without the cyclic garbage collector's
rescans.

Importing the kernels imports numba, initialises its compilation target and loads the
kernel from numba's disk cache: some 200,000 long-lived objects (numba's, and scipy's
linear algebra, which numba loads). Each full collection while that happens, and each
one at the process's exit, walks every object in the process (sympy's included): about
a quarter of a fresh process's CPU time on its first compiled run.
:func:`collector_paused` pauses the collector for the start-up, frees the start-up's
own garbage cycles (a young-generation collection: everything the start-up made is
young) and then moves the objects alive at that point to the collector's permanent
generation (:func:`gc.freeze`), where no later collection rescans them.

What that changes for a program (nothing in its results): a reference cycle among
objects that were alive at the start-up and later become unreachable is no longer
freed by the collector (plain garbage still is, by reference counting); ``gc.unfreeze()``
hands them back. A program that disabled the collector keeps it disabled and nothing is
frozen. During the kernels' one-time compilation (after installing) the pause raises
the peak memory by about 70 MB, freed when it ends.

>>> import gc
>>> with collector_paused():
...     paused = not gc.isenabled()
>>> paused, gc.isenabled()
(True, True)
"""
from __future__ import annotations

import gc
from contextlib import contextmanager

__all__ = ["collector_paused"]


@contextmanager
def collector_paused():
    """Pause the cyclic garbage collector for a one-time load of long-lived objects,
    then collect the load's garbage and freeze what is alive (module doc)."""
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.collect(0)
        gc.freeze()
        gc.enable()
