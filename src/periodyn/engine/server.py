"""A warm server for the command line: one long-lived process that has imported periodyn
and loaded the compiled kernels of the speed solver and of every model family it has
served, and that forks a fresh process for each command sent to it (``periodyn serve``).

A ``periodyn sweep`` in a new interpreter first spends seconds importing and loading
kernels from Numba's cache (the Cardan shaft: about 4 s of imports, then 1 s of kernel
loading under Numba's global compiler lock before its model is built, and 0.3-0.5 s more
in every worker), all of it serial. A command run by the server starts with all of that
done; its sweep forks its workers from itself, so they start with the kernels too.

* The server listens on a Unix socket in a folder only its user can enter
  (:func:`server_dir`), named by :func:`server_key`: the code (every periodyn source and
  the Python, NumPy and Numba versions), the interpreter and the environment variables
  read at import (``NUMBA_*``, ``*_NUM_THREADS``). A client with other code or threads
  finds no socket and runs the command itself.
* The client sends its arguments, working folder, environment and its standard streams
  (the descriptors themselves, over the socket): the command's output, progress and
  errors appear where they would have, and its exit status is the client's. Ctrl-C (and
  SIGTERM) at the client is passed on to the command's process.
* Between commands the server loads the kernels of what it served (``learn``), one
  at a time and only while no command runs, so the next command of that family starts warm.
* It forks only while it is the only thread of its process (:func:`pools.fork_problem`),
  and stops after ``idle`` seconds without a command.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import os
import platform
import signal
import socket
import sys
import tempfile
import time
import traceback
from importlib import metadata
from pathlib import Path
from typing import Callable

from ..errors import InputError

__all__ = ["SERVER_ENV", "SERVER_DIR_ENV", "IDLE_S", "code_version", "server_dir", "server_key", "socket_path",
           "ping", "stop", "delegate", "serve"]

#: "off": never hand a command to a server
SERVER_ENV = "PERIODYN_SERVER"
#: the folder of the servers' sockets and logs (default: ``$XDG_RUNTIME_DIR`` or the temporary folder, then periodyn-<uid>)
SERVER_DIR_ENV = "PERIODYN_SERVER_DIR"
#: a server stops after this many seconds without a command
IDLE_S = 3600.0
_SOCKET_PATH_MAX = 100  # sun_path holds 108 bytes on Linux, 104 on macOS
_FORWARDED = (signal.SIGINT, signal.SIGTERM)


@functools.lru_cache(maxsize=1)
def code_version() -> str:
    """Hash of every periodyn source file and the Python, NumPy and Numba versions (what a
    server and the built-model cache are keyed by; imports neither NumPy nor Numba)."""
    package = Path(__file__).resolve().parents[1]
    versions = f"{platform.python_version()} {metadata.version('numpy')} {metadata.version('numba')}"
    digest = hashlib.sha256(versions.encode())
    for path in sorted(package.rglob("*.py")):
        digest.update(str(path.relative_to(package)).encode() + b"\0" + path.read_bytes() + b"\0")
    return digest.hexdigest()


def _supported() -> str:
    """Why this platform cannot run a server ('' where it can): commands are forked, which
    is safe only on Linux, and reach it over a Unix socket that carries descriptors."""
    if not sys.platform.startswith("linux") or not hasattr(socket, "send_fds"):
        return "periodyn serve runs on Linux only (it forks each command from a process holding loaded kernels)"
    return ""


def server_dir() -> Path:
    """Folder of the sockets and logs of this user's servers."""
    base = os.environ.get(SERVER_DIR_ENV)
    if base:
        return Path(base)
    return Path(os.environ.get("XDG_RUNTIME_DIR") or tempfile.gettempdir()) / f"periodyn-{os.getuid()}"


def server_key() -> str:
    """What a server must share with its clients: the code, the interpreter and the
    environment variables read at import (20 hex digits)."""
    fixed = sorted((k, v) for k, v in os.environ.items() if k.startswith("NUMBA_") or k.endswith("_NUM_THREADS"))
    text = json.dumps([code_version(), sys.executable, sys.prefix, fixed])
    return hashlib.sha256(text.encode()).hexdigest()[:20]


def socket_path() -> Path:
    """The socket of the server for this code, interpreter and environment."""
    return server_dir() / f"{server_key()}.sock"


def _private_dir(folder: Path) -> Path:
    """``folder``, created for this user alone; refused if another user owns it or may enter it."""
    folder.mkdir(mode=0o700, parents=True, exist_ok=True)
    info = folder.stat()
    if info.st_uid != os.getuid() or info.st_mode & 0o077:
        raise InputError(f"the server folder {folder} is open to other users (owner uid {info.st_uid}, mode "
                         f"{oct(info.st_mode & 0o777)}); remove it, or set {SERVER_DIR_ENV} to a folder of your own")
    return folder


def _connect(path: Path, timeout: float | None) -> socket.socket | None:
    """A connection to the server at ``path``, or None where none answers."""
    if len(os.fsencode(path)) > _SOCKET_PATH_MAX or not path.exists():
        return None
    sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    sock.settimeout(timeout)
    try:
        sock.connect(os.fspath(path))
    except OSError:
        sock.close()
        return None
    return sock


