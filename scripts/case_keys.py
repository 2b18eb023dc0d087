"""Write the key tables of the docs again from the config classes' keys.

Every key of a case file is declared once, on its config field
(:func:`coastmesh.case.schema.key`). The tables of ``docs/case-files.md`` and the
table of renamed keys in ``docs/python-api.md`` are written from those
declarations, between ``<!-- keys: NAME -->`` and ``<!-- /keys -->`` markers::

    python scripts/case_keys.py          # rewrite the tables
    python scripts/case_keys.py --check  # exit 1 if a table is out of date

``tests/e2e/test_docs.py`` runs the check.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from coastmesh.case.config import DOCUMENTED
from coastmesh.case.schema.reference import update_reference

DOCS = Path(__file__).resolve().parents[1] / "docs"
PAGES = ("case-files.md", "python-api.md")


def main() -> int:
    """Rewrite (or check) the key tables of the docs."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only check them")
    args = parser.parse_args()
    stale = []
    for name in PAGES:
        page = DOCS / name
        text = page.read_text(encoding="utf-8")
        new = update_reference(text, DOCUMENTED)
        if new != text:
            stale.append(name)
            if not args.check:
                page.write_text(new, encoding="utf-8")
    if args.check and stale:
        print(f"out of date: {', '.join(stale)}; run python scripts/case_keys.py")
        return 1
    print(("rewritten: " if stale else "up to date: ") + ", ".join(stale or PAGES))
    return 0


if __name__ == "__main__":
    sys.exit(main())
