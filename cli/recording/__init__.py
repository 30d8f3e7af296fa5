"""Recordings: MCAP files read and written (``bag``), ``record``, ``play`` and ``recover``."""
