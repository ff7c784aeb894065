import re
import socket
import subprocess
import sys

import click
import pytest
from click.testing import CliRunner

from tentaclass.cli.main import cli


def test_serve_help_names_host_and_port():
    result = CliRunner().invoke(cli, ["serve", "--help"], catch_exceptions=False)
    assert result.exit_code == 0
    assert "--host" in result.output and "--port" in result.output
    assert "127.0.0.1" in result.output


def test_serve_bad_port_is_one_line():
    result = CliRunner().invoke(cli, ["serve", "--port", "70000"])
    assert result.exit_code == 2
    assert "Traceback" not in result.output


def one_line_error(result):
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert result.exit_code == 1, result.output
    assert len(lines) == 1 and lines[0].startswith("Error: "), result.output
    return lines[0]


@pytest.mark.parametrize(
    "host, message, code",
    [
        # a malformed address is a usage error, as --port 70000 is (both were exit code 1)
        ("999.1.1.1", "--host '999.1.1.1' is not an IPv4 address", 2),
        ("300", "--host '300' is not an IPv4 address", 2),  # not 0.0.1.44
        ("", "--host is empty", 2),
        ("[]", "--host is empty", 2),
        ("no.such.host.invalid", "--host 'no.such.host.invalid': no such host", 1),
    ],
)
def test_serve_bad_host_is_one_line(host, message, code):
    result = CliRunner().invoke(cli, ["serve", "--host", host, "--port", "0"])
    lines = [line for line in result.output.splitlines() if line.strip()]
    assert result.exit_code == code, result.output
    assert len(lines) == 1 and lines[0].startswith("Error: "), result.output
    assert message in lines[0]
    assert lines[0].endswith("serve -h')") == (code == 2)  # usage errors name the help


def test_serve_on_a_port_in_use_is_one_line():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        result = CliRunner().invoke(cli, ["serve", "--port", str(port)])
    line = one_line_error(result)
    assert f"cannot listen on 127.0.0.1:{port}" in line
    assert "choose another --port, or 0 for a free one" in line


def test_listening_socket_takes_ipv6_in_brackets():
    from tentaclass.cli.serve import listening_socket

    if not socket.has_ipv6:
        pytest.skip("no IPv6")
    try:
        sock = listening_socket("[::1]", 0)
    except click.ClickException as exc:  # an IPv6 stack without a loopback address
        pytest.skip(str(exc))
    with sock:
        assert sock.family == socket.AF_INET6 and sock.getsockname()[0] == "::1"


def test_serve_prints_its_address_and_answers(tmp_path):
    httpx = pytest.importorskip("httpx")
    pytest.importorskip("uvicorn")
    cmd = [sys.executable, "-m", "tentaclass", "serve", "--port", "0", "--data-dir", str(tmp_path)]
    with open(tmp_path / "err.log", "w") as err:
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=err, text=True)
    try:
        line = proc.stdout.readline()
        match = re.fullmatch(
            r"tentaclass serving on http://127\.0\.0\.1:(\d+)/ \(API docs at /docs\)\n", line
        )
        assert match, (line, (tmp_path / "err.log").read_text()[-2000:])
        base = f"http://127.0.0.1:{match.group(1)}"
        body = httpx.get(base + "/api/classes", timeout=30).json()
        assert len(body["classes"]) == 9
        r = httpx.post(base + "/api/classify", json={"stroke": [[0, 0]]}, timeout=30)
        assert r.status_code == 400  # and the server is still there:
        assert httpx.get(base + "/", timeout=30).status_code == 200
    finally:
        proc.terminate()
        proc.wait(timeout=30)
        proc.stdout.close()


def test_serve_without_the_web_extra_says_how_to_get_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "uvicorn", None)  # import uvicorn -> ImportError
    result = CliRunner().invoke(cli, ["serve", "--port", "0"])
    assert result.exit_code == 1
    assert result.output.strip().endswith("pip install 'tentaclass[web]'")
    assert "Traceback" not in result.output
