"""``python -m cli``: the same as the ``turtlectl`` console script."""

from cli import entry

entry()
