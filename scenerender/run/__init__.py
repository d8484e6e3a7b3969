"""The run layer: a scene loaded and rendered into outputs.

``session``: ``Scene``, ``load`` and ``Renderer`` (one GL context), the objects the rest is
built on. ``output``: what ``-o`` means and the sink that writes there. ``plan``: which
frames are due, from ``--frames`` and the run ``manifest``. ``loop``: ``render_into``, the
one frame loop. ``job``: one ``scenerender render`` run, in this process or on ``workers``.
``references``: ``--check`` against reference frames. ``collection``: Python's cycle
collector paused while a render starts.
"""
