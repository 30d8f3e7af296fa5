"""``turtlectl verify``: a specification file (``spec``) checked against a running system
(``checks``), reported as one table (``report``)."""
