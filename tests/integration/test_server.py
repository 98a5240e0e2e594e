"""The warm server (periodyn.engine.server, ``periodyn serve``): a command runs in a process
forked from the server with the client's streams, folder, environment and exit status;
Ctrl-C reaches it; a killed command is reported; ``periodyn sweep`` through the server
writes the file a sweep run here writes."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

from periodyn.engine import server
from periodyn.results import load

ROOT = Path(__file__).resolve().parents[2]

#: a server whose command is a toy: it prints its argv, folder and one variable, sleeps or dies on request
TOY_SERVER = textwrap.dedent("""
    import json, os, sys, time
    from pathlib import Path
    from periodyn.engine.server import serve

    def command(argv):
        print(json.dumps({"argv": argv, "cwd": os.getcwd(), "value": os.environ.get("TOY_VALUE")}), flush=True)
        print("to stderr", file=sys.stderr, flush=True)
        if argv[:1] == ["sleep"]:
            time.sleep(60)
        if argv[:1] == ["die"]:
            os.kill(os.getpid(), 9)
        return len(argv)

    serve(command, idle=60.0, path=Path(sys.argv[1]), ready=lambda path: print("ready", flush=True))
""")
CLIENT = "import sys; from pathlib import Path; from periodyn.engine.server import delegate; " \
         "code = delegate(sys.argv[2:], Path(sys.argv[1])); sys.exit(99 if code is None else code)"


def _env(**extra) -> dict:
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src"), **extra}
    env.pop("PERIODYN_SERVER", None)  # the suite turns servers off for every other test
    return env


@pytest.fixture
def socket_dir():
    """A short private folder (Unix socket paths are limited to about 100 bytes)."""
    with tempfile.TemporaryDirectory(prefix="pds-", dir="/tmp") as folder:
        os.chmod(folder, 0o700)
        yield Path(folder)


@pytest.fixture
def toy(socket_dir):
    path = socket_dir / "toy.sock"
    process = subprocess.Popen([sys.executable, "-c", TOY_SERVER, str(path)], env=_env(), stdout=subprocess.PIPE,
                               text=True)
    assert process.stdout.readline().strip() == "ready"
    yield path
    server.stop(path)
    process.wait(30)


def _client(path: Path, *argv: str, **kwargs) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", CLIENT, str(path), *argv], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, **kwargs)


def test_a_command_runs_with_the_clients_streams_folder_environment_and_exit_status(toy, tmp_path):
    client = _client(toy, "a", "b c", cwd=tmp_path, env=_env(TOY_VALUE="from the client"))
    out, err = client.communicate(timeout=60)
    assert client.returncode == 2, err  # the command's status: len(argv)
    assert json.loads(out) == {"argv": ["a", "b c"], "cwd": str(tmp_path), "value": "from the client"}
    assert err.strip() == "to stderr"
    state = server.ping(toy)
    assert state is not None and state["pid"] != client.pid


def test_ctrl_c_at_the_client_reaches_the_command(toy):
    client = _client(toy, "sleep", env=_env())
    assert json.loads(client.stdout.readline())["argv"] == ["sleep"]
    client.send_signal(signal.SIGINT)
    client.wait(30)
    assert client.returncode == 130  # KeyboardInterrupt in the command's process


def test_a_killed_command_is_reported_not_taken_for_success(toy):
    client = _client(toy, "die", env=_env())
    out, err = client.communicate(timeout=60)
    assert client.returncode == 1
    assert "ended without an exit status" in err


def test_a_malformed_request_is_dropped_and_the_server_serves_on(toy):
    import socket

    for message in ({"op": "run"}, {"op": "run", "argv": "sweep", "cwd": "/", "env": {}}, {"op": "nonsense"}):
        with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
            sock.connect(str(toy))
            server._request(sock, message, [0, 1, 2])
            assert sock.makefile("rb").readline() == b""  # no reply, the connection closed
    assert server.ping(toy) is not None


def test_without_a_server_the_caller_runs_the_command(socket_dir):
    assert server.delegate(["sweep", "x.toml"], socket_dir / "none.sock") is None
    assert server.ping(socket_dir / "none.sock") is None
    assert server.stop(socket_dir / "none.sock") is False


def test_a_server_is_found_only_by_clients_of_its_code_and_threads(monkeypatch):
    key = server.server_key()
    monkeypatch.setenv("NUMBA_NUM_THREADS", "7")
    assert server.server_key() != key
    monkeypatch.delenv("NUMBA_NUM_THREADS")
    monkeypatch.setenv("PERIODYN_SOMETHING", "1")  # read at run time: the same server serves it
    assert server.server_key() == key


TINY = """
[model]
example = "pendulum"
[sweep]
omega = { start = 0.3, stop = 1.2, num = 12, unit = "omega0" }
harmonics = 5
samples = 24
"""


def test_periodyn_sweep_through_the_server_writes_the_file_a_local_sweep_writes(socket_dir, tmp_path):
    (tmp_path / "tiny.toml").write_text(TINY)
    env = _env(PERIODYN_SERVER_DIR=str(socket_dir))
    cli = [sys.executable, "-m", "periodyn.cli"]
    started = subprocess.run(cli + ["serve", "start", "--idle", "5"], env=env, capture_output=True, text=True,
                             timeout=300)
    assert started.returncode == 0, started.stderr
    try:
        state = subprocess.run(cli + ["serve", "status"], env=env, capture_output=True, text=True, timeout=60)
        assert state.returncode == 0 and "pid" in state.stdout
        served = subprocess.run([sys.executable, "-c", "from periodyn.cli import run; run()", "sweep", "tiny.toml",
                                 "--out", "served.nc", "--workers", "2"],
                                cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
        assert served.returncode == 0, served.stderr
        assert "wrote served.nc" in served.stdout
        here = subprocess.run(cli + ["sweep", "tiny.toml", "--out", "here.nc", "--workers", "2"], cwd=tmp_path,
                              env={**env, "PERIODYN_SERVER": "off"}, capture_output=True, text=True, timeout=300)
        assert here.returncode == 0, here.stderr
        a, b = load(tmp_path / "served.nc"), load(tmp_path / "here.nc")
        assert sorted(a.data_vars) == sorted(b.data_vars)
        for name in a.data_vars:
            np.testing.assert_array_equal(a[name].values, b[name].values, err_msg=name)
        bad = subprocess.run([sys.executable, "-c", "from periodyn.cli import run; run()", "sweep", "missing.toml"],
                             cwd=tmp_path, env=env, capture_output=True, text=True, timeout=60)
        assert bad.returncode == 2 and "no sweep file" in bad.stderr
        deadline = time.monotonic() + 120
        while "pendulum" not in (server.ping(_socket(socket_dir)) or {}).get("learned", []):  # learned once idle
            assert time.monotonic() < deadline, "the server did not load the sweep's kernels after it"
            time.sleep(0.5)
    finally:
        stopped = subprocess.run(cli + ["serve", "stop"], env=env, capture_output=True, text=True, timeout=60)
    assert "stopped" in stopped.stdout
    after = subprocess.run(cli + ["serve", "status"], env=env, capture_output=True, text=True, timeout=60)
    assert after.returncode == 1


def test_serve_refuses_a_missing_file_and_a_bad_idle_time(socket_dir, tmp_path):
    env = _env(PERIODYN_SERVER_DIR=str(socket_dir))
    for args, message in ((["missing.toml"], "is not a sweep file"), (["--idle", "0"], "--idle must be")):
        result = subprocess.run([sys.executable, "-m", "periodyn.cli", "serve", "start", *args], cwd=tmp_path, env=env,
                                capture_output=True, text=True, timeout=60)
        assert result.returncode == 2 and message in result.stderr
    assert not list(socket_dir.glob("*.sock"))


def _socket(folder: Path) -> Path:
    (path,) = folder.glob("*.sock")
    return path


def test_the_server_learns_a_speed_sweeps_kernels_once_and_nothing_from_other_commands(tmp_path, monkeypatch):
    from periodyn.cli import _learn, _preload
    from periodyn.errors import InputError

    monkeypatch.chdir(tmp_path)
    (tmp_path / "tiny.toml").write_text(TINY)
    assert _learn(["sweep", "tiny.toml", "--omega", "0.5:0.6:3"], set()) == "pendulum"
    assert _learn(["sweep", "tiny.toml"], {"pendulum"}) is None  # its family is loaded already
    assert _learn(["info"], set()) is None
    assert _learn(["sweep", "--no-such-option"], set()) is None  # the command itself reports it
    with pytest.raises(InputError):
        _learn(["sweep", "missing.toml"], set())  # the server prints it and goes on (periodyn.engine.server._learn)
    assert not list(tmp_path.glob("*.nc")) and not list(tmp_path.glob("results"))  # learning writes nothing here
    assert _preload([str(tmp_path / "tiny.toml")]) == {"pendulum"}
