"""The client tools' logic, which never prints: sessions (``client``), services and goals
(``services``), topics (``topics``, ``rates``, ``graph``), messages from JSON (``build``) and as
text (``format``), parameters (``params``), node and topic info (``introspect``), message types
(``interface``), and the terminal tools (``view``; ``teleop`` over ``keyboard``)."""
