"""``python -m coastmesh``: the command line."""

from coastmesh.cli.main import main

main()
