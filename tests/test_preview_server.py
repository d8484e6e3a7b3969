"""`scenerender preview` over HTTP, without a browser: only the page, its files and frames
are served; a burst of saves renders at most twice; a scene that fails shows its messages
and the server goes on; Ctrl-C stops it with nothing left behind. The server runs in its
own process on 127.0.0.1 and a free port."""
from __future__ import annotations

import http.client
import json
import socket
import sys
import time
from pathlib import Path
from urllib.parse import urlsplit

import pytest
from click.testing import CliRunner

pytest.importorskip("watchfiles", reason="the preview extra is not installed (pip install 'scenerender[preview]')")

from preview_helpers import FOV_LINE, PreviewProcess, write_paint, write_scene  # noqa: E402

pytestmark = [pytest.mark.gl, pytest.mark.xdist_group("preview")]


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    write_paint(tmp_path)
    write_scene(tmp_path)
    (tmp_path / "secret.txt").write_text("not for the page")
    return tmp_path


@pytest.fixture
def preview(folder: Path):
    running = PreviewProcess(folder / "scene.yaml")
    yield running
    if running.process.poll() is None:
        running.stop()


def raw_get(url: str, path: str) -> int:
    """GET ``path`` sent exactly as written (no client-side normalising of .. or %2e)."""
    parts = urlsplit(url)
    connection = http.client.HTTPConnection(parts.hostname, parts.port, timeout=30)
    try:
        connection.putrequest("GET", path, skip_accept_encoding=True)
        connection.endheaders()
        return connection.getresponse().status
    finally:
        connection.close()


def test_the_page_its_files_and_frames_are_served(preview):
    status, headers, body = preview.get("/")
    assert status == 200 and b"preview.js" in body
    for name in ("preview.js", "preview.css"):
        assert preview.get(f"/static/{name}")[0] == 200
    status, headers, body = preview.get("/frame?frame=3")
    assert status == 200 and headers["content-type"] == "image/png" and body[:8] == b"\x89PNG\r\n\x1a\n"
    camera = json.loads(headers["x-camera"])
    assert camera["yaml"].startswith("camera: {position: [") and camera["fov"] == pytest.approx(50, abs=1e-3)


@pytest.mark.parametrize("path", [
    "/../secret.txt", "/static/../secret.txt", "/static/../server.py", "/static/..%2fserver.py",
    "/static/%2e%2e/server.py", "/static/%2e%2e%2fserver.py", "/%2e%2e/secret.txt", "/static/%2E%2E%2F%2E%2E%2Fcli.py",
    "//etc/passwd", "/static//etc/passwd", "/etc/passwd", "/static/%2fetc%2fpasswd", "/scene.yaml", "/paint.png",
    "/static/__init__.py", "/static/", "/static/preview.js/..", "/static/.%2e/watcher.py",
])
def test_paths_outside_the_served_set_answer_404(preview, path):
    assert raw_get(preview.url, path) == 404


def test_a_burst_of_saves_renders_at_most_twice(preview, folder):
    assert preview.get("/frame?frame=2")[0] == 200
    before = preview.state()
    assert before["renders"] == 1
    for shade in range(10):  # ten saves 10 ms apart, each a different colour
        write_scene(folder, background=(0.1 * shade, 0.2, 0.8))
        time.sleep(0.01)
    state = preview.wait_for_state(lambda s: s["generation"] > before["generation"] and s["renders"] > 1)
    time.sleep(1.5)  # longer than the watcher's grouping: any late render would have started
    state = preview.state()
    assert 1 <= state["renders"] - before["renders"] <= 2, state
    status, headers, _ = preview.get("/frame?frame=2")  # the page's view, already rendered for the last save
    assert status == 200 and int(headers["x-generation"]) == state["generation"]
    assert preview.state()["renders"] == state["renders"]


