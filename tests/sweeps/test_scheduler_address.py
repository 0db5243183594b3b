"""``sweep --scheduler`` (issue 33): malformed addresses are refused before use, and a server that accepts and
stays silent, answers garbage or announces a 16 TiB frame is refused within the stated timeout, in one line,
without allocating what it announces.  The servers are local sockets run by the test."""

from __future__ import annotations

import re
import socket
import struct
import threading
import time

import pytest

from axles.limits import UsageError
from comparisons.cli.main import main
from comparisons.sweeps import cluster
from comparisons.sweeps.cluster import HANDSHAKE_MAX_BYTES, probe_scheduler, scheduler_address

SWEEP = ["sweep", "--vary", "k1=50000:60000:2", "--pressure", "2"]


@pytest.mark.parametrize("address, fragment", [
    ("tcp://127.0.0.1:abc", "the port must be a whole number"),
    ("udp://127.0.0.1:8786", "the scheme udp:// is not supported"),
    ("tcp://127.0.0.1", "no port"),
    ("127.0.0.1:", "no port"),
    ("inproc://192.168.1.2/123/4", "the scheme inproc:// is not supported"),
    ("", "an empty address"),
    ("   ", "an empty address"),
    ("tcp://127.0.0.1 :8786", "blanks"),
    ("tcp://127.0.0.1:87\n86", "blanks or control characters"),
    ("tls://127.0.0.1:8786", "tls:// needs a TLS security context"),
    ("tcp://127.0.0.1:0", "within [1, 65535]"),
    ("tcp://127.0.0.1:65536", "within [1, 65535]"),
    ("tcp://127.0.0.1:٣", "whole number"),
    ("tcp://-bad-:8786", "not a host name"),
    ("tcp://:8786", "not a host name"),
    ("tcp://[::1:8786", "IPv6"),
])
def test_malformed_addresses_are_one_line_exit_2(capsys, address, fragment):
    with pytest.raises(UsageError, match=re.escape(fragment)):
        scheduler_address(address)
    code = main([*SWEEP, "--scheduler", address])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and fragment in err and "Traceback" not in err


@pytest.mark.parametrize("address, expected", [
    ("tcp://127.0.0.1:8786", "tcp://127.0.0.1:8786"),
    ("  127.0.0.1:8786 ", "tcp://127.0.0.1:8786"),
    ("TCP://scheduler.example.org:1", "tcp://scheduler.example.org:1"),
    ("tcp://[::1]:8786", "tcp://[::1]:8786"),
])
def test_good_addresses_are_normalised(address, expected):
    assert scheduler_address(address)[0] == expected


class Server:
    """A local TCP server that accepts one connection and then does ``behaviour(conn)``."""

    def __init__(self, behaviour):
        self.sock = socket.create_server(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.behaviour = behaviour
        self.done = threading.Event()
        self.thread = threading.Thread(target=self.serve, daemon=True)
        self.thread.start()

    def serve(self):
        conn, _ = self.sock.accept()
        with conn:
            self.behaviour(conn)
            self.done.wait(30)          # keep the connection open (silent) until the test ends

    def close(self):
        self.done.set()
        self.sock.close()


BEHAVIOURS = {
    "accepts and stays silent": (lambda conn: None, "no Dask handshake within"),
    "answers garbage": (lambda conn: conn.sendall(b"HTTP/1.1 400 Bad Request\r\n\r\n"), "not a Dask scheduler"),
    "announces a 16 TiB frame": (lambda conn: conn.sendall(struct.pack("Q", 16 << 40)), "announces 17592186044416"),
    "announces 2**40 frames": (lambda conn: conn.sendall(struct.pack("QQ", 16, 1 << 40) + b"\0" * 8),
                               "not a Dask scheduler"),
    "announces a huge frame inside": (lambda conn: conn.sendall(struct.pack("QQQ", 16, 1, 1 << 44)),
                                      "announces 17592186044416 bytes"),
    "closes at once": (lambda conn: conn.close(), "closed the connection"),
}


@pytest.mark.parametrize("case", list(BEHAVIOURS))
def test_servers_that_are_no_scheduler_are_refused_within_the_timeout(case):
    behaviour, fragment = BEHAVIOURS[case]
    server = Server(behaviour)
    try:
        start = time.monotonic()
        with pytest.raises(UsageError, match=fragment) as err:
            probe_scheduler("127.0.0.1", server.port, "--scheduler x", timeout=1.0)
        assert time.monotonic() - start < 3.0
        assert "\n" not in str(err.value)
    finally:
        server.close()


def test_silent_scheduler_port_ends_the_sweep_command_within_the_timeout(capsys, monkeypatch, tmp_path):
    """The whole command, not only the probe: before, the client waited for the handshake for over 300 s."""
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT_S", 1.0)
    monkeypatch.chdir(tmp_path)
    server = Server(lambda conn: None)
    try:
        start = time.monotonic()
        code = main([*SWEEP, "--scheduler", f"tcp://127.0.0.1:{server.port}"])
        elapsed = time.monotonic() - start
    finally:
        server.close()
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "no Dask handshake within 1 s" in err and elapsed < 10


def test_handshake_limit_is_far_above_a_real_handshake():
    assert HANDSHAKE_MAX_BYTES >= 1 << 16
