"""runtime.client.session: keys reached across a domain."""

from turtlectl.runtime.client.session import base_key, domain_prefix


def test_keys_reached_across_a_domain(monkeypatch):
    monkeypatch.delenv("TURTLECTL_DOMAIN", raising=False)
    assert domain_prefix("lab1/navigate_to") == "lab1/" and base_key("lab1/turtle1/cmd_vel") == "turtle1/cmd_vel"
    assert domain_prefix("navigate_to/cancel") == "" and domain_prefix("navigate_to/feedback") == ""
    assert base_key("some/thing") == "some/thing"
    monkeypatch.setenv("TURTLECTL_DOMAIN", "lab1")
    assert domain_prefix("lab1/navigate_to") == ""  # inside a domain keys are used as written


def test_a_refused_client_is_told_where_its_login_was_looked_for(monkeypatch, tmp_path):
    """With TURTLECTL_CREDENTIALS naming a missing file the message says the file named is not
    there (not "(or set TURTLECTL_CREDENTIALS)")."""
    from turtlectl.runtime.client.session import _not_let_in

    monkeypatch.delenv("TURTLECTL_TLS", raising=False)
    monkeypatch.setenv("HOME", str(tmp_path))
    monkeypatch.delenv("TURTLECTL_CREDENTIALS", raising=False)
    default = _not_let_in("tcp/127.0.0.1:7447", False)
    assert f"{tmp_path}/.turtlectl/credentials.json has none for tcp/127.0.0.1:7447 (or set TURTLECTL_CREDENTIALS)" in (
        default
    )
    missing = tmp_path / "none.json"
    monkeypatch.setenv("TURTLECTL_CREDENTIALS", str(missing))
    text = _not_let_in("tcp/127.0.0.1:7447", False)
    assert f"TURTLECTL_CREDENTIALS names {missing}, which does not exist" in text and "or set" not in text, text
    missing.write_text("{}")
    text = _not_let_in("tcp/127.0.0.1:7447", False)
    assert f"{missing} (TURTLECTL_CREDENTIALS) has none for tcp/127.0.0.1:7447" in text and "or set" not in text, text
