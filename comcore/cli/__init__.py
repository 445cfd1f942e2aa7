"""The ``comcore`` command line: ``comcore estimate | demo | bench`` (and ``--version``).

The user's tools live here: :mod:`comcore.cli.estimate` (the CoM of your own
object from a mask image and a CSV of pushes) and :mod:`comcore.cli.demo` (a
simulated object). ``comcore bench``, the paper's evaluation harness, is
:mod:`comcore.bench.command`. Each subcommand module exposes ``HELP`` (one
line), ``add_arguments(parser)`` and ``run(args) -> int``; they are imported
only when the command line starts, so ``import comcore`` stays light.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys

__all__ = ["SUBCOMMANDS", "build_parser", "main"]

#: Subcommand name -> module (each with ``HELP``, ``add_arguments`` and ``run``).
SUBCOMMANDS = {
    "estimate": "comcore.cli.estimate",
    "demo": "comcore.cli.demo",
    "bench": "comcore.bench.command",
}


def build_parser() -> argparse.ArgumentParser:
    """The argument parser with every subcommand whose module is present."""
    from .. import __version__

    parser = argparse.ArgumentParser(
        prog="comcore", description="Estimate an object's centre of mass by pushing it."
    )
    parser.add_argument("--version", action="version", version=f"comcore {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    for name, module_name in SUBCOMMANDS.items():
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as e:
            if e.name and (e.name == module_name or module_name.startswith(e.name + ".")):
                continue  # subcommand not shipped in this build
            raise
        epilog = getattr(module, "EPILOG", None)  # the statuses and exit codes, where given
        formatter = argparse.RawDescriptionHelpFormatter if epilog else argparse.HelpFormatter
        p = sub.add_parser(
            name,
            help=module.HELP,
            description=module.HELP,
            epilog=epilog,
            formatter_class=formatter,
        )
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv=None) -> int:
    """Entry point of the ``comcore`` script; returns the exit status (130 on Ctrl-C)."""
    args = build_parser().parse_args(argv)
    try:
        return int(args._run(args) or 0)
    except KeyboardInterrupt:
        print(f"comcore {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader left (comcore ... | head): quietly, as Unix tools do
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())  # no second error when Python flushes stdout
        return 141


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
