"""One module per ``shimmy`` command; each has ``add_parser(subparsers)`` and ``run(args) -> exit code``."""
