"""``import tentaclass`` and the command line's start stay light; lazy names resolve."""

import importlib
import subprocess
import sys

import pytest

HEAVY = ("sklearn", "matplotlib", "scipy.stats", "pandas")


def _loaded_after(code: str) -> set[str]:
    probe = f"{code}\nimport sys\nprint(' '.join(m for m in {HEAVY!r} if m in sys.modules))"
    out = subprocess.run(
        [sys.executable, "-c", probe], capture_output=True, text=True, check=True
    ).stdout
    return set(out.split())


@pytest.mark.parametrize(
    "code",
    [
        "import tentaclass",
        "import tentaclass.cli.main",
        "from tentaclass.features import fourier_features",
        "import tentaclass.plot",
        "from tentaclass.cli.main import cli\ncli.get_help(__import__('click').Context(cli))",
    ],
)
def test_light_imports_do_not_load_sklearn_or_matplotlib(code):
    assert _loaded_after(code) == set()


@pytest.mark.parametrize(
    "package", ["tentaclass", "tentaclass.classifiers", "tentaclass.features", "tentaclass.plot"]
)
def test_every_public_name_resolves(package):
    module = importlib.import_module(package)
    for name in module.__all__:
        assert getattr(module, name) is not None
        assert name in dir(module)
    with pytest.raises(AttributeError, match="no_such_name"):
        module.no_such_name  # noqa: B018


def test_every_command_loads_and_is_listed():
    import click

    from tentaclass.cli.main import COMMANDS, cli

    ctx = click.Context(cli)
    assert cli.list_commands(ctx) == sorted(COMMANDS)
    for name in COMMANDS:
        assert isinstance(cli.get_command(ctx, name), click.Command)
    assert cli.get_command(ctx, "no-such-command") is None


@pytest.mark.parametrize("rows", [100, 20_000])
def test_fourier_features_do_not_load_numba(rows):
    """numba (about 50 MiB) stays out of the processes, Dask workers' among them."""
    code = (
        "import numpy as np\n"
        "from threadpoolctl import threadpool_limits\n"
        "from tentaclass.features import fourier_features\n"
        "with threadpool_limits(2, user_api='blas'):\n"
        f"    fourier_features(np.tile([0, 0, 0, np.pi / 2], ({rows}, 16)))\n"
        "import sys\n"
        "print('numba' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_reading_a_model_file_imports_only_the_classes_it_names(tmp_path):
    from tentaclass.classifiers import PNNClassifier
    from tentaclass.io import save_model

    path = save_model(PNNClassifier().fit([[0.0], [1.0]], [0, 1]), tmp_path / "m.tcm")
    code = f"from tentaclass.io import load_model\nload_model({str(path)!r})"
    probe = (
        f"{code}\nimport sys\n"
        "print(' '.join(m for m in ('sklearn.linear_model', 'sklearn.neural_network', "
        "'tentaclass.scanner', 'tentaclass.wrapping', 'numba') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.split() == []
