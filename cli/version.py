"""This installation's version, from the package metadata (pyproject.toml)."""

from __future__ import annotations


def version() -> str:
    """The installed version of turtlectl, or a hint to install it."""
    import importlib.metadata  # about 30 ms: only for --version

    try:
        return importlib.metadata.version("turtlectl")
    except importlib.metadata.PackageNotFoundError:
        return "unknown (not installed: run `make install`)"
