"""A progress line for long runs on the command line: the simulated time of the end
time and the percentage (or, for a run that ends by a stop condition, that condition),
rewritten in place on stderr, cleared when the run ends.

The simulation driver calls its ``progress(t, t_end)`` about every quarter second; the
line appears only once a run has taken ``delay`` seconds (2 by default), so short runs
print nothing. A duty cycle (:func:`mechdyn.analyse.cycle.duty_cycle`) announces each phase
through :meth:`ProgressLine.phase`, and the line counts that phase's time.

>>> import io
>>> ticks = iter([0.0, 3.0, 3.5])                 # a clock: start, then two reports
>>> stream = io.StringIO()
>>> with ProgressLine(stream, clock=lambda: next(ticks)) as line:
...     line(5.0, 20.0)
...     line(10.0, 20.0)
>>> stream.getvalue().split("\\r")[1:]
['mechdyn: t = 5 s of 20 s (25 %)', 'mechdyn: t = 10 s of 20 s (50 %)', '                                ', '']

A run that ends by a stop condition (``until``) has no share of its time to show: the
line names the condition and the time bound instead.

>>> ticks, stream = iter([0.0, 3.0]), io.StringIO()
>>> line = ProgressLine(stream, clock=lambda: next(ticks))
>>> line.until = "stopped(phi)"
>>> line(2.169, 1000.0)
>>> stream.getvalue()
'\\rmechdyn: t = 2.169 s, until stopped(phi) (at most t = 1000 s)'
"""
from __future__ import annotations

import sys
import threading
import time
from contextlib import contextmanager

__all__ = ["ProgressLine", "announce", "COMPILE_DELAY"]

COMPILE_DELAY = 1.0     # seconds of a compilation before it is announced


class ProgressLine:
    """``progress(t, t_end)`` writing one line to ``stream`` (stderr), rewritten with a
    carriage return; ``delay``: seconds of a run before the line appears; ``clock``:
    the time source (``time.monotonic``); ``t_start``: the run's start time (the
    percentage counts from it). Use it as a context manager: the line is cleared on
    leaving, also after an error."""

    def __init__(self, stream=None, delay=2.0, clock=None):
        self.stream = stream if stream is not None else sys.stderr
        self.delay = delay
        self.clock = clock or time.monotonic
        self.started = self.clock()
        self.width = 0
        self.label, self.t_start = "", 0.0
        self.until = ""             # the stop condition that ends the run, if any

    def phase(self, name, number, count, t_start, until=""):
        """A duty cycle's phase ``number`` of ``count`` starts at time ``t_start``
        (``until``: its stop condition)."""
        self.label, self.t_start = f"phase {number}/{count} {name}: ", t_start
        self.until = until

    def __call__(self, t, t_end):
        if self.clock() - self.started < self.delay:
            return
        begin = self.t_start
        span = t_end - begin
        share = (t - begin) / span if span > 0 else 1.0
        if self.until:
            text = (f"mechdyn: {self.label}t = {t:.4g} s, until {self.until} "
                    f"(at most t = {t_end:.4g} s)")
        else:
            text = (f"mechdyn: {self.label}t = {t:.4g} s of {t_end:.4g} s "
                    f"({100 * min(max(share, 0.0), 1.0):.0f} %)")
        self.stream.write("\r" + text.ljust(self.width))
        self.stream.flush()
        self.width = max(self.width, len(text))

    def clear(self):
        """Blank the line (if one was written) and return to its start."""
        if self.width:
            self.stream.write("\r" + " " * self.width + "\r")
            self.stream.flush()
            self.width = 0

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.clear()
        return False


@contextmanager
def announce(what, expected=None, stream=None, delay=3.0, every=5.0, cached=True):
    """Announce a one-time wait on ``stream`` (stderr) once it has lasted ``delay``
    seconds: what happens, the ``expected`` seconds (if known), where its result is kept
    (``cached``: on disk, else for this process), and the seconds elapsed every
    ``every`` seconds (a numba compilation gives no finer progress; it runs in foreign
    code that releases the GIL, so a thread can count). Short waits print nothing.
    Every compilation mechdyn does is announced this way, after ``COMPILE_DELAY``
    seconds (the kernels' after 3, as loading them from disk may take 2).

    >>> import io
    >>> stream = io.StringIO()
    >>> with announce("compiling", 15, stream, delay=0.0, every=0.05):
    ...     time.sleep(0.12)
    >>> stream.getvalue().splitlines()[0]
    'mechdyn: compiling (once, about 15 s; cached on disk) ...'
    >>> stream.getvalue().splitlines()[-1].startswith("mechdyn: compiling: done in ")
    True
    """
    stream = stream if stream is not None else sys.stderr
    done, started, shown = threading.Event(), time.monotonic(), []

    def count():
        if done.wait(delay):
            return
        shown.append(True)
        about = "" if expected is None else f", about {expected:.0f} s"
        kept = "cached on disk" if cached else "kept for this process"
        stream.write(f"mechdyn: {what} (once{about}; {kept}) ...\n")
        stream.flush()
        while not done.wait(every):
            stream.write(f"mechdyn: {what}: {time.monotonic() - started:.0f} s\n")
            stream.flush()
    counter = threading.Thread(target=count, daemon=True)
    counter.start()
    try:
        yield
    finally:
        done.set()
        counter.join()
        if shown:
            stream.write(f"mechdyn: {what}: done in {time.monotonic() - started:.1f} s\n")
            stream.flush()
