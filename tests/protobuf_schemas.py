"""Reading Foxglove's well-known messages (protobuf) back in tests, from the schemas they carry."""

from __future__ import annotations

from google.protobuf import descriptor_pb2, descriptor_pool, message_factory


def protobuf_class(descriptors: bytes, name: str):
    """The message class ``name`` from a FileDescriptorSet (a Foxglove well-known schema)."""
    files = descriptor_pb2.FileDescriptorSet.FromString(descriptors)
    pool = descriptor_pool.DescriptorPool()
    for file in files.file:
        pool.Add(file)
    return message_factory.GetMessageClass(pool.FindMessageTypeByName(name))


def decoded(message):
    """A foxglove.messages object (opaque: Rust) as its protobuf message, fields readable."""
    schema = type(message).get_schema()
    return protobuf_class(schema.data, schema.name).FromString(message.encode())
