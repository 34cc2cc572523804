"""Where the cases of a study run: in this process, on local worker processes, or on a dask cluster.

:func:`execute` yields each case's result as it finishes; a local worker that dies has its unfinished cases
run again in a new pool, a dask worker's are retried by dask (or recorded as ``lost``). Ctrl-C is this process's
alone: local workers ignore SIGINT from their start, and an interrupted study stops them (:func:`_stop`).
:func:`connect` refuses an address that does not answer before anything runs. Used by
:func:`mol_shell.runs.study.study`.
"""

from __future__ import annotations

import asyncio
import collections
import contextlib
import multiprocessing
import os
import signal
import sys
import time
import warnings
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, ThreadPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool

import numpy as np
from threadpoolctl import threadpool_limits

from mol_shell._core import interrupts
from mol_shell._core.errors import ParameterError, RunWarning
from mol_shell.runs.worker_start import openblas_threads, start_method

#: seconds to wait for a dask scheduler to answer before the study is refused
SCHEDULER_TIMEOUT = 10.0


def connect(scheduler):
    """A ``distributed.Client`` for a scheduler address (``None`` for local processes or ``"serial"``).

    Raises :class:`ParameterError` for an address that is malformed or does not answer within
    :data:`SCHEDULER_TIMEOUT` seconds, so a study never starts on a cluster it cannot reach.
    """
    if scheduler is None or scheduler == "serial":
        return None
    allowed = "'serial', or the address of a running dask scheduler such as tcp://host:8786, or a distributed.Client"
    if isinstance(scheduler, str) and ":" not in scheduler:  # no port and no protocol: refused before dask's import
        raise ParameterError.invalid("scheduler", scheduler, "is not a scheduler address", allowed,
                                     hint=f"missing port number in address {scheduler!r}")
    try:
        from distributed import Client
    except ImportError:
        raise ParameterError.invalid("scheduler", scheduler, "needs dask.distributed, which is not installed",
                                     allowed, hint="pip install 'mol_shell[dask]'") from None
    if isinstance(scheduler, Client):
        return scheduler
    if not isinstance(scheduler, str) or not scheduler.strip():
        raise ParameterError.not_a("scheduler", scheduler, "a scheduler address", allowed)
    from distributed.comm import resolve_address

    try:  # before a Client exists: one made for a malformed address is left half-open, and closing it at exit
        # waits 20 s and prints a traceback
        with warnings.catch_warnings():  # a protocol dask no longer has warns, then raises the same text
            warnings.simplefilter("ignore")
            resolve_address(scheduler)
    except ValueError as exc:
        raise ParameterError.invalid("scheduler", scheduler, "is not a scheduler address", allowed,
                                     hint=str(exc)) from None
    except OSError as exc:  # a host name that does not resolve
        raise ParameterError.invalid("scheduler", scheduler, "does not name a reachable host", allowed,
                                     hint=f"{type(exc).__name__}: {exc}") from None
    except Exception as exc:  # noqa: BLE001 - a protocol this installation of dask cannot use
        text = " ".join(str(exc).split())
        raise ParameterError.invalid("scheduler", scheduler, "is not an address this dask can connect to", allowed,
                                     hint=f"{type(exc).__name__}: {text}".rstrip(": ")) from None
    _ask_identity(scheduler, allowed)
    client = Client.__new__(Client)  # held, so that one left half-open is closed here and not at exit (which
    try:  # waited 20 s and printed a traceback)
        # not the default client: a failed connection would otherwise leave dask (and xarray's netCDF locks)
        # pointing at the unreachable scheduler for the rest of the process
        client.__init__(scheduler, timeout=SCHEDULER_TIMEOUT, set_as_default=False)
        return client
    except Exception as exc:  # noqa: BLE001 - OSError, TimeoutError, or distributed's own failures to start
        with contextlib.suppress(Exception):
            client.close(timeout=1)
        text = str(exc).splitlines()[0] if str(exc) else ""
        raise ParameterError.invalid("scheduler", scheduler, f"does not answer within {SCHEDULER_TIMEOUT:g} s",
                                     allowed, hint=f"{type(exc).__name__}: {text}".rstrip(": ")) from None