def test_saving_an_asset_renders_again(preview, folder):
    first = preview.get("/frame?frame=0")[2]
    generation = preview.state()["generation"]
    write_paint(folder, colour=(20, 200, 60))
    preview.wait_for_state(lambda s: s["generation"] > generation and s["renders"] >= 2)
    assert preview.get("/frame?frame=0")[2] != first


def test_a_failing_scene_shows_its_message_and_the_server_goes_on(preview, folder):
    assert preview.get("/frame?frame=0")[0] == 200
    write_scene(folder, fov="500")
    state = preview.wait_for_state(lambda s: s["errors"])
    assert any(f"scene.yaml:{FOV_LINE}" in line and "camera.fov" in line for line in state["errors"]), state
    status, _, body = preview.get("/frame?frame=1")
    assert status == 422 and f"scene.yaml:{FOV_LINE}" in json.loads(body)["errors"][0]
    for query in ("camera=1,2,3,nan,0,0,50", "mode=shaded%0Arender.size%3A%20%5B1%2C1%5D", "frame=-1", "frame=x"):
        assert preview.get(f"/frame?{query}")[0] == 400, query
    write_scene(folder)
    preview.wait_for_state(lambda s: not s["errors"])
    assert preview.get("/frame?frame=1")[0] == 200


def test_without_an_opengl_context_the_page_says_why(folder):
    preview = PreviewProcess(folder / "scene.yaml", env={"SCENERENDER_GL_BACKEND": "no-such-backend"})
    try:
        status, _, body = preview.get("/frame?frame=0")
        assert status == 422 and "cannot create an OpenGL" in json.loads(body)["errors"][0]
        assert "cannot create an OpenGL" in preview.wait_for_state(lambda s: s["errors"])["errors"][0]
        assert preview.get("/")[0] == 200  # the page is still served
    finally:
        code, _, err = preview.stop()
    assert code == 0 and "Traceback" not in err, err


def test_ctrl_c_stops_it_with_nothing_left_behind(preview, folder):
    listing = sorted(path.name for path in folder.iterdir())
    port = urlsplit(preview.url).port
    assert preview.get("/frame?frame=0")[0] == 200
    started = time.monotonic()
    code, out, err = preview.stop()
    assert code == 0, err
    assert time.monotonic() - started < 10
    assert "preview stopped" in out and "Traceback" not in err
    assert sorted(path.name for path in folder.iterdir()) == listing
    with socket.socket() as probe:  # nothing listens there any more (a restart binds it as this does)
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        probe.bind(("127.0.0.1", port))
        probe.listen(1)


def test_ctrl_c_while_the_page_waits_for_news(preview):
    """An open /state poll (the page always has one) does not hold the stop up."""
    parts = urlsplit(preview.url)
    connection = http.client.HTTPConnection(parts.hostname, parts.port, timeout=30)
    connection.request("GET", f"/state?since={preview.state()['version']}")
    time.sleep(0.3)
    started = time.monotonic()
    code, _, err = preview.stop()
    assert code == 0 and "Traceback" not in err and "ERROR" not in err, err
    assert time.monotonic() - started < 5
    connection.close()


def test_without_the_extra_it_says_what_to_install(folder, monkeypatch):
    from scenerender.cli import main

    for name in [name for name in sys.modules if name.startswith("scenerender.preview")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "uvicorn", None)  # as if not installed: importing it raises ImportError
    result = CliRunner().invoke(main, ["preview", str(folder / "scene.yaml"), "--no-open"])
    assert result.exit_code == 3
    assert "pip install 'scenerender[preview]'" in result.stderr


def test_a_taken_port_is_a_one_line_error(folder):
    from scenerender.cli import main

    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen(1)
        port = taken.getsockname()[1]
        result = CliRunner().invoke(main, ["preview", str(folder / "scene.yaml"), "--no-open", "--port", str(port)])
    assert result.exit_code == 2
    assert result.stderr.startswith(f"error: cannot listen on 127.0.0.1:{port}") and "--port 0" in result.stderr
