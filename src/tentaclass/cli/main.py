"""The ``tentaclass`` command group: options shared by all commands, errors.

Every expected error (bad input, unreadable files) ends as a one-line message
on stderr and exit code 1 (2 for usage errors), never a traceback. A reader
that closes the output early (``tentaclass classify ... | head -1``) ends the
command quietly, as it ends standard Unix tools: exit code 141, nothing printed.
"""

from __future__ import annotations

import importlib
import logging
import os
import sys
import warnings
from typing import Any, NoReturn

import click

from .. import __version__
from ..errors import TentaclassError

#: Command name -> (module in this package, one-line help). A command's module
#: (and the libraries it needs) is imported only when the command runs, so that
#: ``tentaclass --help`` answers at once.
COMMANDS = {
    "bench": ("bench", "Stratified k-fold accuracy of recognition methods on a dataset."),
    "classify": ("classify", "Classify joint-angle arrays with a trained model."),
    "demo": ("demo", "Train on the thesis's four shapes and classify perturbed copies."),
    "grasp": ("grasp", "Close a simulated chain on an object in MuJoCo; print its joint angles."),
    "scan": ("scan", "Classify and inspect objects on a conveyor belt."),
    "serve": ("serve", "Serve the web page: draw a shape, watch a tentacle wrap and name it."),
    "train": ("train", "Train a classifier on labelled joint-angle arrays and save it."),
    "wrap": ("wrap", "Wrap a tentacle around an object and print its joint angles."),
}


class _Group(click.Group):
    """Loads commands on first use; turns library errors into one-line CLI errors."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(set(COMMANDS) | set(self.commands))

    def get_command(self, ctx: click.Context, cmd_name: str) -> click.Command | None:
        if cmd_name not in self.commands and cmd_name in COMMANDS:
            module = importlib.import_module(f".{COMMANDS[cmd_name][0]}", __package__)
            self.add_command(getattr(module, cmd_name), cmd_name)
        return self.commands.get(cmd_name)

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        rows = [(name, COMMANDS[name][1]) for name in sorted(COMMANDS)]
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def parse_args(self, ctx: click.Context, args: list[str]) -> list[str]:
        try:
            return super().parse_args(ctx, args)
        except click.UsageError as exc:
            raise _one_line(exc) from None

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except click.UsageError as exc:
            raise _one_line(exc) from None
        except BrokenPipeError:
            _stop_writing()
        except (TentaclassError, ValueError, OSError) as exc:
            raise click.ClickException(
                str(exc).splitlines()[0] if str(exc) else repr(exc)
            ) from None
        except MemoryError as exc:
            detail = f": {str(exc).splitlines()[0]}" if str(exc) else ""
            raise click.ClickException(
                f"out of memory{detail} (check sizes and counts given as options or in the input)"
            ) from None


#: What click raises to show a command's help when it is given no arguments (click 8.2
#: and later; earlier versions show the help and exit without raising).
_NO_ARGS_IS_HELP = getattr(click.exceptions, "NoArgsIsHelpError", ())


def _one_line(exc: click.UsageError) -> click.UsageError:
    """A usage error shown on one line, naming the command's help (exit code 2).

    Asking for help (a command given no arguments that shows its help then)
    is left as it is.
    """
    if isinstance(exc, _NO_ARGS_IS_HELP):
        return exc
    message = " ".join(exc.format_message().split())
    where = f" (see '{exc.ctx.command_path} -h')" if exc.ctx is not None else ""
    return click.UsageError(message + where)  # without a context: the "Error:" line alone


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="tentaclass")
@click.option("-v", "--verbose", count=True, help="More log output on stderr.")
@click.option("-q", "--quiet", is_flag=True, help="Only errors on stderr.")
@click.pass_context
def cli(ctx: click.Context, verbose: int, quiet: bool) -> None:
    """Recognise objects from one-dimensional data arrays.

    Tentacle case: a planar chain's joint angles -> the object's class.
    """
    configure_logging(verbose, quiet)
    ctx.ensure_object(dict)
    ctx.obj["quiet"] = quiet


def configure_logging(verbose: int, quiet: bool) -> None:
    """Log records of ``-v``/``-q``'s level and above to stderr, whichever logger sends them.

    The level is set on the handler too: libraries that set their own loggers
    to INFO (Dask's ``distributed`` does) would otherwise print every record
    through the root handler (dozens of lines for ``--scheduler local``).
    """
    level = logging.ERROR if quiet else (logging.WARNING - 10 * min(verbose, 2))
    handler = logging.StreamHandler(sys.stderr)
    handler.setLevel(level)
    handler.setFormatter(logging.Formatter("%(levelname)s: %(message)s"))
    logging.basicConfig(level=level, handlers=[handler])


def _warning_line(
    message: Warning | str, category: type[Warning], filename: str, lineno: int,
    file: Any = None, line: str | None = None,
) -> None:  # fmt: skip
    """A warning as one line of stderr, as the errors are (no source line)."""
    from .options import note

    text = " ".join(str(message).split()) or category.__name__
    note(f"warning: {text}")


#: Exit code of a command whose reader closed the pipe (128 + SIGPIPE, as a shell reports it).
EXIT_BROKEN_PIPE = 141


def _stop_writing() -> NoReturn:
    """Stop quietly: the reader of standard output has gone.

    What Python still flushes at exit goes to devnull, and the exit code is
    that of a tool ended by SIGPIPE.
    """
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, sys.stdout.fileno())
    sys.exit(EXIT_BROKEN_PIPE)


def main() -> None:
    """Entry point of the ``tentaclass`` script."""
    warnings.showwarning = _warning_line
    try:
        try:
            cli(prog_name="tentaclass")
        finally:
            sys.stdout.flush()  # output still buffered meets a closed pipe here
    except BrokenPipeError:
        _stop_writing()
