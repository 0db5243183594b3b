"""``python -m comparisons.cli``: the ``shimmy`` command."""

from comparisons.cli.main import entry

entry()