def _ask_identity(scheduler, allowed):
    """Refuse an address where no dask scheduler answers, in :data:`SCHEDULER_TIMEOUT` seconds at most: a dask
    ``Client`` waits for the handshake without end, so an HTTP server or any service that accepts and stays
    silent hung a study (and its half-open client printed a traceback at exit). One connection, its
    handshake and the ``identity`` call, in a thread of its own (the caller's may be running an event loop)."""
    with ThreadPoolExecutor(1) as pool:
        try:
            identity = pool.submit(asyncio.run, _identity(scheduler)).result()
        except TimeoutError:  # connected (dask's own connect gives up first), then silence
            raise ParameterError.invalid("scheduler", scheduler, "does not answer as a dask scheduler within "
                                         f"{SCHEDULER_TIMEOUT:g} s", allowed, hint="it accepts the connection but "
                                         "sends no dask handshake") from None
        except OSError as exc:  # nothing listens, or no connection (dask retries until the time is up)
            raise ParameterError.invalid("scheduler", scheduler, f"does not answer within {SCHEDULER_TIMEOUT:g} s",
                                         allowed, hint=f"{type(exc).__name__}: {exc}".splitlines()[0]) from None
        except Exception:  # noqa: BLE001 - an answer that is not dask's: an 8-byte length of 3 EiB, a bad frame
            raise ParameterError.invalid("scheduler", scheduler, "does not answer as a dask scheduler", allowed,
                                         hint="something listens there but speaks another "
                                         "protocol: an HTTP server, say") from None
    kind = identity.get("type") if isinstance(identity, dict) else None
    if kind != "Scheduler":
        raise ParameterError.invalid("scheduler", scheduler, "does not answer as a dask scheduler", allowed,
                                     hint=f"it is a dask {kind}" if isinstance(kind, str) else "")


async def _identity(address):
    from distributed.comm import connect as dask_connect
    from distributed.security import Security

    async def ask():
        # a line end in the handshake (a key dask ignores): a line-based service (HTTP) answers it at once
        # instead of waiting for the line, so its answer, which is not dask's, is refused at once
        comm = await dask_connect(address, timeout=SCHEDULER_TIMEOUT, handshake_overrides={"probe": "\r\n\r\n"},
                                  **Security().get_connection_args("client"))
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    return await asyncio.wait_for(ask(), SCHEDULER_TIMEOUT + 0.5)


def execute(run_task, tasks, scheduler, workers, client=None, started=None):
    """Yield ``run_task(task)``, i.e. ``(index, ds, info)``, as cases finish, on the chosen back end (``client``: a
    connected cluster). ``run_task`` must be importable by name (it is sent to other processes). ``started``, a list,
    gets the start method of each pool of local workers made (:func:`start_method`)."""
    if not tasks:
        return
    if scheduler == "serial":
        for task in tasks:
            yield run_task(task)
        return
    if scheduler is None:
        yield from _execute_local(run_task, tasks, workers, started)
        return
    from distributed import as_completed

    if client is None:
        client = connect(scheduler)
    futures = client.map(run_task, tasks, pure=False)
    owner = {f.key: t for f, t in zip(futures, tasks)}
    try:
        with client.as_current():  # the client is not the process-wide default (see connect)
            for future in as_completed(futures):
                yield _collect(future, owner[future.key])
    finally:
        client.cancel(futures)


