"""Write the generated tables of the docs again: case keys, mesh formats.

Every key of a case file is declared once, on its config field
(:func:`coastmesh.case.schema.key`), and every mesh format once, in the format
registry. The key tables of ``docs/case-files.md``, the table of renamed keys in
``docs/python-api.md`` and the formats table of ``docs/formats.md`` are written
from them, between markers (``<!-- keys: NAME -->`` ... ``<!-- /keys -->``,
``<!-- formats -->`` ... ``<!-- /formats -->``)::

    python scripts/doc_tables.py          # rewrite the tables
    python scripts/doc_tables.py --check  # exit 1 if a table is out of date

``tests/e2e/test_docs.py`` runs the check.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from coastmesh.case.config import DOCUMENTED, reference_blocks
from coastmesh.case.schema.reference import update_reference
from coastmesh.io import formats_table

DOCS = Path(__file__).resolve().parents[1] / "docs"
PAGES = ("case-files.md", "python-api.md", "formats.md")
FORMATS = re.compile(r"(<!-- formats -->\n).*?(<!-- /formats -->)", re.DOTALL)


def rewritten(text: str) -> str:
    """Return a page's text with its generated tables written anew."""
    text = update_reference(text, DOCUMENTED, reference_blocks())
    return FORMATS.sub(lambda m: m.group(1) + formats_table() + m.group(2), text)


def main() -> int:
    """Rewrite (or check) the key tables of the docs."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="only check them")
    args = parser.parse_args()
    stale = []
    for name in PAGES:
        page = DOCS / name
        text = page.read_text(encoding="utf-8")
        new = rewritten(text)
        if new != text:
            stale.append(name)
            if not args.check:
                page.write_text(new, encoding="utf-8")
    if args.check and stale:
        print(f"out of date: {', '.join(stale)}; run python scripts/doc_tables.py")
        return 1
    print(("rewritten: " if stale else "up to date: ") + ", ".join(stale or PAGES))
    return 0


if __name__ == "__main__":
    sys.exit(main())
