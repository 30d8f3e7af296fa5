"""cli.client: keys reached across a domain."""

from cli.client import base_key, domain_prefix


def test_keys_reached_across_a_domain(monkeypatch):
    monkeypatch.delenv("TURTLECTL_DOMAIN", raising=False)
    assert domain_prefix("lab1/navigate_to") == "lab1/" and base_key("lab1/turtle1/cmd_vel") == "turtle1/cmd_vel"
    assert domain_prefix("navigate_to/cancel") == "" and domain_prefix("navigate_to/feedback") == ""
    assert base_key("some/thing") == "some/thing"
    monkeypatch.setenv("TURTLECTL_DOMAIN", "lab1")
    assert domain_prefix("lab1/navigate_to") == ""  # inside a domain keys are used as written