#: thread counts of the compiled kernels and of the numerical libraries' pools (which size themselves when a
#: process loads them): one each in every process of a local study, unless the user set them
THREAD_VARIABLES = ("MOL_SHELL_THREADS", "OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


@contextlib.contextmanager
def _one_thread_per_process():
    """Local processes share the cores: each runs its cases on one thread. Sets :data:`THREAD_VARIABLES` (unless
    set), which the workers inherit and libraries loaded later read, and limits the pools this process
    has loaded already (two processes with two BLAS threads each made the spectrum of every case contend; idle
    BLAS threads spinning here made a study 1.5x slower). Once for the whole study: threadpoolctl's search of
    the loaded libraries costs 1 ms a time. This process's settings are restored afterwards."""
    saved = {name: os.environ.get(name) for name in THREAD_VARIABLES}
    for name in THREAD_VARIABLES:
        os.environ.setdefault(name, "1")
    try:
        with threadpool_limits(limits=1):
            yield
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value


#: times a case whose local worker process died (killed, out of memory) is run again before it is recorded ``lost``
LOST_RETRIES = 2


#: cases handed to each worker ahead of time: the one it runs and two waiting, so it never waits for
#: this process (busy with a case of its own) to hand it the next
AHEAD = 3


def _execute_local(run_task, tasks, workers, started=None):
    """Cases on ``workers`` local processes: this one and ``workers - 1`` started ones (:func:`start_method`).

    The workers are handed cases from the front of the queue, :data:`AHEAD` each; this process, which has
    the package imported and its kernels loaded, runs them from the back, so it computes from the first moment
    while a spawned worker spends 0.5-1.5 s starting (a forked one, the default where it is safe, starts at once).
    Who runs a case is settled in a table shared with the workers (:class:`_Claims`): a worker claims a case as it
    starts it and skips one this process has claimed, so at the end this process also takes the handed-over cases no
    worker has started, and
    the two finish within about a case of each other. A worker that dies breaks its pool: the case it was
    running (the table says which) runs again in a new pool, up to :data:`LOST_RETRIES` times, and the cases it
    had not started run there as they were. Ctrl-C reaches this process only (:func:`_starting_workers`): its case
    ends ``"interrupted"`` (or the interrupt lands here), and the workers are stopped, not waited for (:func:`_stop`).
    """
    refuse_in_starting_worker()
    attempts = {task.index: 0 for task in tasks}
    pending, alone = list(tasks), False
    blas_threads = openblas_threads()  # as loaded: the limits below make the pools' sizes read 1
    with _one_thread_per_process():
        while pending:
            spawned = 0 if alone else max(1, min(workers or os.cpu_count() or 1, len(pending))) - 1
            if not spawned:  # this process alone
                for task in pending:
                    yield _retried(run_task(task), attempts[task.index])
                return
            method = start_method(blas_threads)  # again for each pool: a broken pool's thread may still run
            if started is not None:
                started.append(method)
            context = multiprocessing.get_context(method)
            claims = _Claims(context, len(pending))
            pool = ProcessPoolExecutor(max_workers=spawned, mp_context=context, initializer=_worker_start,
                                       initargs=(claims,))
            queue, running, failed, mine = collections.deque(range(len(pending))), {}, [], set()
            ended = False
            try:
                while queue or running:
                    for future in [f for f in running if f.done()]:
                        slot = running.pop(future)
                        if isinstance(future.exception(), BrokenProcessPool):
                            failed.append(slot)
                        elif future.result() is not None:  # None: skipped, claimed by this process
                            yield _retried(_collect(future, pending[slot]), attempts[pending[slot].index])
                    if queue and not failed and len(running) < AHEAD * spawned:
                        with _starting_workers():  # the pool starts its processes in its submits
                            while queue and not failed and len(running) < AHEAD * spawned:
                                slot = queue.popleft()
                                try:
                                    running[pool.submit(_claimed, run_task, pending[slot], slot)] = slot
                                except BrokenProcessPool:  # a worker died since the futures were read: the slot
                                    failed.append(slot)  # was not handed over and runs again without an attempt
                    slot = _next_here(queue, running, claims) if not failed else None
                    if slot is not None:
                        mine.add(slot)
                        yield _retried(run_task(pending[slot]), attempts[pending[slot].index])
                    elif running:
                        wait(running, return_when=FIRST_COMPLETED)
                    elif failed:
                        break
                ended = True
            finally:
                claims.close()  # interrupted, or done: a worker starts nothing more
                if ended:  # every result in (or the pool broken): the workers exit on their own, waited for so
                    with interrupts.held():  # that the pool's semaphores go with it (a Ctrl-C later left them to
                        pool.shutdown(wait=True, cancel_futures=True)  # the resource tracker, which warned)
                else:  # Ctrl-C, an error, or the caller stopped reading: the workers' cases are not waited for
                    _stop(pool)
            if failed and not any(claims.owner(slot) > 0 for slot in range(len(pending))):
                alone = True  # the workers died before any case: a new pool would too
                warnings.warn(_NO_START.format(left=len((set(failed) | set(queue)) - mine)), RunWarning,
                              stacklevel=5)  # the caller of study (through execute and run_cases)
            again, lost = [], []
            for slot in sorted((set(failed) | set(queue)) - mine):
                task = pending[slot]
                if claims.owner(slot) > 0:  # the worker that died was running it (or had finished it unread)
                    if attempts[task.index] >= LOST_RETRIES:
                        lost.append(task)
                        continue
                    attempts[task.index] += 1
                again.append(task)
            for task in lost:
                yield _retried((task.index, None, {"status": "lost", "message": "BrokenProcessPool",
                                                   "case_wall_time_s": float("nan"), "worker": ""}),
                               attempts[task.index])
            pending = again


#: why a study's workers could not start, said once (the cases then run in the calling process)
_NO_START = ("the local worker processes stopped before their first case (see what they printed above; a script "
             'that starts a study outside if __name__ == "__main__": is the usual cause), so this process runs the '
             "study's remaining cases ({left})")


def refuse_in_starting_worker():
    """Stop a spawned worker that is still importing the user's main script, which starts a study at its top
    level: one line saying what to change, where multiprocessing raised a long RuntimeError (and the study went
    on spawning workers that died the same way). Called first thing by the studies (before any check, file or
    case: with every case stored, the worker ran the whole script); ``_inheriting`` is the flag multiprocessing's
    own check reads."""
    if getattr(multiprocessing.current_process(), "_inheriting", False):
        script = next((m.__file__ for m in map(sys.modules.get, ("__mp_main__", "__main__"))  # the first: as it runs
                       if getattr(m, "__file__", None)), "the main script")
        raise SystemExit(f"mol_shell: a study's worker process re-ran {script} as it started (Python's spawned "
                         "processes import the main script), and the script starts a study at its top level: put "
                         'the study under if __name__ == "__main__":')


def _next_here(queue, running, claims):
    """The slot this process runs next, claimed: the back of the queue, else the newest case handed to a worker
    that no worker has started; ``None`` when every case left is a worker's."""
    if queue:
        slot = queue.pop()
        claims.take(slot)
        return slot
    for slot in sorted(running.values(), reverse=True):
        if claims.take(slot):
            return slot
    return None


class _Claims:
    """Who runs each case of a pool: 0 nobody yet, -1 this process, else the pid of the worker that started it.

    Shared memory with a lock, handed to the workers when they start (:func:`_worker_start`)."""

    def __init__(self, context, size):
        self.table = context.Array("q", size)

    def take(self, slot, owner=-1):
        """Claim ``slot`` for ``owner``; False if someone has it already."""
        with self.table.get_lock():
            if self.table[slot]:
                return False
            self.table[slot] = owner
            return True

    def owner(self, slot):
        return self.table[slot]

    def close(self):
        """Claim every free case for this process: the workers skip whatever they have not started."""
        with self.table.get_lock():
            for slot in range(len(self.table)):
                self.table[slot] = self.table[slot] or -1


_CLAIMS = None

#: seconds that a stopped study's local workers have to end after SIGTERM before they are killed
STOP_WAIT = 2.0


@contextlib.contextmanager
def _starting_workers():
    """Around the calls that start a pool's processes: Ctrl-C is for this process alone. SIGINT is blocked in this
    thread, and every process started meanwhile inherits the mask (a spawned one through its exec, the forkserver
    too, whose children inherit it from there), so the signal of a terminal's Ctrl-C, sent to the whole process
    group, stays pending in a worker until :func:`_worker_start` ignores it (it then never arrives): a worker
    interrupted in its imports printed a KeyboardInterrupt traceback, one interrupted as it sent a result back left
    half a message in the pool's pipe, for which the pool then waited forever. Setting SIGINT to ``SIG_IGN`` here
    instead would lose a Ctrl-C that arrives meanwhile; this way this process notes one
    (:func:`mol_shell._core.interrupts.held`) and raises ``KeyboardInterrupt`` once the processes are started.
    A main script that is no file (:func:`_main_not_a_file`) is not re-run by the workers."""
    with interrupts.held(), _main_not_a_file():
        if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - Windows: no process groups, no mask
            yield
            return
        mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
        try:
            yield
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, mask)


