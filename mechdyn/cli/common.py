"""What the ``mechdyn`` commands share: a command's parser (its help laid out as every
command's: a line for the list of commands, a description, then the examples and notes as
written) and the exit status after a run that may have failed in part.

>>> import argparse
>>> commands = argparse.ArgumentParser(prog="mechdyn").add_subparsers()
>>> spin = command_parser(commands, "spin", "spin a disc", "Spin a disc for a while.",
...                       ["mechdyn spin models/disc.py"], ["exit status 1 if it stops"])
>>> print(spin.epilog)
example:
  mechdyn spin models/disc.py
<BLANKLINE>
exit status 1 if it stops
"""
from __future__ import annotations

import argparse
import sys

from mechdyn.cli.arguments import EXIT_FAILED, EXIT_OK

__all__ = ["command_parser", "exit_status"]


def command_parser(commands, name, summary, description, examples, notes=()):
    """A subparser of ``commands``: ``summary`` in the command list, ``description`` on
    top of its help, ``examples`` (command lines) and ``notes`` (lines) below."""
    heading = "example:" if len(examples) == 1 else "examples:"
    epilog = "\n".join([heading, *(f"  {line}" for line in examples)])
    if notes:
        epilog += "\n\n" + "\n".join(notes)
    return commands.add_parser(name, help=summary, description=description, epilog=epilog,
                               formatter_class=argparse.RawDescriptionHelpFormatter)


def exit_status(failure) -> int:
    """``EXIT_FAILED`` after saying what failed on stderr, or ``EXIT_OK`` (no ``failure``)."""
    if failure:
        print(f"mechdyn: {failure}", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK
