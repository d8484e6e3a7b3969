"""``scenerender preview``: a local page that shows a scene while it is written.

The page (``static/``) asks the server (``server.py``) for frames; one worker thread
(``worker.py``) owns the only OpenGL context and renders one view at a time, the newest
asked for; a watcher thread (``watcher.py``) sees the scene file and every asset it read
saved and has the last view rendered again. Only the command line imports this package.
"""
