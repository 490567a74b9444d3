"""Test session setup: a compile cache of the session's own (subprocesses inherit it), so
tests neither read nor fill the user's ~/.cache/mechdyn (``MECHDYN_CACHE=off``, as the
mutation runs set it, is kept: no disk cache at all). Registers the hypothesis profile
``mutation`` (no shrinking, no example database) for benchmarks/mutation.py."""
import os
import tempfile

from hypothesis import Phase, settings

if os.environ.get("MECHDYN_CACHE", "").lower() != "off":
    os.environ["MECHDYN_CACHE"] = tempfile.mkdtemp(prefix="mechdyn-test-cache-")

settings.register_profile("mutation", database=None,
                          phases=[Phase.explicit, Phase.reuse, Phase.generate])