def _request(sock: socket.socket, message: dict, fds: list[int] = ()) -> None:
    """One request: a byte carrying the descriptors ``fds``, then the message as a JSON line."""
    socket.send_fds(sock, [b"R"], list(fds))
    sock.sendall(json.dumps(message).encode() + b"\n")


def _ask(message: dict, path: Path | None, fds: list[int] = (), then=None):
    """Send ``message`` (with the descriptors ``fds``) to the server at ``path`` (default
    :func:`socket_path`) and read its first reply, waiting as long as the server takes (one
    loading kernels answers when done); ``then(reply, replies)`` reads on. None where no
    server answers."""
    if _supported():
        return None
    sock = _connect(path or socket_path(), timeout=5.0)
    if sock is None:
        return None
    with sock, sock.makefile("rb") as replies:
        try:
            _request(sock, message, fds)
            sock.settimeout(None)
            reply = json.loads(replies.readline() or b"null")
        except (OSError, ValueError):
            return None  # the server went away before it answered
        return reply if then is None or not isinstance(reply, dict) else then(reply, replies)


def ping(path: Path | None = None) -> dict | None:
    """The server's state (``pid``, ``key``, ``learned``: the kernel families it holds,
    ``idle_s``) or None where none answers at ``path`` (default :func:`socket_path`)."""
    return _ask({"op": "ping"}, path)


def stop(path: Path | None = None) -> bool:
    """Stop the server at ``path`` (default :func:`socket_path`); False where none answered.
    Commands it is running finish."""
    return _ask({"op": "stop"}, path) is not None


def delegate(argv: list[str], path: Path | None = None) -> int | None:
    """Run the command ``argv`` in the server at ``path`` (default :func:`socket_path`), with
    this process's standard streams, folder and environment; its exit status, or None where
    no server answers (or ``PERIODYN_SERVER=off``, or a standard stream is closed): then the
    caller runs the command itself. The first reply is the command's process id, sent by
    that process: a command is never run both there and here."""
    if os.environ.get(SERVER_ENV, "").lower() == "off" or (path is None and not server_dir().is_dir()):
        return None  # (no folder, no server: the code is not even hashed)
    try:
        for fd in (0, 1, 2):
            os.fstat(fd)
    except OSError:
        return None
    message = {"op": "run", "argv": list(argv), "cwd": os.getcwd(), "env": dict(os.environ)}
    try:
        code = _ask(message, path, [0, 1, 2], then=_started)
    except KeyboardInterrupt:  # before the command started: its process, finding no client, ends unstarted
        print(f"periodyn {argv[0] if argv else ''}: interrupted before the server started the command",
              file=sys.stderr)
        return 130
    return code


def _started(reply: dict, replies) -> int | None:
    return _wait(replies, int(reply["pid"])) if "pid" in reply else None


def _wait(replies, pid: int) -> int:
    """The exit status the command's process ``pid`` reports on ``replies``, passing this
    process's SIGINT and SIGTERM on to it meanwhile."""
    def forward(signum, frame):
        with contextlib.suppress(OSError):
            os.kill(pid, signum)

    previous = {s: signal.signal(s, forward) for s in _FORWARDED}
    try:
        line = replies.readline()  # a signal handled meanwhile does not end the read (PEP 475)
    except OSError:
        line = b""
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    try:
        return int(json.loads(line)["exit"])
    except (ValueError, KeyError, TypeError):
        print(f"periodyn: the server's process {pid} for this command ended without an exit status "
              "(killed?); its output above is all there is", file=sys.stderr)
        return 1


