"""The life of one sweep writing ``out``: its output path checked before any computing,
an exclusive lock on ``out`` for the whole run, and Ctrl-C deferred to the next point
where stopping is clean.

* :func:`check_output`: ``out`` must be a file path whose folder exists or can be made
  and is writable; an InputError names the path and the fix otherwise.
* The lock is ``<out>.lock``, held with ``flock`` (POSIX) and holding the holder's pid,
  host and start time; the kernel drops it when its process ends, even by SIGKILL, so a
  lock left by a killed sweep is taken over, and a second sweep on the same ``out`` is
  refused with the first one named.
* SIGINT (Ctrl-C) only sets a flag while a sweep runs in the main thread; the sweep
  calls :func:`check_interrupt` between chunks and raises ``KeyboardInterrupt`` there,
  so an interrupt never lands inside a compiled kernel or a C call (where it surfaces as
  ``SystemError ... returned a result with an exception set``). A second Ctrl-C
  interrupts at once.

Sessions nest (a study wraps the sweep it runs): the outer one owns the lock and the
handler.
"""

from __future__ import annotations

import contextlib
import datetime
import errno
import fcntl
import json
import os
import signal
import socket
import sys
import threading
from pathlib import Path
from typing import Iterator

from ..errors import InputError

__all__ = ["check_output", "sweep_guard", "check_interrupt", "caused_by_interrupt", "lock_path", "forget_locks"]

_HELD: dict[Path, int] = {}  # locks held by this process: resolved out -> nesting depth
_FDS: dict[Path, int] = {}  # their open descriptors
_INTERRUPT = {"installed": 0, "requested": False}


def lock_path(out: Path) -> Path:
    return out.with_name(out.name + ".lock")


def _fix(exc: OSError) -> str:
    if exc.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        return "make the folder writable or give another --out (out=) file"
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return "free space on that disk or give another --out (out=) file on another disk"
    return "give another --out (out=) file"


def check_output(out: Path, flag: str = "--out") -> None:
    """Refuse (InputError naming the path and the fix) an output file ``out`` (given as
    ``flag``) that cannot be written: a folder, a path below a file, or a folder that
    cannot be made or written to."""
    out = Path(out)
    if out.is_dir():
        raise InputError(f"{flag} {out} is a folder; give a file path such as {out / 'result.nc'}")
    for parent in out.parents:
        if parent.exists() and not parent.is_dir():
            raise InputError(f"{flag} {out} lies below {parent}, which is a file, not a folder; give another "
                             f"{flag} file")
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot make the folder {out.parent} for {flag} {out} ({exc.strerror or exc}); "
                         f"{_fix(exc).replace('--out (out=)', flag)}") from None
    if not os.access(out.parent, os.W_OK | os.X_OK):
        raise InputError(f"the folder {out.parent} of {flag} {out} is not writable; make it writable or give "
                         f"another {flag} file")


def _holder(path: Path) -> str:
    try:
        info = json.loads(path.read_text())
        return f"pid {info['pid']} on {info['host']}, started {info['started']}"
    except (OSError, ValueError, KeyError, TypeError):
        return "another process"


def _acquire(out: Path) -> int:
    """An open, flock-ed descriptor of ``<out>.lock`` holding this process's identity."""
    path = lock_path(out)
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as exc:
            raise InputError(f"cannot create the lock file {path} for --out {out} ({exc.strerror or exc}); "
                             f"{_fix(exc)}") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            raise InputError(f"another sweep is writing {out} ({_holder(path)}; lock {path}); wait for it to "
                             "finish or give another --out (out=) file") from None
        try:
            same = os.stat(path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:  # else the holder removed that file as we opened it: lock the new one
            break
        os.close(fd)
    stamp = {"pid": os.getpid(), "host": socket.gethostname(),
             "started": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")}
    os.ftruncate(fd, 0)
    os.write(fd, json.dumps(stamp).encode())
    return fd


@contextlib.contextmanager
def _locked(out: Path) -> Iterator[None]:
    key = out.resolve()
    if key in _HELD:
        _HELD[key] += 1
        try:
            yield
        finally:
            _HELD[key] -= 1
        return
    check_output(out)
    fd = _acquire(out)
    _HELD[key], _FDS[key] = 1, fd
    try:
        yield
    finally:
        del _HELD[key], _FDS[key]
        lock_path(out).unlink(missing_ok=True)  # before the release: a waiting sweep then locks a new file
        os.close(fd)


def forget_locks() -> None:
    """In a process forked from a sweep's: close the inherited descriptors of the sweep's
    locks, without unlocking (the lock belongs to the open file, which the sweep's process
    still holds), so that they go with the sweep's process alone."""
    for fd in _FDS.values():
        with contextlib.suppress(OSError):
            os.close(fd)
    _HELD.clear()
    _FDS.clear()


def _on_sigint(signum, frame) -> None:
    if _INTERRUPT["requested"]:  # asked twice: stop now
        raise KeyboardInterrupt
    _INTERRUPT["requested"] = True
    print("periodyn: stopping after the current chunk (Ctrl-C again stops at once)", file=sys.stderr, flush=True)


def caused_by_interrupt(exc: BaseException | None) -> bool:
    """Whether a KeyboardInterrupt is in the cause/context chain of ``exc`` (Ctrl-C that
    landed inside a C call surfaces as a SystemError caused by it)."""
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def check_interrupt() -> None:
    """Raise KeyboardInterrupt if Ctrl-C was pressed since the session began."""
    if _INTERRUPT["requested"]:
        raise KeyboardInterrupt


@contextlib.contextmanager
def _deferred_interrupts() -> Iterator[None]:
    own = (not _INTERRUPT["installed"] and threading.current_thread() is threading.main_thread()
           and signal.getsignal(signal.SIGINT) is signal.default_int_handler)
    if not own:
        yield
        return
    _INTERRUPT.update(installed=1, requested=False)
    signal.signal(signal.SIGINT, _on_sigint)
    try:
        yield
        check_interrupt()  # pressed during the last step: the result is written, report the interrupt
    finally:
        signal.signal(signal.SIGINT, signal.default_int_handler)
        _INTERRUPT.update(installed=0, requested=False)


@contextlib.contextmanager
def sweep_guard(out: Path | None) -> Iterator[None]:
    """One sweep's run: ``out`` checked and locked (when given), Ctrl-C deferred to
    :func:`check_interrupt`. Re-entrant within a process."""
    with _deferred_interrupts():
        if out is None:
            yield
            return
        with _locked(Path(out)):
            yield
