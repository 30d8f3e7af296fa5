"""``python -m turtlectl.cli``: the same as the ``turtlectl`` console script."""

from turtlectl.cli import entry

entry()
