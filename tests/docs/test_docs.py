"""Every code block of README.md and docs/*.md runs; every documented command exists."""

import re

import matplotlib
import pytest
from click.testing import CliRunner

from docs_helpers import markdown_files, run_python_blocks, shell_commands
from tentaclass.cli.main import cli

matplotlib.use("Agg")


@pytest.fixture(autouse=True)
def _in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # blocks that save figures or models write here


# what some guides' code must have computed, beyond running
CHECKS = {
    "manipulator.md": lambda ns: ns["held"].q.shape == (501, 16),
    "wrapping.md": lambda ns: abs(ns["w"].laps - 1.0) < 1e-9 and ns["two"].angles.shape == (2, 16),
}
# trains on thousands of generated wraps
SLOW = {"recognition.md"}


@pytest.mark.parametrize(
    "path",
    [pytest.param(p, marks=pytest.mark.slow) if p.name in SLOW else p for p in markdown_files()],
    ids=lambda p: p.name,
)
def test_python_blocks_run(path):
    import matplotlib.pyplot as plt

    try:
        namespace = run_python_blocks(path, min_blocks=0)
    finally:
        plt.close("all")
    assert CHECKS.get(path.name, lambda ns: True)(namespace)


@pytest.mark.parametrize("path", markdown_files(), ids=lambda p: p.name)
def test_documented_commands_and_options_exist(path):
    runner = CliRunner()
    for args in shell_commands(path):
        if args[0].startswith("-"):  # options of the group itself
            command, help_args = [], ["--help"]
        else:
            command, help_args = [args[0]], [args[0], "--help"]
        result = runner.invoke(cli, help_args)
        assert result.exit_code == 0, f"{path.name}: tentaclass {' '.join(args)}: {result.output}"
        known = set(re.findall(r"(?<![\w-])(--?[a-zA-Z][\w-]*)", result.output))
        for token in args[len(command) :]:
            option = token.split("=", 1)[0]
            if re.match(r"--?[a-zA-Z]", option):
                assert option in known, f"{path.name}: tentaclass {' '.join(args)}: {option}?"
