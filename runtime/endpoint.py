"""Where a turtlectl system is reached, without importing zenoh (pure): the default router
endpoint and the environment variables that choose the endpoint and the domain."""

from __future__ import annotations

import os

DEFAULT_PORT = 7447
DEFAULT_ENDPOINT = f"tcp/127.0.0.1:{DEFAULT_PORT}"
CONNECT_ENV = "TURTLECTL_CONNECT"
DOMAIN_ENV = "TURTLECTL_DOMAIN"


def default_domain() -> str:
    """The domain the environment chooses (``TURTLECTL_DOMAIN``), '' for none."""
    return os.environ.get(DOMAIN_ENV, "")


TLS_ENV = "TURTLECTL_TLS"  # the folder of `turtlectl certs` (ca.pem, client.pem, client.key) for tls/ endpoints


def tls_folder() -> str:
    """The folder with the CA and client certificate for ``tls/`` endpoints ('' if not set)."""
    return os.environ.get(TLS_ENV, "")
