"""The launch supervisor: ``process`` (one child), ``printer`` (output), ``manager`` (the system)."""
