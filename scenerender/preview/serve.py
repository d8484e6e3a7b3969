"""Run a preview until Ctrl-C: bind the address, start the worker and the watcher, serve,
then stop all three and free the GL context, leaving no thread, file or socket behind."""
from __future__ import annotations

import os
import socket
import sys
import webbrowser
from pathlib import Path

import uvicorn

from scenerender.errors import UserError
from scenerender.preview.server import Preview, create_app

# An open /state poll is cut off this long after Ctrl-C instead of running out its wait.
SHUTDOWN_SECONDS = 1


def bind(host: str, port: int) -> socket.socket:
    """A listening socket on ``host``:``port`` (0: a free port); a UserError naming the
    option when the address is taken or not this machine's."""
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
        sock.listen(64)
    except OSError as exc:
        sock.close()
        raise UserError(f"cannot listen on {host}:{port} ({exc.strerror or exc}); choose another --port, "
                        "or --port 0 for a free one") from None
    sock.set_inheritable(True)
    return sock


def page_address(sock: socket.socket) -> str:
    host, port = sock.getsockname()[:2]
    return f"http://[{host}]:{port}/" if ":" in host else f"http://{host}:{port}/"


def can_open_browser() -> bool:
    """A graphical session to open a browser in: on a headless Linux machine (or over SSH)
    Python's webbrowser would start a text browser in this terminal instead."""
    if sys.platform in ("darwin", "win32"):
        return True
    return bool(os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))


class PreviewServer(uvicorn.Server):
    """uvicorn's server, which on Ctrl-C (SIGINT, SIGTERM) also answers the page's open
    polls, so that it stops at once instead of waiting for them or cutting them off."""

    def __init__(self, config: uvicorn.Config, preview: Preview):
        super().__init__(config)
        self.preview = preview

    def handle_exit(self, sig, frame) -> None:
        self.preview.state.close()
        super().handle_exit(sig, frame)


def serve(preview: Preview, sock: socket.socket, echo, open_browser: bool = True) -> None:
    """Serve ``preview`` on ``sock`` until interrupted; ``echo`` prints a line."""
    address = page_address(sock)
    config = uvicorn.Config(create_app(preview), log_level="warning", access_log=False, lifespan="on",
                            timeout_graceful_shutdown=SHUTDOWN_SECONDS)
    server = PreviewServer(config, preview)
    preview.start()
    try:
        echo(f"preview of {preview.scene_path.name}: {address}  (Ctrl-C stops)")
        if open_browser and can_open_browser():
            webbrowser.open(address)
        server.run(sockets=[sock])
    except KeyboardInterrupt:  # uvicorn stops on the signal, then raises it again for the caller
        pass
    finally:
        preview.stop()
        sock.close()
    echo("preview stopped")


def check_folder(path: Path | None) -> Path | None:
    if path is not None and not Path(path).is_dir():
        raise UserError(f"--check {path}: no such folder of reference frames")
    return path
