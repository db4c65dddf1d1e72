"""The ``sarsp-edu`` command."""

from __future__ import annotations

import argparse
import importlib.metadata
import platform
import sys

from ._version import __version__

#: the packages whose versions ``sarsp-edu info`` reports (for bug reports)
_REPORTED = ("numpy", "scipy", "sympy", "matplotlib", "ipywidgets", "gymnasium")


def _info(args) -> int:
    print(f"sarsp_edu {__version__}")
    print(f"python {platform.python_version()} ({sys.executable})")
    for name in _REPORTED:
        try:
            version = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            version = "not installed"
        print(f"{name} {version}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="sarsp-edu",
        description="Safe RL with Gaussian and Student-t processes: the paper's experiments from the command line.",
    )
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    info = sub.add_parser("info", help="print the versions of sarsp_edu and its dependencies")
    info.set_defaults(func=_info)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not hasattr(args, "func"):
        parser.print_help()
        return 0
    return args.func(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
