"""The ``sarsp-edu`` command: the paper's experiments from a terminal.

Examples::

    sarsp-edu run --model tp --m 60 --p 0.3 --nss 6 --out results/tp-run
    sarsp-edu compare --episodes 50 --seed 1
    sarsp-edu sweep --jobs 2 --out results/paper
    sarsp-edu tables results/paper
    sarsp-edu info

The command's parser and entry point are in :mod:`~sarsp_edu.cli.main`, its
settings flags and path checks in :mod:`~sarsp_edu.cli.arguments`, what each
command does in :mod:`~sarsp_edu.cli.commands`.
"""

import os
import sys


def _the_command() -> bool:
    """Whether this process is the ``sarsp-edu`` command (its script or ``python -m sarsp_edu.cli``)."""
    return (os.path.basename(sys.argv[0]) == "sarsp-edu"
            or "sarsp_edu.cli" in getattr(sys, "orig_argv", [])[1:3])


try:
    from .arguments import add_config_arguments, config_flags, config_from_args
    from .main import build_parser, main
except KeyboardInterrupt:  # Ctrl-C while the command starts: one line, as at any later moment
    if not _the_command():
        raise
    sys.stderr.write("interrupted: the command had not begun; nothing was written\n")  # main.NOT_BEGUN
    raise SystemExit(130) from None

__all__ = ["add_config_arguments", "build_parser", "config_flags", "config_from_args", "main"]
