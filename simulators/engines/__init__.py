"""The physics engines a :class:`~simulators.PushSimulator` runs on.

``_quasistatic``: our own quasi-static engine over the exact limit surface
(``_limit_surface``), batched in numpy; ``_pymunk``: the same pushes in pymunk's
dynamics; ``_contact``: the round pusher's contact with a polygon, shared by both.
May import :mod:`simulators`' base modules (``_deps``, ``_settings``) and
:mod:`comcore`'s public names.
"""
