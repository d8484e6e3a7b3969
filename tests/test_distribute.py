"""Rendering on several processes: local workers and a Dask cluster give the same files as
one process; a chunk whose worker dies is retried and no frame is lost or written twice."""
from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from scenerender.cli import main
from scenerender.run.workers import ChunkTask, chunk_tasks, render_chunk

from conftest import SCENES

pytestmark = pytest.mark.gl

SCENE = str(SCENES / "primitives.yaml")
SMALL = ("--size", "64x48", "--samples", "1")


def render(output, *args):
    result = CliRunner().invoke(main, ["render", SCENE, "-o", str(output), *SMALL, "-q", *args])
    assert result.exit_code == 0, result.output
    return output


def frame_bytes(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if not p.name.startswith(".") and p.is_file()}


@pytest.fixture(scope="module")
def single(tmp_path_factory):
    """Frames 0..11 as PNGs and as a GIF, rendered by one process."""
    root = tmp_path_factory.mktemp("single")
    render(root / "png", "--frames", "0:12")
    render(root / "gif", "--frames", "0:12", "--format", "gif")
    return root


def test_chunks_cover_the_frames_in_order():
    base = ChunkTask("s", (), (), None, "f", "png", "{frame}", 90, ())
    chunks = chunk_tasks(base, list(range(10)), workers=2)
    assert [i for c in chunks for i in c.indices] == list(range(10))
    assert len(chunks) == 5 and all(len(c.indices) == 2 and c.scene == "s" for c in chunks)


def test_local_workers_write_the_same_files(single, tmp_path):
    assert frame_bytes(render(tmp_path / "png", "--frames", "0:12", "--workers", "2")) == frame_bytes(single / "png")
    assert (tmp_path / "png" / ".scenerender.json").is_file()
    again = CliRunner().invoke(main, ["render", SCENE, "-o", str(tmp_path / "png"), *SMALL, "--frames", "0:12",
                                      "--workers", "2"])
    assert "nothing to do" in again.stderr  # the manifest vouches for what the workers wrote


def test_local_workers_keep_the_same_object_ids(tmp_path):
    one = render(tmp_path / "one", "--frames", "0:6", "--object-ids")
    two = render(tmp_path / "two", "--frames", "0:6", "--object-ids", "--workers", "2")
    assert frame_bytes(two / ".object_ids") == frame_bytes(one / ".object_ids")
    assert len(frame_bytes(two / ".object_ids")) == 7  # six frames' ids and objects.json
    assert frame_bytes(two / ".object_ids" / "behind") == frame_bytes(one / ".object_ids" / "behind")
    assert len(frame_bytes(two / ".object_ids" / "behind")) == 6
    again = CliRunner().invoke(main, ["render", SCENE, "-o", str(two), *SMALL, "--frames", "0:6", "--object-ids",
                                      "--workers", "2"])
    assert "nothing to do" in again.stderr  # the manifest vouches for the ids the workers wrote


def test_local_workers_make_the_same_video(single, tmp_path):
    render(tmp_path / "gif", "--frames", "0:12", "--format", "gif", "--workers", "2")
    assert frame_bytes(tmp_path / "gif") == frame_bytes(single / "gif")


def test_a_retried_chunk_keeps_the_frames_its_first_try_wrote(single, tmp_path):
    task = ChunkTask(SCENE, ("render.size=[64,48]", "render.samples=1"), (), None, str(tmp_path), "png",
                     "frame_{frame:04d}", 90, (0, 1, 2))
    (tmp_path / "frame_0001.png").write_bytes((single / "png" / "frame_0001.png").read_bytes())
    before = (tmp_path / "frame_0001.png").stat().st_mtime_ns
    result = render_chunk(task)
    assert result.error is None and [i for i, _ in result.written] == [0, 1, 2]
    assert (tmp_path / "frame_0001.png").stat().st_mtime_ns == before  # not written twice
    assert frame_bytes(tmp_path) == {k: v for k, v in frame_bytes(single / "png").items() if "frame_0000" <= k < "frame_0003"}
    # every frame's camera comes back, also the one the first try wrote (the parent writes cameras.json)
    cameras = json.loads((single / "png" / "cameras.json").read_text())["frames"][:3]
    assert [result.cameras[i] == {k: v for k, v in cameras[i].items() if k not in ("file", "scene")}
            for i in range(3)] == [True] * 3


def test_an_unreachable_scheduler_is_a_clear_error(tmp_path, monkeypatch):
    pytest.importorskip("distributed")
    from scenerender.run.workers import DaskWorkers

    monkeypatch.setattr(DaskWorkers, "CONNECT_TIMEOUT", "1s")
    result = CliRunner().invoke(main, ["render", SCENE, "-o", str(tmp_path), *SMALL, "--frames", "0:4",
                                       "--scheduler", "tcp://127.0.0.1:9"])
    assert result.exit_code == 2
    assert "cannot reach the Dask scheduler" in result.stderr


class _DieOnFirstTask:
    """A worker plugin: the first worker to start a chunk dies on the spot (once)."""

    def __init__(self, marker: str):
        self.marker = marker

    def transition(self, key, start, finish, **kwargs):
        if finish == "executing" and not os.path.exists(self.marker):
            Path(self.marker).write_text(str(os.getpid()))
            os._exit(1)


def test_dask_cluster_writes_the_same_files_even_when_a_worker_dies(single, tmp_path):
    distributed = pytest.importorskip("distributed")
    import dask

    class DieOnFirstTask(_DieOnFirstTask, distributed.WorkerPlugin):
        pass

    marker = tmp_path / "killed"
    # Dask's scratch space (and its lock files) inside tmp_path, not the temp folder
    with dask.config.set({"temporary-directory": str(tmp_path / "dask-scratch")}), \
            distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                     dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            client.register_plugin(DieOnFirstTask(str(marker)))
            out = render(tmp_path / "png", "--frames", "0:12", "--scheduler", cluster.scheduler_address)
    assert marker.exists()  # a worker really died mid-run
    assert frame_bytes(out) == frame_bytes(single / "png")
