"""Step a Session on a worker thread and publish snapshots, so that an interactive
caller (Blender's modal timer) never waits for a system iteration.

The worker calls ``session.step()`` until the session is done or a stop is asked
for, and after every iteration publishes a snapshot: the outlines found so far (as
plain arrays) and the progress figures. The caller reads the latest snapshot at any
time without touching the session. Only the worker touches the session until it has
finished (``finished`` is True); after that the caller owns it again. An exception in
the worker is kept and raised again by :meth:`check` in the caller's thread.

The session and everything it calls is numpy-only; no Blender data is touched here.

While a worker runs, the interpreter's thread switch interval is cut to
``SWITCH_INTERVAL`` (0.2 ms instead of 5 ms): Blender's main thread takes the GIL for
every Python callback of its UI (panels, polls, timers, hundreds per redraw), and each
take waits up to one switch interval for the worker to let go. On Linux the worker
thread also runs at a lower priority (nice 10) so that the UI's drawing threads win
the CPU: measured under Xvfb on 2 cores with the heart, a 0.1 s timer fired every
0.24 s idle, 0.43 s during a run with it and 0.60 s without it.
"""
import os
import sys
import threading
import time

SWITCH_INTERVAL = 2e-4
WORKER_NICE = 10             # on Linux the worker yields the CPU to Blender's UI threads
_active = [0, None]          # running workers, the switch interval to restore
_active_lock = threading.Lock()


def _enter():
    with _active_lock:
        if _active[0] == 0:
            _active[1] = sys.getswitchinterval()
            sys.setswitchinterval(min(SWITCH_INTERVAL, _active[1]))
        _active[0] += 1


def _leave():
    with _active_lock:
        _active[0] -= 1
        if _active[0] == 0:
            sys.setswitchinterval(_active[1])


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
        _enter()
        self._thread.start()
        return self

    def _work(self):
        try:
            if sys.platform.startswith("linux"):     # a thread id is a process id only on Linux
                os.setpriority(os.PRIO_PROCESS, threading.get_native_id(), WORKER_NICE)
            self._steps()
        except BaseException as e:          # handed to the caller by check()
            self._error = e
        finally:
            _leave()

    def _steps(self):
        version = 0
        while not self._stop.is_set() and self.session.step():
            version += 1
            self._publish(version)
        if self.session.done and not self._stop.is_set():
            self._publish(version + 1, self.finalize() if self.finalize is not None else True)

    def _publish(self, version, final=None):
        outlines = self.session.outlines()
        snap = Snapshot(outlines, self.session.progress(outlines), version,
                        time.perf_counter() - self._t0, final)
        with self._lock:
            self._snap = snap

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
