"""``python -m coastmesh``: the command line."""

from coastmesh.cli.main import main

if __name__ == "__main__":
    raise SystemExit(main())
