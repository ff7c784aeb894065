"""Start-up time of ``import tentaclass`` and the command line, against ``import numpy``.

Each command runs in a fresh interpreter; the commands are interleaved and each
keeps the minimum of its repeats, so a busy machine slows all of them alike.
The ratio is the command's time over ``python -c "import numpy"`` measured in
the same run. Start-up is single-threaded; the BLAS thread count is pinned to
1 for every child (OPENBLAS/OMP/MKL_NUM_THREADS) so thread-pool creation does
not add noise.

The package's bytecode is cached as on any installation (pip compiles it when
installing; a clone writes ``__pycache__`` on its first run): the children may
write it even where ``PYTHONDONTWRITEBYTECODE`` is set, and a first round of
every command, not timed, writes it. Without it each run compiles the
package's modules from source, which no installed copy does.

Usage: ``python benchmarks/bench_startup.py [repeats]``.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _timing import markdown_table

ROOT = Path(__file__).resolve().parents[1]


def _commands(model: Path) -> dict[str, list[str]]:
    py = [sys.executable]
    cli = [*py, "-m", "tentaclass"]
    angles = "0 0 0 1.5708 0 0 0 1.5708 0 0 0 1.5708 0 0 0 1.5708"
    return {
        'python -c "import numpy"': [*py, "-c", "import numpy"],
        # the floor of any command that builds a scikit-learn estimator
        'python -c "import sklearn.base"': [*py, "-c", "import sklearn.base"],
        # what reading the grasp state costs (tentaclass.wrapping imports the wrap generator)
        'python -c "import tentaclass.wrapping"': [*py, "-c", "import tentaclass.wrapping"],
        "python -c \"import tentaclass\"": [*py, "-c", "import tentaclass"],
        "tentaclass --help": [*cli, "--help"],
        "tentaclass classify (one array, saved model)": [
            *cli, "classify", angles, "--model", str(model)
        ],
        "tentaclass classify (one array, built-in reference)": [*cli, "classify", angles],
    }  # fmt: skip


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + env.get("PYTHONPATH", "")
    for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
        env[var] = "1"
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # bytecode cached, as installed
    return env


def _time(cmd: list[str], env: dict[str, str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, env=env, check=True, stdout=subprocess.DEVNULL)
    return time.perf_counter() - t0


def main(repeats: int = 7) -> None:
    env = _env()
    with tempfile.TemporaryDirectory() as tmp:
        model = Path(tmp) / "model.tcm"
        subprocess.run([sys.executable, "-c", _SAVE_MODEL, str(model)], env=env, check=True)
        commands = _commands(model)
        for cmd in commands.values():  # writes the bytecode caches; not timed
            _time(cmd, env)
        best = dict.fromkeys(commands, float("inf"))
        for _ in range(repeats):  # interleaved: each round runs every command once
            for name, cmd in commands.items():
                best[name] = min(best[name], _time(cmd, env))
    ref = best['python -c "import numpy"']
    rows = [[name, f"{t:.3f}", f"{t / ref:.1f}"] for name, t in best.items()]
    print(f"min of {repeats} interleaved runs, Python {sys.version.split()[0]}")
    print(markdown_table(["command", "time (s)", "ratio to import numpy"], rows))


_SAVE_MODEL = """
import sys
from tentaclass import TentacleClassifier, save_model
from tentaclass.datasets import thesis_tentacle
X, y = thesis_tentacle(16, return_X_y=True)
save_model(TentacleClassifier().fit(X, y), sys.argv[1])
"""

if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 7)
