"""``python -m mechdyn.cli``: the ``mechdyn`` command."""
from mechdyn.cli.command import main

raise SystemExit(main())