def serve(command: Callable[[list[str]], int], learn: Callable[[list[str], set[str]], str | None] | None = None,
          idle: float = IDLE_S, path: Path | None = None, preload: Callable[[], set[str]] | None = None,
          ready: Callable[[Path], None] | None = None) -> int:
    """Serve commands until stopped or ``idle`` seconds pass without one: each in a process
    forked from this one that runs ``command(argv)`` with the client's streams, folder and
    environment. ``preload()`` runs first (it loads kernels, and returns their families);
    ``learn(argv, learned)`` runs here after each command, while none runs: it loads the
    kernels of ``argv``'s command unless its family is in ``learned``, and returns the
    family (or None); ``ready(path)`` is called once the socket listens. Returns an exit
    status."""
    if _supported():
        raise InputError(_supported())
    path = path or socket_path()
    _private_dir(path.parent)
    if len(os.fsencode(path)) > _SOCKET_PATH_MAX:
        raise InputError(f"the socket path {path} is longer than Unix sockets allow ({_SOCKET_PATH_MAX} bytes); "
                         f"set {SERVER_DIR_ENV} to a shorter folder")
    from .pools import fork_problem

    if ping(path) is not None:
        raise InputError(f"a server already answers at {path}; stop it with `periodyn serve stop`")
    learned = set(preload()) if preload is not None else set()
    problem = fork_problem()
    if problem:
        print(f"periodyn serve: loading the kernels left this process unable to fork commands safely: {problem}",
              file=sys.stderr)
        return 1
    with contextlib.suppress(FileNotFoundError):
        path.unlink()
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit(0))  # `kill` removes the socket too
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(os.fspath(path))
    os.chmod(path, 0o600)
    listener.listen(64)
    listener.settimeout(1.0)
    children: set[int] = set()
    pending: list[tuple[list[str], str]] = []  # (argv, folder) of commands whose kernels to load here
    last = time.monotonic()
    if ready is not None:
        ready(path)
    try:
        while True:
            _reap(children)
            if pending and not children:
                if not _learn(learn, *pending.pop(0), learned):
                    return 1
                continue
            try:
                conn, _ = listener.accept()
            except TimeoutError:
                if not children and time.monotonic() - last > idle:
                    return 0
                continue
            last = time.monotonic()
            conn.settimeout(10.0)
            fds: list[int] = []
            with conn:
                try:
                    _, fds, _, _ = socket.recv_fds(conn, 1, 3)
                    with conn.makefile("rb") as lines:
                        message = json.loads(lines.readline())
                    op = message.get("op") if isinstance(message, dict) else None
                except (OSError, ValueError):
                    op = None
                if op == "ping":
                    _reply(conn, {"pid": os.getpid(), "key": path.stem, "learned": sorted(learned),
                                  "running": len(children), "idle_s": idle})
                elif op == "stop":
                    _reply(conn, {"stopped": os.getpid()})
                    return 0
                elif op == "run" and len(fds) == 3 and _is_command(message):
                    pid = os.fork()
                    if pid == 0:
                        listener.close()
                        _run_command(command, conn, fds, message)  # never returns
                    children.add(pid)
                    if learn is not None:
                        pending.append((list(message["argv"]), message["cwd"]))
                for fd in fds:
                    os.close(fd)
    finally:
        listener.close()
        with contextlib.suppress(FileNotFoundError):
            path.unlink()


def _is_command(message: dict) -> bool:
    """Whether a "run" request carries what running it needs (else it is dropped: the client runs it)."""
    argv, cwd, env = message.get("argv"), message.get("cwd"), message.get("env")
    return (isinstance(argv, list) and all(isinstance(a, str) for a in argv) and isinstance(cwd, str)
            and isinstance(env, dict) and all(isinstance(k, str) and isinstance(v, str) for k, v in env.items()))


def _reply(conn: socket.socket, message: dict) -> None:
    with contextlib.suppress(OSError):
        conn.sendall(json.dumps(message).encode() + b"\n")


def _reap(children: set[int]) -> None:
    for pid in list(children):
        with contextlib.suppress(ChildProcessError):
            done, _ = os.waitpid(pid, os.WNOHANG)
            if not done:
                continue
        children.discard(pid)


def _learn(learn, argv: list[str], cwd: str, learned: set[str]) -> bool:
    """Load the kernels of ``argv``'s command (run in the folder ``cwd``) here, so the next
    such command starts warm; a failure only leaves them unloaded (the command itself has
    reported its errors). False where this process can no longer fork safely: the server
    stops, and commands run in their own processes."""
    from .pools import fork_problem

    try:
        os.chdir(cwd)
        family = learn(argv, learned)
    except Exception:  # noqa: BLE001 - the server outlives a command it could not learn from
        traceback.print_exc()
    else:
        if family:
            learned.add(family)
    problem = fork_problem()
    if problem:
        print(f"periodyn serve: loading the kernels of {argv} left this process unable to fork commands safely: "
              f"{problem}; the server stops", file=sys.stderr)
    return not problem


def _run_command(command, conn: socket.socket, fds: list[int], message: dict) -> None:
    """In the forked process: say its pid (the first reply, so the client never reads a
    status before it), take the client's streams, folder and environment, run the command,
    report its exit status and end."""
    try:
        conn.sendall(json.dumps({"pid": os.getpid()}).encode() + b"\n")
    except OSError:
        os._exit(1)  # the client went away before the command started: it runs it itself, or not at all
    code = 1
    try:
        for target, fd in zip((0, 1, 2), fds):
            os.dup2(fd, target)
            os.close(fd)
        for stream in (sys.stdout, sys.stderr):
            stream.reconfigure(line_buffering=os.isatty(stream.fileno()))
        os.chdir(message["cwd"])
        os.environ.clear()
        os.environ.update(message["env"])
        sys.argv = ["periodyn", *message["argv"]]
        for s in _FORWARDED:
            signal.signal(s, signal.default_int_handler if s == signal.SIGINT else signal.SIG_DFL)
        code = command(list(message["argv"]))
    except SystemExit as exc:
        code = exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 1)
        if exc.code is not None and not isinstance(exc.code, int):
            print(exc.code, file=sys.stderr)
    except KeyboardInterrupt:
        code = 130
    except BaseException:  # noqa: BLE001 - reported to the client as the command's failure
        traceback.print_exc()
        code = 1
    finally:
        with contextlib.suppress(Exception):
            sys.stdout.flush()
            sys.stderr.flush()
        _reply(conn, {"exit": int(code)})
        os._exit(int(code) & 0xFF)
