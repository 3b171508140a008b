"""The ``spacearm`` command line: the parser and the dispatch to one module per subcommand.

``inspect`` (``spacearm.cli.inspect``), ``derive`` (``spacearm.cli.derive``), ``analyze``
(``spacearm.cli.analyze``), ``simulate`` and ``demo`` (``spacearm.cli.simulate``),
``campaign`` (``spacearm.cli.campaign``), ``capture`` (``spacearm.cli.capture``),
``plan`` (``spacearm.cli.plan``), ``fmu`` (``spacearm.cli.fmu``) and ``view`` (``spacearm.cli.view``). ``MODEL`` is a preset name (``planar4``,
``spatial6``, ...), a TOML model file (``docs/model-format.md``) or a URDF file
(``docs/urdf.md``), with the model options of ``spacearm.cli.model_options``. Optional packages are
imported only inside the subcommand that needs them, so the command starts on a plain install.
Every error a user can cause is answered with ``spacearm: error: ...`` on stderr and exit status
2, never a traceback: a [`SpacearmError`][spacearm.SpacearmError], and an error of the file system
(a missing or read-only directory, a directory where a file is expected, a full disk), named
with its path. Ctrl-C exits with status 130 and one line.
"""

from __future__ import annotations

import argparse
import functools
import os
import shutil
import sys

from .._core import __version__
from . import analyze as cli_analyze
from . import campaign as cli_campaign
from . import capture as cli_capture
from . import derive as cli_derive
from . import fmu as cli_fmu
from . import inspect as cli_inspect
from . import plan as cli_plan
from . import simulate as cli_simulate
from . import view as cli_view
from .model_options import MODEL_HELP, add_model_arguments, load_model, model_from_args
from .numbers import attach_negative_values
from .._util.atomic import check_writable
from ..errors import SpacearmError

__all__ = ["main", "load_model", "add_model_arguments", "model_from_args", "MODEL_HELP", "describe_os_error"]


#: The options of each subcommand that name a file to write: checked before the command
#: computes anything (``spacearm._util.atomic.check_writable``).
OUTPUT_OPTIONS = {
    "simulate": ("out", "csv", "plot", "animate", "video"),
    "campaign": ("out", "plot"),
    "analyze": ("out",),
    "derive": ("latex", "python", "c"),
    "capture": ("out", "plot", "animate", "video"),
    "plan": ("out", "plot"),
    "fmu": ("out",),
    "view": ("out",),
}


def describe_os_error(exc: OSError) -> str:
    """An ``OSError`` as one line naming the path: ``cannot use 'out/run.csv': No space left on
    device`` (Python's own text repeats the errno and quotes a temporary name)."""
    reason = exc.strerror or str(exc)
    if exc.filename is not None:
        return f"cannot use '{os.fsdecode(exc.filename)}': {reason}"
    return reason


def main(argv=None) -> int:
    # The terminal's width read once: argparse's HelpFormatter asks the terminal at each
    # add_argument (85 times for these parsers, about 12 ms of a capture; benchmarks/README.md).
    formatter = functools.partial(argparse.HelpFormatter, width=shutil.get_terminal_size().columns - 2)
    parser = argparse.ArgumentParser(
        prog="spacearm",
        description="Equations of motion of spacecraft-manipulator systems (GJM formulation).",
        formatter_class=formatter,
    )
    parser.add_argument("--version", action="version", version=f"spacearm {__version__}")
    sub = parser.add_subparsers(dest="command", required=True,
                                parser_class=functools.partial(argparse.ArgumentParser, formatter_class=formatter))
    cli_inspect.add_parser(sub)
    cli_derive.add_parser(sub)
    cli_analyze.add_parser(sub)
    cli_simulate.add_parsers(sub)
    cli_campaign.add_parser(sub)
    cli_capture.add_parser(sub)
    cli_plan.add_parser(sub)
    cli_fmu.add_parser(sub)
    cli_view.add_parser(sub)
    # "--target -0.3,0.3,0" would be read as two options: pass such values as "--target=-0.3,...".
    args = parser.parse_args(attach_negative_values(sys.argv[1:] if argv is None else argv))
    try:
        for option in OUTPUT_OPTIONS.get(args.command, ()):
            if getattr(args, option, None):
                check_writable(getattr(args, option))
        if args.command == "inspect":
            cli_inspect.run(args, model_from_args)
        elif args.command == "derive":
            cli_derive.run(args, model_from_args)
        elif args.command == "analyze":
            cli_analyze.run(args, model_from_args)
        elif args.command in ("simulate", "demo"):
            return cli_simulate.run(args, model_from_args)
        elif args.command == "campaign":
            cli_campaign.run(args, model_from_args)
        elif args.command == "capture":
            return cli_capture.run(args, model_from_args)
        elif args.command == "plan":
            cli_plan.run(args, model_from_args)
        elif args.command == "fmu":
            cli_fmu.run(args, model_from_args)
        elif args.command == "view":
            return cli_view.run(args)
    except SpacearmError as exc:
        print(f"spacearm: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # The reader went away (e.g. `spacearm inspect spatial6 | head`): not an error of ours.
        # Point stdout at devnull so the interpreter's final flush cannot raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except OSError as exc:
        print(f"spacearm: error: {describe_os_error(exc)}", file=sys.stderr)
        return 2
    except MemoryError:
        print("spacearm: error: out of memory (a smaller request: fewer samples, a coarser grid, a smaller model)",
              file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("spacearm: interrupted", file=sys.stderr)
        return 130
    return 0


if __name__ == "__main__":
    sys.exit(main())
