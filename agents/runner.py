"""Step a Session on a worker thread and publish snapshots, so that an interactive
caller (Blender's modal timer) never waits for a system iteration.

The worker calls ``session.step()`` until the session is done or a stop is asked
for, and after every iteration publishes a snapshot: the outlines found so far (as
plain arrays) and the progress figures. The caller reads the latest snapshot at any
time without touching the session. Only the worker touches the session until it has
finished (``finished`` is True); after that the caller owns it again. An exception in
the worker is kept and raised again by :meth:`check` in the caller's thread.

The session and everything it calls is numpy-only; no Blender data is touched here.
"""
import threading
import time


class Snapshot:
    def __init__(self, outlines, progress, version, seconds, final=None):
        self.outlines = outlines
        self.progress = progress
        self.version = version
        self.seconds = seconds
        self.final = final          # the finalize() result once the session is done


class Runner:
    """``finalize()``, if given, runs on the worker once the session is done (e.g. the
    hidden-line removal and stroke layers) and its result lands in the last snapshot."""

    def __init__(self, session, finalize=None):
        self.session = session
        self.finalize = finalize
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self._error = None
        self._snap = Snapshot([], session.progress(), 0, 0.0)
        self._thread = threading.Thread(target=self._work, name="blobtree-ink-agents", daemon=True)
        self._t0 = None

    def start(self):
        self._t0 = time.perf_counter()
        self._thread.start()
        return self

    def _work(self):
        version = 0
        try:
            while not self._stop.is_set() and self.session.step():
                version += 1
                snap = Snapshot(self.session.outlines(), self.session.progress(), version,
                                time.perf_counter() - self._t0)
                with self._lock:
                    self._snap = snap
            if self.session.done and not self._stop.is_set():
                final = self.finalize() if self.finalize is not None else True
                snap = Snapshot(self.session.outlines(), self.session.progress(), version + 1,
                                time.perf_counter() - self._t0, final)
                with self._lock:
                    self._snap = snap
        except BaseException as e:          # handed to the caller by check()
            self._error = e

    def snapshot(self):
        with self._lock:
            return self._snap

    def stop(self, wait=None):
        """Ask the worker to stop after its current iteration; with ``wait`` seconds,
        wait for it (returns whether it has finished)."""
        self._stop.set()
        if wait is not None:
            self._thread.join(wait)
        return self.finished

    @property
    def finished(self):
        return self._t0 is not None and not self._thread.is_alive()

    def check(self):
        """Raise the worker's exception, if it had one."""
        if self._error is not None:
            raise RuntimeError(f"the agents failed: {self._error!r}") from self._error
