"""cli.system.certs: a certificate per host, the names a router with --deny-host lets in."""

from __future__ import annotations

import pytest
from cryptography import x509
from cryptography.x509.oid import NameOID

from turtlectl.cli.system import access
from turtlectl.cli.system.certs import (
    CLIENT_COMMON_NAME,
    allowed_common_names,
    hand_credentials,
    host_common_name,
    issue,
    issued_hosts,
    make,
)
from turtlectl.runtime.client.errors import BadInput


def common_name(path) -> str:
    cert = x509.load_pem_x509_certificate(path.read_bytes())
    return cert.subject.get_attributes_for_oid(NameOID.COMMON_NAME)[0].value


def test_a_host_s_certificate_is_its_own_signed_by_the_authority(tmp_path):
    make(tmp_path, [])
    written = issue(tmp_path, "robot7")
    folder = tmp_path / "hosts" / "robot7"
    assert written == [folder / "ca.pem", folder / "client.pem", folder / "client.key"]
    assert common_name(folder / "client.pem") == host_common_name("robot7") != CLIENT_COMMON_NAME
    assert common_name(tmp_path / "client.pem") == CLIENT_COMMON_NAME
    assert (folder / "ca.pem").read_bytes() == (tmp_path / "ca.pem").read_bytes()
    assert (folder / "client.key").stat().st_mode & 0o777 == 0o600
    with pytest.raises(BadInput, match="already"):
        issue(tmp_path, "robot7")  # nothing is overwritten
    assert issued_hosts(tmp_path) == ["robot7"]


def test_issuing_needs_an_authority_and_a_name():
    with pytest.raises(BadInput, match="cannot name a host"):
        issue(__import__("pathlib").Path("/nonexistent"), "a/b")


def test_credentials_go_to_an_issued_host_and_replace_an_earlier_launch_s(tmp_path):
    make(tmp_path, [])
    with pytest.raises(BadInput, match="no certificate"):
        hand_credentials(tmp_path, "robot7", b"{}")
    issue(tmp_path, "robot7")
    hand_credentials(tmp_path, "robot7", b'{"a": 1}')
    path = hand_credentials(tmp_path, "robot7", b'{"b": 2}')
    assert path.read_bytes() == b'{"b": 2}' and path.stat().st_mode & 0o777 == 0o600


def test_the_router_lets_in_the_shared_and_every_issued_host_but_the_denied(tmp_path):
    make(tmp_path, [])
    issue(tmp_path, "robot7")
    issue(tmp_path, "robot8")
    names = allowed_common_names(tmp_path, ["robot8"])
    assert names == [CLIENT_COMMON_NAME, host_common_name("robot7")]
    with pytest.raises(BadInput, match="robot9: no certificate was issued to it"):
        allowed_common_names(tmp_path, ["robot9"])
    rules = access.access_control({"u": {"publish": ("x",)}}, common_names=names)
    assert rules["subjects"] == [{"id": "u", "usernames": ["u"], "cert_common_names": names}]
    assert "cert_common_names" not in access.access_control({"u": {"publish": ("x",)}})["subjects"][0]
