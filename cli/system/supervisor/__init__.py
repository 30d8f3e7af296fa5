"""The launch supervisor, split as honcho's: ``process`` (one child and the command it runs),
``supervision`` (the policy: start, respawn, give-up, shutdown; no Zenoh), ``manager`` (the
Zenoh and signal shell around it), ``router`` (opening or joining a router), ``printer``
(prefixed output), ``logs`` (run folders), ``zygote`` (the supervisor's handle on the process
that forks the nodes) and ``zygote_server`` (that process's own loop)."""
