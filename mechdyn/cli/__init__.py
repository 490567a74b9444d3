"""Stage 7, the command line (``mechdyn``): argument parsing, commands, the warm start.
The entry point is :func:`main`.
"""
from mechdyn.cli.command import main

__all__ = ["main"]