@contextlib.contextmanager
def _main_not_a_file():
    """Around the start of spawned (or forkserver) workers: a main module whose ``__file__`` is no file (a script
    read from stdin, ``python - < script.py``: ``'<stdin>'``) is hidden from them, as for ``python -c``, instead of
    each worker's failing to run it again (a traceback ending ``FileNotFoundError: ... '<stdin>'``, and the study's
    cases all in this process). Its ``__file__`` is put back once the processes are started."""
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    by_name = getattr(getattr(main, "__spec__", None), "name", None)  # python -m: re-imported by name
    if path is None or by_name is not None or os.path.isfile(os.path.join(multiprocessing.process.ORIGINAL_DIR or "",
                                                                           path)):
        yield
        return
    del main.__file__
    try:
        yield
    finally:
        main.__file__ = path


def _worker_start(claims):
    """A worker's initializer: SIGINT ignored, then unblocked (a Ctrl-C pending since the worker started is dropped:
    :func:`_starting_workers`), SIGTERM's default action (a forked worker inherits the command line's handler, which
    takes it as a Ctrl-C: :func:`_stop` ends workers with it), and the claims table."""
    global _CLAIMS
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if hasattr(signal, "pthread_sigmask"):
        signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    _CLAIMS = claims


def _stop(pool):
    """End the workers of a study that stops early (Ctrl-C, an error): SIGTERM, and SIGKILL for one still alive
    after :data:`STOP_WAIT` s, instead of a shutdown that waits for the cases they run (minutes, perhaps) and can wait
    forever: a worker ended as it wrote a result leaves part of it in the result pipe, where the pool's thread waits
    for the rest. Closing this process's end of that pipe, its last writer once the workers are gone, turns that wait
    into an end of file, which breaks the pool, and the pool's thread then ends (Python's exit waits for it). Ctrl-C
    meanwhile is held back until the workers are gone. Uses the pool's ``_processes`` and ``_result_queue``, which
    Python 3.11 keeps private (3.14 has ``terminate_workers``)."""
    with interrupts.held():
        processes = list((getattr(pool, "_processes", None) or {}).values())
        for process in processes:
            process.terminate()
        deadline = time.monotonic() + STOP_WAIT
        for process in processes:
            process.join(max(0.0, deadline - time.monotonic()))
            if process.exitcode is None:
                process.kill()
                process.join(STOP_WAIT)
        writer = getattr(getattr(pool, "_result_queue", None), "_writer", None)
        if writer is not None:
            writer.close()
        pool.shutdown(wait=True, cancel_futures=True)


def _claimed(run_task, task, slot):
    """``run_task(task)`` in a worker if the case is still free (claimed for this worker), else ``None``."""
    if not _CLAIMS.take(slot, os.getpid()):
        return None
    return run_task(task)


def _retried(result, attempts):
    """A case's ``(index, ds, info)``, its message saying how often it ran when a worker died under it before."""
    if attempts:
        result[2]["message"] += f" (run {attempts + 1} times: a worker process died)"
    return result


def _collect(future, task):
    """The result of a finished future; a task that died outside our code is recorded as ``lost``."""
    try:
        return future.result()
    except Exception as exc:  # noqa: BLE001 - e.g. a killed worker
        return task.index, None, {"status": "lost", "message": f"{type(exc).__name__}: {exc}",
                                  "case_wall_time_s": float("nan"), "worker": ""}


def check_workers(workers, scheduler):
    """Refuse ``workers`` that is not a count of local processes up to the machine's cores, or that is given with
    another scheduler (it was ignored there: "serial" is this process alone, which ``workers=1`` may say, a cluster
    has its own workers)."""
    if scheduler is None:
        start_method()  # a start method this platform lacks is refused before anything runs
    if workers is None:
        return
    most = most_workers()
    if not (isinstance(workers, (int, np.integer)) and not isinstance(workers, bool) and workers >= 1):
        raise ParameterError("workers", workers, f"integers in [1, {most}]")
    if scheduler is None and workers > most:  # 30 processes on 2 cores ran a study 4.7x slower than 2
        raise ParameterError("workers", workers, f"integers in [1, {most}]", hint="at most this machine's cores (2 "
                             "on one): each local process runs its cases on one core, and more processes than cores "
                             "only share them, each with its own start and memory")
    if scheduler is not None and not (scheduler == "serial" and workers == 1):  # serial is one process: 1 agrees
        # it said "workers = 2 is outside None with scheduler = 'serial'"
        serial = scheduler == "serial"
        which = ("'serial', which runs every case in this process" if serial else
                 f"{scheduler_name(scheduler)!r}, a dask cluster with workers of its own")
        raise ParameterError.invalid("workers", workers, "applies to local processes (scheduler None, the default), "
                                     f"not to scheduler = {which}", "1 or None (left out) with scheduler = 'serial'"
                                     if serial else "None (left out) with a dask scheduler")


def most_workers():
    """The most local processes a study takes: the cores this process may run on, at least 2."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    return max(2, cores)


def scheduler_name(scheduler):
    if scheduler is None:
        return "local processes"
    return scheduler if isinstance(scheduler, str) else type(scheduler).__name__


def scheduler_attrs(scheduler, started):
    """A study's ``scheduler`` attribute, and for local processes ``worker_start``: how their pools' workers started
    (``started``, from :func:`execute`: ``"fork"``, ``"spawn"``, both when a pool broke and the next one could not
    fork, ``"none"`` when this process ran every case)."""
    attrs = {"scheduler": scheduler_name(scheduler)}
    if scheduler is None:
        attrs["worker_start"] = ", ".join(dict.fromkeys(started)) or "none"
    return attrs
