"""The ``turtlectl`` command line: launch supervisor and client tools."""
