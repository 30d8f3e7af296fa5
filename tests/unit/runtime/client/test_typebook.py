"""runtime.client.typebook and topics.learn: a type learnt from its descriptions; one name described
two ways decodes each message by the description it fits; a payload that names a known type
and is not one stays skipped, never shown as undescribed."""

from __future__ import annotations

import msgspec

from turtlectl.messages import Message, encode
from turtlectl.messages.described import describe
from turtlectl.runtime.client.samples import Received, decode_sample, learn
from turtlectl.runtime.client.typebook import TypeBook


class Survey(Message, tag="ReviewSurvey"):
    count: int  # -: things counted
    mood: str = "calm"  # -: how it went


class OtherSurvey(Message, tag="ReviewSurvey"):
    count: float  # -: another team's count


def book_of(**by_node: type[Message]) -> TypeBook:
    book = TypeBook(None)  # type: ignore[arg-type]  # no session: the descriptions are handed over
    book.learn("tests/ReviewSurvey", {node: describe(cls) for node, cls in by_node.items()})
    return book


def test_one_name_two_ways_each_message_by_the_description_it_fits():
    book = book_of(surveyor=Survey, mapper=OtherSurvey)
    assert "described 2 ways" in book.conflict("tests/ReviewSurvey")
    encoding = "application/msgpack;tests/ReviewSurvey"
    mine = learn(decode_sample("s/survey", encode(Survey(count=3, mood="busy")), encoding), book)
    theirs = learn(decode_sample("m/survey", encode(OtherSurvey(count=1.5)), encoding), book)
    assert (mine.message.count, mine.message.mood) == (3, "busy")
    assert theirs.message is not None and theirs.message.count == 1.5 and theirs.generic is None


def test_a_payload_naming_a_known_type_that_is_not_one_stays_skipped():
    book = book_of(surveyor=Survey)
    spoof = msgspec.msgpack.encode({"type": "tests/ReviewSurvey", "count": "nope"})
    item = learn(decode_sample("raw/spoof", spoof, "application/msgpack;tests/ReviewSurvey"), book)
    assert item.message is None and item.generic is None and "not a valid" in item.problem


def test_an_undescribed_payload_is_shown_generically():
    book = TypeBook(None)  # type: ignore[arg-type]
    book.asked["NobodysType"] = float("inf")  # asked already: nobody describes it
    data = msgspec.msgpack.encode({"type": "NobodysType", "a": 1})
    item = learn(Received("raw/x", None, "unknown", data, "application/msgpack;NobodysType"), book)
    assert item.generic == {"type": "NobodysType", "a": 1}
