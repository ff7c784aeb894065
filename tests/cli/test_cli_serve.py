import re
import subprocess
import sys

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
    result = CliRunner().invoke(cli, ["serve"])
    assert result.exit_code == 1
    assert result.output.strip().endswith("pip install 'tentaclass[web]'")
    assert "Traceback" not in result.output
