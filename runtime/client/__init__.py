"""The client layer: a running system as a program or a command sees it (``turtlectl.Client``,
``turtlectl.Error`` and what they are built on).

``errors`` says what can go wrong and the exit code of each; ``session`` opens a client
session (its endpoint, domain and login are arguments); ``services`` and ``goals`` call
services and send goals; ``api`` is ``Client``.  The command line (``cli/``) is built on this
layer, never the other way round.  Nothing is imported here, so ``turtlectl.runtime.client.errors``
costs no zenoh.
"""
