"""The `restircl` command line: the parser (main.py) from one module per sub-command, the arguments they share
(arguments.py) and progress output (progress.py)."""
