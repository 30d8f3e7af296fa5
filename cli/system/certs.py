"""``turtlectl certs DIR``: a certificate authority and the certificates a ``launch --secure
--tls DIR`` system uses for mutual TLS (the ``cryptography`` library; pure: files, no zenoh).

Written into DIR (the keys readable by the user only):

* ``ca.pem`` / ``ca.key``: the authority (the key signs the others; keep it where only you
  read it, or delete it once the certificates are made);
* ``router.pem`` / ``router.key``: the router's, valid for the host names and addresses given
  (and localhost, 127.0.0.1);
* ``client.pem`` / ``client.key``: the one the nodes and the client commands show.

Another machine that joins copies ``ca.pem``, ``client.pem`` and ``client.key`` and names the
folder in ``TURTLECTL_TLS``.
"""

from __future__ import annotations

import datetime
import ipaddress
import os
from pathlib import Path
from typing import Any

from turtlectl.cli.errors import BadInput

FILES = ("ca.pem", "ca.key", "router.pem", "router.key", "client.pem", "client.key")
VALID_DAYS = 365


def _write(folder: Path, name: str, key: Any, cert: Any) -> None:
    from cryptography.hazmat.primitives import serialization

    key_path = folder / f"{name}.key"
    fd = os.open(key_path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "wb") as out:
        out.write(
            key.private_bytes(
                serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption()
            )
        )
    (folder / f"{name}.pem").write_bytes(cert.public_bytes(serialization.Encoding.PEM))


def _certificate(subject: str, key: Any, issuer: Any, signer: Any, extensions: list[tuple[Any, bool]]) -> Any:
    from cryptography import x509
    from cryptography.hazmat.primitives import hashes
    from cryptography.x509.oid import NameOID

    now = datetime.datetime.now(datetime.UTC)
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, subject)])
    builder = (
        x509.CertificateBuilder()
        .subject_name(name)
        .issuer_name(issuer or name)
        .public_key(key.public_key())
        .serial_number(x509.random_serial_number())
        .not_valid_before(now - datetime.timedelta(minutes=5))
        .not_valid_after(now + datetime.timedelta(days=VALID_DAYS))
    )
    for extension, critical in extensions:
        builder = builder.add_extension(extension, critical=critical)
    return builder.sign(signer, hashes.SHA256())


def make(folder: Path, hosts: list[str]) -> list[Path]:
    """The authority and the router's and clients' certificates in ``folder``; the router's is
    valid for ``hosts`` (names or addresses) and localhost.  BadInput if ``folder`` holds some
    already (nothing is overwritten).  Returns the files written."""
    from cryptography import x509
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import ExtendedKeyUsageOID

    existing = [name for name in FILES if (folder / name).exists()]
    if existing:
        raise BadInput(f"{folder} already holds {', '.join(existing)}: choose an empty folder (nothing is overwritten)")
    names: list[Any] = []
    for host in [*hosts, "localhost", "127.0.0.1"]:
        try:
            entry: Any = x509.IPAddress(ipaddress.ip_address(host.strip("[]")))
        except ValueError:
            if not host or any(c in host for c in "/: "):
                raise BadInput(f"--host {host!r} is not a host name or an IP address") from None
            entry = x509.DNSName(host)
        if entry not in names:
            names.append(entry)
    folder.mkdir(parents=True, exist_ok=True, mode=0o700)
    ca_key = ec.generate_private_key(ec.SECP256R1())
    usage = x509.KeyUsage(
        digital_signature=True,
        key_cert_sign=True,
        crl_sign=True,
        content_commitment=False,
        key_encipherment=False,
        data_encipherment=False,
        key_agreement=False,
        encipher_only=False,
        decipher_only=False,
    )
    ca = _certificate(
        "turtlectl CA", ca_key, None, ca_key, [(x509.BasicConstraints(ca=True, path_length=0), True), (usage, True)]
    )
    _write(folder, "ca", ca_key, ca)
    leaf = x509.BasicConstraints(ca=False, path_length=None)
    router_key = ec.generate_private_key(ec.SECP256R1())
    router = _certificate(
        "turtlectl router",
        router_key,
        ca.subject,
        ca_key,
        [
            (leaf, True),
            (x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH]), False),
            (x509.SubjectAlternativeName(names), False),
        ],
    )
    _write(folder, "router", router_key, router)
    client_key = ec.generate_private_key(ec.SECP256R1())
    client = _certificate(
        "turtlectl client",
        client_key,
        ca.subject,
        ca_key,
        [(leaf, True), (x509.ExtendedKeyUsage([ExtendedKeyUsageOID.CLIENT_AUTH]), False)],
    )
    _write(folder, "client", client_key, client)
    return [folder / name for name in FILES]
