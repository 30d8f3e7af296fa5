"""``turtlectl certs DIR``: a certificate authority and the certificates a ``launch --secure
--tls DIR`` system uses for mutual TLS (the ``cryptography`` library; pure: files, no zenoh).

Written into DIR (the keys readable by the user only):

* ``ca.pem`` / ``ca.key``: the authority (the key signs the others; keep it where only you
  read it, or delete it once the certificates are made);
* ``router.pem`` / ``router.key``: the router's, valid for the host names and addresses given
  (and localhost, 127.0.0.1);
* ``client.pem`` / ``client.key``: the one the nodes and the client commands show.

Another machine that joins copies ``ca.pem``, ``client.pem`` and ``client.key`` and names the
folder in ``TURTLECTL_TLS``; or, for an identity of its own that the router's rules can tell
apart and shut out (``launch --deny-host``), ``issue`` makes it a folder of its own,
``hosts/NAME/``: ``ca.pem`` and a ``client.pem`` / ``client.key`` whose common name is
``host_common_name(NAME)``, and the system's credentials entry if given.
"""

from __future__ import annotations

import datetime
import ipaddress
import os
from pathlib import Path
from typing import Any

from turtlectl.runtime.client.errors import BadInput

FILES = ("ca.pem", "ca.key", "router.pem", "router.key", "client.pem", "client.key")
VALID_DAYS = 365
CLIENT_COMMON_NAME = "turtlectl client"  # the shared client certificate's (this machine's nodes and tools)
HOSTS = "hosts"  # the folder of DIR that holds each host's own certificate folder


def host_common_name(name: str) -> str:
    """The common name of host ``name``'s certificate: what the router's rules name it by."""
    return f"turtlectl host {name}"


def check_host_name(name: str) -> str:
    """``name`` if it can name a host (letters, digits, ``-``, ``_``, ``.``), else BadInput."""
    if not name or not all(c.isalnum() or c in "-_." for c in name) or name.startswith("."):
        raise BadInput(f"{name!r} cannot name a host: use letters, digits, -, _ and . (robot7, lab-pc.local)")
    return name


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
        CLIENT_COMMON_NAME,
        client_key,
        ca.subject,
        ca_key,
        [(leaf, True), (x509.ExtendedKeyUsage([ExtendedKeyUsageOID.CLIENT_AUTH]), False)],
    )
    _write(folder, "client", client_key, client)
    return [folder / name for name in FILES]


def _load_authority(folder: Path) -> tuple[Any, Any]:
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization

    missing = [name for name in ("ca.pem", "ca.key") if not (folder / name).exists()]
    if missing:
        raise BadInput(
            f"{folder} has no {' or '.join(missing)}: make the authority first (turtlectl certs {folder} --host ADDRESS)"
        )
    ca = x509.load_pem_x509_certificate((folder / "ca.pem").read_bytes())
    key = serialization.load_pem_private_key((folder / "ca.key").read_bytes(), password=None)
    return ca, key


def issue(folder: Path, name: str) -> list[Path]:
    """Host ``name``'s own certificate, signed by the authority in ``folder``, in
    ``folder/hosts/NAME/``: ``ca.pem``, ``client.pem``, ``client.key`` (so ``TURTLECTL_TLS``
    names that folder as it would ``folder``).  BadInput without an authority, for a bad name,
    or if the host has its certificate already (nothing is overwritten)."""
    from cryptography import x509
    from cryptography.hazmat.primitives import serialization
    from cryptography.hazmat.primitives.asymmetric import ec
    from cryptography.x509.oid import ExtendedKeyUsageOID

    check_host_name(name)
    ca, ca_key = _load_authority(folder)
    target = folder / HOSTS / name
    if (target / "client.pem").exists():
        raise BadInput(f"{target} holds host {name}'s certificate already (nothing is overwritten)")
    target.mkdir(parents=True, exist_ok=True, mode=0o700)
    key = ec.generate_private_key(ec.SECP256R1())
    leaf = x509.BasicConstraints(ca=False, path_length=None)
    cert = _certificate(
        host_common_name(name),
        key,
        ca.subject,
        ca_key,
        [(leaf, True), (x509.ExtendedKeyUsage([ExtendedKeyUsageOID.CLIENT_AUTH]), False)],
    )
    _write(target, "client", key, cert)
    (target / "ca.pem").write_bytes(ca.public_bytes(serialization.Encoding.PEM))
    return [target / "ca.pem", target / "client.pem", target / "client.key"]


def hand_credentials(folder: Path, name: str, text: bytes) -> Path:
    """Put ``text`` (a credentials file with a running system's entry) in issued host ``name``'s
    folder as ``credentials.json`` (readable by the user only), replacing the one of an earlier
    launch: each ``launch --secure`` makes new logins.  BadInput if the host has no certificate."""
    target = folder / HOSTS / check_host_name(name)
    if not (target / "client.pem").exists():
        raise BadInput(f"host {name} has no certificate in {folder / HOSTS}: `turtlectl certs {folder} --issue {name}`")
    path = target / "credentials.json"
    temporary = target / ".credentials.json.new"
    fd = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "wb") as out:
        out.write(text)
    os.replace(temporary, path)
    return path


def issued_hosts(folder: Path) -> list[str]:
    """The hosts ``issue`` made a certificate for in ``folder``, by name."""
    hosts = folder / HOSTS
    return sorted(p.name for p in hosts.iterdir() if (p / "client.pem").exists()) if hosts.is_dir() else []


def allowed_common_names(folder: Path, denied: list[str]) -> list[str]:
    """The certificate common names a ``launch --secure --tls folder --deny-host ...`` router lets
    in: the shared client certificate's and every issued host's but the ``denied``.  BadInput for a
    denied name no certificate was issued to (a typo would otherwise shut out no one)."""
    issued = issued_hosts(folder)
    unknown = [name for name in denied if name not in issued]
    if unknown:
        known = ", ".join(issued) or "none"
        raise BadInput(
            f"--deny-host {unknown[0]}: no certificate was issued to it in {folder / HOSTS} (issued: {known}; "
            f"`turtlectl certs {folder} --issue NAME` issues one)"
        )
    return [CLIENT_COMMON_NAME] + [host_common_name(name) for name in issued if name not in denied]
