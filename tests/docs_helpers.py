"""Run the code in README.md and the user guides under docs/."""

import doctest
import re
import shlex
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def markdown_files() -> list[Path]:
    """README.md and every docs/*.md."""
    return [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]


def fenced_blocks(path: Path, languages: tuple[str, ...]) -> list[str]:
    """The bodies of the fenced blocks of ``path`` in one of ``languages``."""
    pattern = r"^```(" + "|".join(languages) + r")\n(.*?)^```"
    return [m[1] for m in re.findall(pattern, path.read_text(), flags=re.DOTALL | re.M)]


def run_python_blocks(name: str | Path, min_blocks: int = 1) -> dict:
    """Execute every ```python block of docs/<name> in one namespace; return it.

    A block written as an interactive session (``>>>`` prompts) is run as a
    doctest, its outputs compared; any other block is executed as a script.
    """
    path = name if isinstance(name, Path) else DOCS / name
    blocks = fenced_blocks(path, ("python", "pycon"))
    assert len(blocks) >= min_blocks, f"{path} has {len(blocks)} python blocks"
    namespace: dict = {"__name__": "__docs__"}
    parser = doctest.DocTestParser()
    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    for i, block in enumerate(blocks):
        if re.search(r"^\s*>>> ", block, flags=re.M):
            test = parser.get_doctest(block, namespace, f"{path.name}[{i}]", str(path), 0)
            runner = doctest.DocTestRunner(optionflags=flags)
            runner.run(test, clear_globs=False)
            namespace.update(test.globs)  # DocTest ran on a copy
            assert runner.failures == 0, f"{path}, block {i}: {runner.failures} example(s) failed"
        else:
            exec(compile(block, f"{path}[{i}]", "exec"), namespace)
    return namespace


def shell_commands(path: Path) -> list[list[str]]:
    """Each ``tentaclass ...`` command of the shell blocks of ``path``, as arguments."""
    out = []
    for block in fenced_blocks(path, ("sh", "bash", "console", "shell")):
        text = block.replace("\\\n", " ")
        for line in text.splitlines():
            line = line.strip().removeprefix("$ ")
            if line.startswith("python -m tentaclass"):
                line = line.replace("python -m tentaclass", "tentaclass", 1)
            for part in line.split("|"):  # each command of a pipe
                part = part.strip()
                if part.startswith("tentaclass "):
                    out.append(shlex.split(part, comments=True)[1:])
    return out
