"""Test session setup: a compile cache of the session's own (subprocesses inherit it), so
tests neither read nor fill the user's ~/.cache/mechdyn."""
import os
import tempfile

os.environ["MECHDYN_CACHE"] = tempfile.mkdtemp(prefix="mechdyn-test-cache-")
