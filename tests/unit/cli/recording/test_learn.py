"""record learns a type turtlectl was not built with before writing its sample; the
name in a raw payload's encoding can be anything, and only a name a node could describe is
asked about (``a//b`` would make an invalid key expression: a Zenoh error would end the recorder)."""

from __future__ import annotations

from turtlectl.cli.recording.record import learn


class FakeBook:
    def __init__(self):
        self.asked: list[str] = []

    def resolve(self, name: str):
        self.asked.append(name)
        return None


def test_an_unknown_type_is_asked_about_and_a_known_or_foreign_one_is_not():
    book = FakeBook()
    for encoding in (
        "application/msgpack;someone/ElsesType",
        "application/msgpack;turtlectl/Pose",  # a built-in
        "application/json",
        "text/plain;WallState",
        "application/msgpack",
    ):
        learn(book, encoding)  # type: ignore[arg-type]
    assert book.asked == ["someone/ElsesType"]


def test_a_name_no_node_could_describe_is_not_asked_about():
    book = FakeBook()
    for name in ("a//b", "a/b/c", "Bare", "a*b", "**", "a$b", "a?b", "a#b", "@x", ""):
        learn(book, f"application/msgpack;{name}")  # type: ignore[arg-type]
    assert book.asked == []
