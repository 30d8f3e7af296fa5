"""What every generator of a reference page shares: write the page, or (``--check``) say
whether the committed page is what the code renders now (the unit tests run the check)."""

from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from pathlib import Path


def main(output: Path, render: Callable[[], str], argv: Sequence[str], script: str) -> int:
    """Write ``render()`` to ``output``; with ``--check`` in ``argv``, write nothing and exit 1
    (naming ``script``, the generator to run) if the committed page differs."""
    text = render()
    if "--check" in argv:
        if output.read_text() != text:
            print(f"{output} is out of date: run python docs/{script}", file=sys.stderr)
            return 1
        return 0
    output.write_text(text)
    print(f"wrote {output}")
    return 0
