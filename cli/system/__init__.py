"""The launch side: launch files (``launchfile``, the packaged ``launch.toml``), the supervisor
that runs them (``supervisor/``), and what ``--secure`` needs (``access`` rules, ``credentials``,
``certs``)."""
