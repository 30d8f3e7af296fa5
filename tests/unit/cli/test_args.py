"""cli.args: checks of what users type, pure (each returns the value to use or raises BadInput)."""

from __future__ import annotations

import pytest

from turtlectl.cli import args
from turtlectl.runtime.client import checks
from turtlectl.runtime.client.errors import BadInput


@pytest.mark.parametrize("text, value", [("1", 1.0), ("-2.5", -2.5), ("1e3", 1000.0), (" 7 ", 7.0)])
def test_finite_numbers(text, value):
    assert args.finite_number(text, "x") == value


@pytest.mark.parametrize("text", ["nan", "inf", "-Infinity", "1e999"])
def test_infinite_or_nan_is_refused(text):
    with pytest.raises(BadInput, match=f"x must be a finite number, got {text!r}"):
        args.finite_number(text, "x")


@pytest.mark.parametrize("text", ["north", "1_0", "", "0x10"])
def test_text_is_not_a_number(text):
    with pytest.raises(BadInput, match="theta must be a number"):
        args.finite_number(text, "theta")


@pytest.mark.parametrize("name", ["", "lab1", "42", "a-b_c"])
def test_domains(name):
    assert args.domain(name) == name


@pytest.mark.parametrize("name", ["a/b", "a b", "*", "lab1/", "é"])
def test_a_domain_is_one_key_chunk(name):
    with pytest.raises(BadInput, match="use letters, digits, _ and -"):
        args.domain(name)


@pytest.mark.parametrize("text", ["tcp/127.0.0.1:7447", "tcp/[::1]:7447", "tcp/robot.local:1", "udp/10.0.0.1:65535"])
def test_endpoints(text):
    assert checks.endpoint(text) == text


@pytest.mark.parametrize("text", ["tcp/127.0.0.1", "tcp/127.0.0.1:abc", "tcp/h:0", "tcp/h:99999", "127.0.0.1:7447"])
def test_an_endpoint_is_protocol_host_port(text):
    with pytest.raises(BadInput, match="write it as tcp/HOST:PORT"):
        checks.endpoint(text)


@pytest.mark.parametrize("text, host", [("127.0.0.1", "127.0.0.1"), ("0.0.0.0", "0.0.0.0"), ("::1", "[::1]")])
def test_listen_addresses_are_written_as_an_endpoint_writes_them(text, host):
    assert args.listen_address(text) == host


def test_listen_takes_an_ip_address_not_a_name():
    with pytest.raises(BadInput, match="--listen 'localhost' is not an IP address"):
        args.listen_address("localhost")


def test_echo_limit_and_formats():
    assert args.echo_limit(False, None) is None and args.echo_limit(True, None) == 1 and args.echo_limit(False, 3) == 3
    with pytest.raises(BadInput, match="--once and --count"):
        args.echo_limit(True, 3)
    args.one_format(True, False)
    with pytest.raises(BadInput, match="--json and --csv"):
        args.one_format(True, True)


@pytest.mark.parametrize(
    "once, rate, times, count",
    [(False, None, None, 1), (True, None, None, 1), (False, 5.0, None, None), (False, 5.0, 3, 3), (False, None, 3, 3)],
)
def test_publish_count(once, rate, times, count):
    assert args.publish_count(once, rate, times) == count


@pytest.mark.parametrize("rate, times", [(5.0, None), (None, 2), (5.0, 2)])
def test_publish_once_goes_alone(rate, times):
    with pytest.raises(BadInput, match="--once does not go with --rate or --times"):
        args.publish_count(True, rate, times)


def test_certs_make_an_authority_and_certificates_it_signed(tmp_path):
    """`turtlectl certs DIR`; the keys readable by their owner only; nothing overwritten."""
    import stat

    from cryptography import x509

    from turtlectl.cli.system.certs import FILES, make

    written = make(tmp_path / "tls", ["10.0.0.5", "robot.local"])
    assert [p.name for p in written] == list(FILES)
    assert all(stat.S_IMODE(p.stat().st_mode) == 0o600 for p in written if p.suffix == ".key")
    ca = x509.load_pem_x509_certificate((tmp_path / "tls" / "ca.pem").read_bytes())
    router = x509.load_pem_x509_certificate((tmp_path / "tls" / "router.pem").read_bytes())
    router.verify_directly_issued_by(ca)
    names = router.extensions.get_extension_for_class(x509.SubjectAlternativeName).value
    assert "robot.local" in names.get_values_for_type(x509.DNSName) and "localhost" in names.get_values_for_type(
        x509.DNSName
    )
    assert {str(ip) for ip in names.get_values_for_type(x509.IPAddress)} == {"10.0.0.5", "127.0.0.1"}
    with pytest.raises(BadInput, match="already holds ca.pem"):
        make(tmp_path / "tls", [])
    with pytest.raises(BadInput, match="is not a host name or an IP address"):
        make(tmp_path / "other", ["a/b"])
