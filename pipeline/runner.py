"""Step an illustration (pipeline.Illustration) on a worker thread and publish its
results, so that an interactive caller (Blender's modal timer) never waits for a step:
not for the initialisation (polygonising a big model), a system iteration or a layer.

The worker calls ``illustration.step()`` until the illustration is finished, and
publishes ``illustration.result()`` after the first step, when a stage ends, at most
every PUBLISH_EVERY seconds between, and at the end; the caller reads the latest at any time
(:meth:`Runner.latest`) without touching the illustration. :meth:`Runner.stop` asks for
an early finish (the illustration keeps what it made and removes the hidden lines of
the outlines traced so far, on the worker); :meth:`Runner.cancel` asks the worker to
end after its current step with nothing more. Both are followed by :meth:`Runner.join`,
which waits a bounded time and raises :class:`RunnerError` saying so if the worker did
not end. Only the worker touches the illustration until it has ended. An exception on
the worker is kept and raised again by :meth:`Runner.check` in the caller's thread.

Everything the worker runs is numpy-only; no Blender data is touched here.

While a worker runs, the interpreter's thread switch interval is cut to
``SWITCH_INTERVAL`` (0.2 ms instead of 5 ms): Blender's main thread takes the GIL for
every Python callback of its UI (panels, polls, timers, hundreds per redraw), and each
take waits up to one switch interval for the worker to let go. It is restored when the
last worker ends, however it ends. On Linux the worker thread also runs at a lower
priority (nice 10) so that the UI's drawing threads win the CPU.

A test hook holds a worker between steps (:data:`HOLD`), so that tests of stopping and
of the UI during a run do not depend on how fast a machine is.
"""
import os
import sys
import threading
import time
import traceback

from .framing import NothingToDraw
from .job import JobError

PUBLISH_EVERY = 0.2          # seconds between published results while a stage runs (each costs a
                             # snapshot: tens of ms on the train's thousands of fragments)
SWITCH_INTERVAL = 2e-4
WORKER_NICE = 10             # on Linux the worker yields the CPU to Blender's UI threads
JOIN_SECONDS = 30.0          # how long stopping waits for the worker's current step
_active = [0, None]          # running workers, the switch interval to restore
_active_lock = threading.Lock()


class RunnerError(RuntimeError):
    """The worker failed, or did not end when asked."""


class Hold:
    """Test hook: armed with ``after`` (a number of steps) or ``at`` (a stage and the parts
    of it done: Illustration.position), the ``run``-th worker started after arming (the
    first by default: a bake starts one per frame) waits there until :meth:`release` (or
    a stop or cancel)."""

    def __init__(self):
        self.after = self.at = None
        self.run, self.runs = 1, 0
        self._lock = threading.Lock()
        self.reached = threading.Event()
        self._go = threading.Event()

    def arm(self, after=None, at=None, run=1):
        with self._lock:
            self.after, self.at, self.run, self.runs = after, at, run, 0
        self.reached.clear()
        self._go.clear()

    def release(self):
        self.after = self.at = None
        self._go.set()

    def started(self):
        """A worker starts: its number among those started since arming."""
        with self._lock:
            self.runs += 1
            return self.runs

    def due(self, steps, illustration, run):
        if run != self.run:
            return False
        return (self.after is not None and steps == self.after) or \
            (self.at is not None and illustration.position() == tuple(self.at))

    def wait(self, steps, illustration, run, stop):
        """Hold here after the armed step, until released or stopped (once: the hook is
        disarmed as the held worker goes on)."""
        if not self.due(steps, illustration, run):
            return
        self.reached.set()
        while not self._go.wait(0.05) and not stop.is_set():
            pass
        self.after = self.at = None


HOLD = Hold()


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


class Runner:
    def __init__(self, illustration):
        self.illustration = illustration
        self._stop = threading.Event()
        self._cancel = threading.Event()
        self._lock = threading.Lock()
        self._error = None
        self._latest = None
        self._steps = 0
        self.notes = []              # what the worker could not do as it wished (not errors)
        self._thread = threading.Thread(target=self._work, name="blobtree-ink-worker", daemon=True)
        self._started = False

    def start(self):
        self._run = HOLD.started()
        _enter()
        try:
            self._thread.start()
        except BaseException:
            _leave()
            raise
        self._started = True
        return self

    def _work(self):
        try:
            self._lower_priority()
            self._loop()
        except BaseException as e:          # handed to the caller by check()
            self._error = e
        finally:
            _leave()

    def _lower_priority(self):
        """On Linux (where a thread id is a process id), nice the worker to WORKER_NICE
        unless it is nicer already; a process not allowed to change it (a limit on
        priorities) runs the worker as it is."""
        if not sys.platform.startswith("linux"):
            return
        tid = threading.get_native_id()
        try:
            if os.getpriority(os.PRIO_PROCESS, tid) < WORKER_NICE:
                os.setpriority(os.PRIO_PROCESS, tid, WORKER_NICE)
        except PermissionError as e:
            self.notes.append(f"the worker runs at the process's priority ({e.strerror})")

    def _loop(self):
        ill = self.illustration
        last = None
        while not self._cancel.is_set():
            if self._stop.is_set():
                ill.stop()
            stage = ill.stage
            going = ill.step()
            self._steps += 1
            held = HOLD.due(self._steps, ill, self._run)
            now = time.monotonic()
            if not going or held or ill.stage != stage or last is None or now - last >= PUBLISH_EVERY:
                self._publish()
                last = now
            if not going:
                return
            HOLD.wait(self._steps, ill, self._run, self._stop)

    def _publish(self):
        res = self.illustration.result()
        with self._lock:
            self._latest = res

    def latest(self):
        """The latest published result (None before the first step ends)."""
        with self._lock:
            return self._latest

    @property
    def steps(self):
        return self._steps

    def stop(self):
        """Ask for an early finish: the worker keeps what was made and draws the visible
        outlines traced so far, then ends (follow with :meth:`join`)."""
        self._stop.set()

    def cancel(self):
        """Ask the worker to end after its current step, with nothing more."""
        self._stop.set()
        self._cancel.set()

    def join(self, seconds=JOIN_SECONDS):
        """Wait for the worker to end; RunnerError if it is still running after that long."""
        if self._started:
            self._thread.join(seconds)
        if self._thread.is_alive():
            raise RunnerError(f"the illustration's worker did not end within {seconds:g} s "
                              f"(it is finishing a step on the '{self.illustration.stage}' stage)")

    @property
    def finished(self):
        return self._started and not self._thread.is_alive()

    def check(self):
        """Raise the worker's exception, if it had one (its traceback printed first: the
        message alone does not say where it came from); bad input found as the run
        began (a JobError or NothingToDraw: a light inside the model) is said in its
        own words."""
        if self._error is not None:
            traceback.print_exception(self._error)
            said = str(self._error) if isinstance(self._error, (JobError, NothingToDraw)) else repr(self._error)
            raise RunnerError(f"the illustration failed: {said}") from self._error
