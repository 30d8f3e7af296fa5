"""The Foxglove bridge: the WebSocket server over a live system (``bridge``), the 3D scene it
draws (``scene``, also recorded by ``record --scene``) and the ready-made layout
(``foxglove_layout.json``)."""
