"""The groups of ``turtlectl`` commands, one module each, in the order of ``turtlectl --help``:
``system`` (launch, router, run, log-level, certs), ``driving`` (goto, cancel, teleport, reset,
teleop), ``topics`` (echo, hz, pub, topic), ``services`` (call), ``parameters`` (param),
``introspection`` (list, node, interface, view) and ``recording`` (record, info, play, recover,
foxglove); ``options`` holds what several share.  Each module's ``register(app)`` adds its
commands to cli.main's app.

A group module imports at module level only what its commands' signatures need (typer, the
shared options, errors); the logic and its heavy imports are loaded inside each command.
"""
