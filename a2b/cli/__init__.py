"""The ``a2b`` command line: a lazy click group and its one error boundary.

Each command lives in its own module, imported only when it runs (or shows its own help), so
``a2b --help`` and ``a2b --version`` import neither numpy nor rich, yaml or mcap.

To add a command ``NAME``: write ``a2b/cli/NAME.py`` defining a click command called
``command`` (thin: parse options, call a reader, one library function, a writer), and add
one line ``"NAME": ("a2b.cli.NAME", "Short help."),`` to :data:`COMMANDS`. Mention it in
README.md; ``tests/test_readme.py`` checks that.
"""

from __future__ import annotations

import importlib
import os
import sys
import warnings

# One BLAS thread: a2b's products are small and blocked, and a second OpenBLAS thread stalls
# badly when another process (the other end of a pipe) holds the other core. An explicit
# setting in the environment wins.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import click

from .. import __version__
from ..errors import A2bError, A2bWarning, OptionError, printable

#: glibc's ``mallopt`` parameters, and the values a command sets (see
#: :func:`_keep_freed_memory`): what glibc's own adaptive thresholds reach at most.
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
_MMAP_THRESHOLD, _TRIM_THRESHOLD = 32 << 20, 64 << 20


def _keep_freed_memory() -> None:
    """Let the C allocator of this process (glibc) keep memory that is freed, up to what its
    own adaptive thresholds reach at most (32 MiB blocks from the heap, 64 MiB free at its
    top), from the start of a command.

    By default glibc maps every block of 128 KiB or more afresh and returns it when freed,
    so the formatter's temporaries of a few MiB were faulted in again for every block of
    text: with the allocator keeping them, 10^6 CSV rows took 0.46 s instead of 0.55 s (0.47 s
    with the code of a727f64). Elsewhere (not Linux, or no glibc), or where the environment
    sets the allocator already (``MALLOC_*_`` or ``GLIBC_TUNABLES``), nothing changes.
    """
    if not sys.platform.startswith("linux") or any(k in os.environ for k in _ALLOCATOR_ENVIRONMENT):
        return
    try:
        import ctypes

        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError, TypeError):  # pragma: no cover - not glibc
        return
    mallopt(_M_MMAP_THRESHOLD, _MMAP_THRESHOLD)
    mallopt(_M_TRIM_THRESHOLD, _TRIM_THRESHOLD)


_ALLOCATOR_ENVIRONMENT = ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "GLIBC_TUNABLES")

#: name -> (module defining ``command``, short help shown by ``a2b --help``)
COMMANDS = {
    "interpolate": (
        "a2b.cli.interpolate",
        "Sample the motion between two poses to CSV, TUM, KITTI, MCAP, ROS 2 or Parquet.",
    ),
    "describe": (
        "a2b.cli.describe",
        "Show the essential parameters of a motion or curve and every choice made.",
    ),
    "fiber": ("a2b.cli.fiber", "Show points of the fiber of a pose under κ or μ_[m]."),
    "batch": (
        "a2b.cli.batch",
        "Sample many motions from a jobs file (CSV, TUM, KITTI, MCAP, ROS 2, Parquet).",
    ),
    "plot": (
        "a2b.cli.plot",
        "Draw a motion or curve: moving frame, trajectories, transmission curve.",
    ),
    "view": (
        "a2b.cli.view",
        "Write an interactive 3D page of a motion, curve or trajectory (one HTML file).",
    ),
    "bezier": ("a2b.cli.bezier", "Sample the Bézier motion of control poses (μ_[m] or κ)."),
    "spline": ("a2b.cli.spline", "Sample a C¹ spline through many key poses."),
    "resample": (
        "a2b.cli.resample",
        "Sample a trajectory (TUM, KITTI, EuRoC, CSV, MCAP) at new times.",
    ),
}

#: numpy's floating-point RuntimeWarnings, e.g. "overflow encountered in multiply".
_NUMPY_FLOAT_WARNINGS = r"(overflow|invalid value|divide by zero|underflow) encountered"

