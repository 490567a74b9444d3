"""What a command said on stderr, without mechdyn's announcements of long waits
(``mechdyn.progress.announce``: printed only when a derivation or compilation outlasts
its delay, so their presence depends on the machine's speed and load)."""
import re

_ANNOUNCEMENT = re.compile(r"^mechdyn: .*( \.\.\.|: \d+ s|: done in [\d.]+ s)$")


def said(err: str) -> list:
    """The lines of ``err`` that are not announcements."""
    return [line for line in err.splitlines() if not _ANNOUNCEMENT.match(line)]