CONTEXT_SETTINGS = {"help_option_names": ["-h", "--help"], "max_content_width": 100}


class LazyGroup(click.Group):
    """A group whose commands are imported on first use, from :data:`COMMANDS`.

    It is also the single error boundary of the program: an :class:`a2b.A2bError` (bad input,
    a parameter without a solution, a singular motion, an output that cannot be written)
    becomes a one-line message and exit status 1. Any other exception is a bug and keeps its
    traceback. A closed output pipe (``a2b ... | head``) ends the program quietly with status 0.
    numpy's floating-point warnings (overflow, invalid value) are not shown: the commands
    check their results and refuse non-finite ones with an error of their own. An
    :class:`a2b.errors.A2bWarning` (a result sensitive to rounding) is one line on stderr,
    ``Warning: ...``, and the run goes on.
    """

    def list_commands(self, ctx):
        return list(COMMANDS)

    def get_command(self, ctx, name):
        if name not in COMMANDS:
            return None
        return importlib.import_module(COMMANDS[name][0]).command

    def format_commands(self, ctx, formatter):
        rows = [(name, help_) for name, (_, help_) in COMMANDS.items()]
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def main(self, *args, **kwargs):
        try:
            return super().main(*args, **kwargs)
        except OSError as e:  # printing the help or the version (the commands: see invoke)
            from ..io.atomic import silence_stdout

            silence_stdout()
            click.echo(f"Error: cannot write standard output: {e.strerror or e}", err=True)
            sys.exit(1)

    def invoke(self, ctx):
        _keep_freed_memory()
        try:
            with warnings.catch_warnings():
                warnings.filterwarnings("ignore", _NUMPY_FLOAT_WARNINGS, RuntimeWarning)
                warnings.showwarning = _show_warning
                return super().invoke(ctx)
        except OptionError as e:  # an option that does not apply: a usage error, status 2
            raise click.UsageError(printable(str(e))) from e
        except A2bError as e:
            raise click.ClickException(printable(str(e))) from e
        except click.ClickException as e:  # usage errors quote what the user typed
            e.message = printable(e.message)
            raise
        except BrokenPipeError:
            from ..io.atomic import silence_stdout

            silence_stdout()
            ctx.exit(0)
        except OSError as e:  # reading failed (EIO, a vanished network file): no bug of a2b's
            what = e.filename if e.filename is not None else "an input file"
            message = f"cannot read {what}: {e.strerror or e}"
            raise click.ClickException(printable(message)) from e


_python_showwarning = warnings.showwarning


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """``Warning: message`` for a2b's own warnings; Python's format for any other."""
    if issubclass(category, A2bWarning):
        click.echo(f"Warning: {printable(str(message))}", err=True)
    else:
        _python_showwarning(message, category, filename, lineno, file, line)


@click.group(cls=LazyGroup, context_settings=CONTEXT_SETTINGS)
@click.version_option(
    __version__, "-V", "--version", prog_name="a2b", message="%(prog)s %(version)s"
)
def cli():
    """Interpolate two rigid-body poses: vertical Darboux motions, cubic circular motions and
    screw motions (H.-P. Schröcker, From A to B: New Methods to Interpolate Two Poses).

    Poses come from JSON or YAML files, trajectories from TUM, KITTI, EuRoC, CSV, MCAP files
    or ROS 2 bags; samples go to CSV, TUM, KITTI, MCAP (Foxglove or ROS 2), ROS 2 bags or
    Parquet.

    \b
    Example:
        a2b interpolate samples/quarter-turn.yaml --samples 5
        a2b interpolate samples/quarter-turn.yaml --format mcap -o turn.mcap
        a2b describe samples/quarter-turn.yaml
        a2b resample samples/reference.tum --rate 100 -o dense.tum

    \b
    Shell completion (bash; zsh and fish likewise with zsh_source, fish_source):
        eval "$(_A2B_COMPLETE=bash_source a2b)"
    """
