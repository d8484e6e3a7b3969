"""Faults on the output side: signals, killed runs, full and read-only disks, ffmpeg
failures, file modes, what ``-o`` means, and output names that try to leave ``-o``.

Every case ends the same way: exit 2 (or 128 + signal) with one line naming the path, and
no partial file left behind. Tests marked ``gl`` render tiny frames.
"""
from __future__ import annotations

import errno
import os
import re
import signal
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from conftest import skip_without_gl
from scenerender.cli import main
from scenerender.errors import EnvironmentProblem, UserError, display_path
from scenerender.run.interrupts import Interrupted, signals_as_exceptions
from scenerender.run.output import resolve_output
from scenerender.sinks.names import name_template_problem
from scenerender.sinks import ImageSequenceSink, SingleImageSink, ThreadedSink, VideoSink, remove_stale_partials
from scenerender.sinks import base as base_module
from scenerender.sinks import images as images_module
from scenerender.sinks import video as video_module
from scenerender.sinks.video import container_is_whole

from test_sinks import H, W, Frame  # the sinks' synthetic frames

LAUNCHER = Path(__file__).with_name("fault_launcher.py")
ANIMATED = ("render: {size: [32, 24], samples: 1}\n"
            "output: {frames: 12, fps: 12}\n"
            "objects:\n"
            "  - mesh: {primitive: box}\n"
            "    rotation: {keys: [[0, [0, 0, 0]], [1, [30, 180, 0]]]}\n")


def frame(index: int = 0) -> Frame:
    pixels = np.random.default_rng(index).integers(0, 256, (H, W, 3), dtype=np.uint8)
    return Frame(index, pixels, pixels.astype(np.float32) / 255.0)


def partials(folder: Path) -> list[str]:
    return sorted(name for name in os.listdir(folder) if ".partial" in name) if folder.exists() else []


def outputs(folder: Path) -> list[str]:
    """The files a user sees in ``folder``: everything but the run manifest."""
    return sorted(n for n in os.listdir(folder) if not n.endswith(".scenerender.json")) if folder.exists() else []


@pytest.fixture
def scene(tmp_path, monkeypatch):
    """tmp_path as working folder, with anim.yaml (12 animated frames) in it."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "anim.yaml").write_text(ANIMATED, encoding="utf-8")
    return tmp_path


def cli(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def render_ok(*args):
    result = cli("render", *args, "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 0, result.output
    return result


def launch(*args, cwd: Path, **env) -> subprocess.Popen:
    """``scenerender`` in a child process, frame writes slowed or stalled (fault_launcher)."""
    return subprocess.Popen([sys.executable, str(LAUNCHER), *map(str, args)], cwd=cwd, text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            env={**os.environ, **{k: str(v) for k, v in env.items()}})


def wait_for(condition, process: subprocess.Popen, what: str, timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while not condition():
        if process.poll() is not None:
            out, err = process.communicate()
            skip_without_gl(process.returncode, err)
            pytest.fail(f"the render ended (exit {process.returncode}) before {what}: {err}")
        if time.monotonic() > deadline:
            process.kill()
            pytest.fail(f"timed out waiting for {what}")
        time.sleep(0.01)


# ---------------------------------------------------------------------------------------
# signals: a real render process, stopped mid-render, then resumed


@pytest.mark.gl
@pytest.mark.parametrize("signum, code, name", [(signal.SIGTERM, 143, "SIGTERM"), (signal.SIGHUP, 129, "SIGHUP")])
def test_signal_mid_render_then_resume_gives_identical_frames(scene, signum, code, name):
    render_ok("anim.yaml", "-o", "reference")
    reference = {p.name: p.read_bytes() for p in (scene / "reference").glob("*.png")}
    assert len(reference) == 12

    process = launch("render", "anim.yaml", "-o", "out", "-q", cwd=scene, FAULT_WRITE_DELAY=0.1)
    wait_for(lambda: (scene / "out" / "frame_0000.png").exists(), process, "the first frame was written")
    process.send_signal(signum)
    _, err = process.communicate(timeout=60)
    assert process.returncode == code, err
    assert err.strip().splitlines() == [
        f"error: interrupted by {name}; frames already finished are complete, nothing partial was left"]
    assert partials(scene / "out") == []
    done = [n for n in outputs(scene / "out") if n != "cameras.json"]
    assert 1 <= len(done) < 12  # stopped mid-render
    for name_ in done:
        assert (scene / "out" / name_).read_bytes() == reference[name_]

    resumed = cli("render", "anim.yaml", "-o", "out")
    assert resumed.exit_code == 0, resumed.output
    assert f"rendered {12 - len(done)} frames" in resumed.stderr
    assert outputs(scene / "out") == sorted([*reference, "cameras.json"])
    for name_, data in reference.items():
        assert (scene / "out" / name_).read_bytes() == data
    # the frames' cameras too: the stopped run's and the resumed run's together
    assert (scene / "out" / "cameras.json").read_bytes() == (scene / "reference" / "cameras.json").read_bytes()


@pytest.mark.gl
def test_sigterm_during_mp4_removes_the_temporary_video(scene):
    process = launch("render", "anim.yaml", "-o", "out", "--format", "mp4", "-q", cwd=scene, FAULT_WRITE_DELAY=0.1)
    # the video's own temporary file: the run manifest is written through one too, briefly
    video_partials = (lambda: [name for name in partials(scene / "out") if name.endswith(".mp4")])
    wait_for(video_partials, process, "the video's temporary file appeared")
    temp = video_partials()[0]
    time.sleep(0.2)  # a frame or two into ffmpeg
    process.send_signal(signal.SIGTERM)
    _, err = process.communicate(timeout=60)
    assert process.returncode == 143, err
    assert "interrupted by SIGTERM" in err and "Traceback" not in err
    assert outputs(scene / "out") == []
    if Path("/proc/self/cmdline").exists():
        assert _processes_naming(temp) == []  # ffmpeg was stopped, not orphaned


@pytest.mark.gl
def test_sigkill_leaves_a_partial_the_next_run_removes(scene):
    process = launch("render", "anim.yaml", "-o", "out", "-q", cwd=scene, FAULT_HANG_AT=2)
    stalled = (lambda: any(n.startswith(".frame_0002.png.") for n in partials(scene / "out")))
    wait_for(stalled, process, "frame 2's temporary file appeared")
    process.kill()
    process.communicate(timeout=60)
    left = partials(scene / "out")
    assert len(left) == 1 and left[0].startswith(".frame_0002.png.")

    render_ok("anim.yaml", "-o", "out")
    assert partials(scene / "out") == []
    assert outputs(scene / "out") == ["cameras.json"] + [f"frame_{i:04d}.png" for i in range(12)]


def _processes_naming(text: str) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if text.encode() in (entry / "cmdline").read_bytes():
                    found.append(int(entry.name))
            except OSError:
                continue
    return found


@pytest.mark.gl
@pytest.mark.skipif(not Path("/proc/self/cmdline").exists(), reason="needs /proc to see the orphaned ffmpeg")
def test_sigkill_during_mp4_leaves_a_partial_the_next_run_removes(scene):
    process = launch("render", "anim.yaml", "-o", "out", "--format", "mp4", "-q", cwd=scene, FAULT_WRITE_DELAY=0.1)
    # the video's own temporary file: the run manifest is written through one too, briefly
    video_partials = (lambda: [name for name in partials(scene / "out") if name.endswith(".mp4")])
    wait_for(video_partials, process, "the video's temporary file appeared")
    temp = video_partials()[0]
    process.kill()
    process.communicate(timeout=60)
    deadline = time.monotonic() + 30  # the orphaned ffmpeg sees end of input and finishes
    while _processes_naming(temp) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert partials(scene / "out") == [temp]

    render_ok("anim.yaml", "-o", "out", "--format", "mp4")
    assert outputs(scene / "out") == ["anim.mp4", "anim.mp4.cameras.json"]


def test_stale_partials_removed_only_when_ours_and_dead(tmp_path):
    finished = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True)
    dead = int(finished.stdout)
    names = {
        f".frame_0001.png.{dead}-0123abcd.partial.png": True,        # a killed run's frame
        f".shot.mp4.{dead}-89abcdef.partial.mp4": True,              # a killed run's video
        ".frame_0002.png.k2_9xq1z.partial.png": True,                # earlier versions' names
        ".shot.mp4.partial.mp4": True,
        f".frame_0003.png.{os.getpid()}-0123abcd.partial.png": False,  # a live run's
        f".frame_0004.png.{os.getppid()}-0123abcd.partial.png": False,
        ".notes.partial.png": False,                                 # not our pattern
        "frame_0001.png.partial.png": False,
        ".my.holiday1.partial.png": False,
        "frame_0000.png": False,
    }
    for name in names:
        (tmp_path / name).write_bytes(b"x")
    removed = remove_stale_partials(tmp_path)
    assert sorted(p.name for p in removed) == sorted(n for n, stale in names.items() if stale)
    assert sorted(os.listdir(tmp_path)) == sorted(n for n, stale in names.items() if not stale)
    assert remove_stale_partials(tmp_path / "missing") == []


def test_signals_become_exceptions_only_inside_the_block():
    before = signal.getsignal(signal.SIGTERM)
    with pytest.raises(Interrupted) as info:
        with signals_as_exceptions():
            os.kill(os.getpid(), signal.SIGTERM)
            time.sleep(5)  # the handler raises before this ends
    assert info.value.exit_code == 143 and info.value.signal_name == "SIGTERM"
    assert isinstance(info.value, KeyboardInterrupt)  # cleans up wherever Ctrl-C does
    assert signal.getsignal(signal.SIGTERM) is before


def test_ignored_signals_stay_ignored():
    """Under nohup SIGHUP is ignored: a render must not turn it into an exit."""
    previous = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    try:
        with signals_as_exceptions():
            assert signal.getsignal(signal.SIGHUP) is signal.SIG_IGN
            os.kill(os.getpid(), signal.SIGHUP)
            time.sleep(0.05)
    finally:
        signal.signal(signal.SIGHUP, previous)


def test_threaded_sink_abort_drops_queued_frames():
    """An interrupt should not wait for (or write) frames still in the queue."""
    gate = threading.Event()
    written = []

    class Slow:
        needs_linear = False

        def write(self, f):
            gate.wait(5)
            written.append(f.index)

        def abort(self):
            pass

    sink = ThreadedSink(Slow(), depth=3)
    for i in range(4):
        sink.write(frame(i))
    gate.set()
    sink.abort()
    assert written == [0]
    assert not sink._thread.is_alive()


# ---------------------------------------------------------------------------------------
# full, read-only and forbidden output folders


def enospc_half_write(path, data):
    """What a full disk does: part of the file lands, then the write fails."""
    with open(path, "wb") as handle:
        handle.write(bytes(data)[: len(data) // 2])
    raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))


@pytest.mark.gl
@pytest.mark.parametrize("fmt", ["png", "exr"])
def test_full_disk_while_writing_a_frame(scene, monkeypatch, fmt):
    monkeypatch.setattr(images_module, "write_file", enospc_half_write)
    result = cli("render", "anim.yaml", "-o", "out", "--format", fmt, "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 2, result.output
    assert result.stderr.strip().splitlines() == [
        f"error: out/frame_0000.{fmt}: cannot write: no space left on device (free some space or write "
        "elsewhere with -o)"]
    assert outputs(scene / "out") == []


@pytest.mark.gl
@pytest.mark.parametrize("code, cause", [(errno.EROFS, "read-only file system"), (errno.EACCES, "permission denied"),
                                         (errno.EDQUOT, "disk quota exceeded")])
def test_rename_refused(scene, monkeypatch, code, cause):
    """Root ignores chmod 0555, so the refusal is injected where the file is renamed into place."""
    real_replace = os.replace

    def refusing_replace(src, dst, **kwargs):
        if os.fspath(src).endswith(".partial.png"):  # a frame's temporary file
            raise OSError(code, os.strerror(code), os.fspath(src), os.fspath(dst))
        return real_replace(src, dst, **kwargs)

    monkeypatch.setattr(os, "replace", refusing_replace)
    result = cli("render", "anim.yaml", "-o", "out", "--frames", "0:2", "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 2, result.output
    line, = result.stderr.strip().splitlines()
    assert line.startswith("error: out/frame_0000.png: cannot write: " + cause)
    assert outputs(scene / "out") == []


def test_folder_cannot_be_created(tmp_path, monkeypatch):
    def refusing_mkdir(path, *args, **kwargs):
        raise PermissionError(errno.EACCES, os.strerror(errno.EACCES), os.fspath(path))

    monkeypatch.setattr(os, "mkdir", refusing_mkdir)
    sink = ImageSequenceSink(tmp_path / "a" / "b", "png", "f_{frame}")
    with pytest.raises(UserError, match=r"cannot write: permission denied \(no permission to write there"):
        sink.write(frame())


@pytest.mark.parametrize("fmt", ["png", "jpg", "tga", "exr"])
def test_full_disk_errors_for_every_encoder(tmp_path, monkeypatch, fmt):
    """Every encoder's bytes go through one write that reports the errno (OpenEXR writing
    a file itself says nothing on a full disk)."""
    monkeypatch.setattr(images_module, "write_file", enospc_half_write)
    sink = ImageSequenceSink(tmp_path, fmt, "f_{frame}")
    with pytest.raises(UserError, match="no space left on device"):
        sink.write(frame())
    assert os.listdir(tmp_path) == []


def test_dev_full_is_a_full_disk(tmp_path):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full on this system")
    with pytest.raises(OSError) as info:
        base_module.write_file(Path("/dev/full"), b"x" * 100_000)
    assert info.value.errno == errno.ENOSPC


def test_writer_thread_errors_keep_their_class(tmp_path, monkeypatch):
    monkeypatch.setattr(images_module, "write_file", enospc_half_write)
    sink = ThreadedSink(ImageSequenceSink(tmp_path, "png", "f_{frame}"))
    sink.write(frame(0))
    with pytest.raises(UserError, match="no space left"):
        sink.close()
    assert os.listdir(tmp_path) == []


# ---------------------------------------------------------------------------------------
# ffmpeg failures


def fake_ffmpeg(tmp_path, monkeypatch, script: str) -> None:
    """Make VideoSink run ``script`` (sh) instead of ffmpeg; the output path is its last argument."""
    exe = tmp_path / "fake-ffmpeg"
    exe.write_text("#!/bin/sh\nfor last; do :; done\n" + script)
    exe.chmod(0o755)
    monkeypatch.setattr(video_module, "ffmpeg_exe", lambda: str(exe))


@pytest.mark.parametrize("script, error, message", [
    # the disk fills up while ffmpeg muxes: it says so and exits 228 (-ENOSPC)
    ("cat > \"$last\"\necho 'Error writing trailer: No space left on device' >&2\nexit 228\n",
     UserError, "v.mp4: cannot write: no space left on device"),
    ("cat > /dev/null\necho 'Could not open file : Read-only file system' >&2\nexit 1\n",
     UserError, "v.mp4: cannot write: read-only file system"),
    # exit 0 although writing the trailer failed (seen in older ffmpeg versions)
    ("cat > \"$last\"\necho 'Error writing trailer: Disk quota exceeded' >&2\nexit 0\n",
     UserError, "v.mp4: cannot write: disk quota exceeded"),
    ("cat > /dev/null\necho 'Unknown encoder libx264' >&2\nexit 1\n",
     EnvironmentProblem, "ffmpeg failed (exit status 1): Unknown encoder libx264"),
    # exit 0 but the file is not a whole MP4 (no 'moov'): never renamed into place
    ("cat > /dev/null\nprintf '\\000\\000\\000\\010mdat' > \"$last\"\nexit 0\n",
     EnvironmentProblem, "is incomplete"),
])
def test_failed_ffmpeg_leaves_no_video(tmp_path, monkeypatch, script, error, message):
    fake_ffmpeg(tmp_path, monkeypatch, script)
    out = tmp_path / "out"
    sink = VideoSink(out / "v.mp4", "mp4", fps=10, size=(W, H))
    with pytest.raises(error, match=re.escape(message)):
        for i in range(5):
            sink.write(frame(i))
        sink.close()
    assert os.listdir(out) == []


def test_ffmpeg_dying_early_is_not_a_broken_pipe(tmp_path, monkeypatch):
    """A BrokenPipeError would reach the CLI's "output piped into head" path and exit 0."""
    fake_ffmpeg(tmp_path, monkeypatch, "echo 'No space left on device' >&2\nexit 228\n")
    sink = VideoSink(tmp_path / "v.mp4", "mp4", fps=10, size=(256, 256))
    with pytest.raises(UserError, match="no space left on device"):
        for i in range(50):  # more than a pipe buffer
            sink.write(Frame(i, np.zeros((256, 256, 3), np.uint8), None))
        sink.close()
    assert os.listdir(tmp_path) == ["fake-ffmpeg"]


@pytest.mark.gl
def test_full_disk_during_mp4_render(scene, monkeypatch):
    fake_ffmpeg(scene, monkeypatch,
                "cat > \"$last\"\necho 'av_interleaved_write_frame(): No space left on device' >&2\nexit 228\n")
    result = cli("render", "anim.yaml", "-o", "out", "--format", "mp4", "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 2, result.output
    assert result.stderr.strip().splitlines() == [
        "error: out/anim.mp4: cannot write: no space left on device (free some space or write elsewhere with -o)"]
    assert outputs(scene / "out") == []
    again = cli("render", "anim.yaml", "-o", "out", "--format", "mp4", "-q")  # nothing was taken as done
    assert again.exit_code == 2


def test_container_check():
    assert not container_is_whole(Path("/nonexistent.mp4"), "mp4")


def test_real_mp4_and_gif_pass_the_container_check(tmp_path):
    for fmt in ("mp4", "gif"):
        sink = VideoSink(tmp_path / f"v.{fmt}", fmt, fps=10, size=(W, H))
        for i in range(3):
            sink.write(frame(i))
        sink.close()
        assert sink.is_complete()
        data = (tmp_path / f"v.{fmt}").read_bytes()
        (tmp_path / f"cut.{fmt}").write_bytes(data[: len(data) * 2 // 3])
        assert not VideoSink(tmp_path / f"cut.{fmt}", fmt, fps=10, size=(W, H)).is_complete()


# ---------------------------------------------------------------------------------------
# a real full and a real read-only file system (tmpfs; needs permission to mount)


@pytest.fixture
def tmpfs(tmp_path):
    """mount(options) -> a fresh tmpfs folder; skipped where mounting is not permitted."""
    mounted = []

    def mount(options: str) -> Path:
        target = tmp_path / f"fs{len(mounted)}"
        target.mkdir()
        result = subprocess.run(["mount", "-t", "tmpfs", "-o", options, "tmpfs", str(target)],
                                capture_output=True, text=True)
        if result.returncode != 0:
            pytest.skip(f"cannot mount a tmpfs here (needs root outside a restricted container): "
                        f"{result.stderr.strip()}")
        mounted.append(target)
        return target

    yield mount
    for target in mounted:
        subprocess.run(["umount", "-l", str(target)], capture_output=True)


def fill(folder: Path) -> None:
    """Write until the file system is full."""
    with pytest.raises(OSError) as info:
        with open(folder / "filler", "wb", buffering=0) as handle:
            while True:
                handle.write(b"\0" * 4096)
    assert info.value.errno == errno.ENOSPC


@pytest.mark.gl
@pytest.mark.parametrize("fmt", ["png", "mp4"])
def test_really_full_tmpfs(scene, tmpfs, fmt):
    disk = tmpfs("size=64k")
    fill(disk)
    result = cli("render", "anim.yaml", "-o", disk / "out", "--format", fmt, "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 2, result.output
    line, = result.stderr.strip().splitlines()
    assert line.startswith(f"error: {display_path(disk / 'out')}/") and "cannot write: no space left on device" in line
    assert outputs(disk / "out") == []


@pytest.mark.gl
def test_really_read_only_tmpfs(scene, tmpfs):
    disk = tmpfs("size=64k,ro")
    result = cli("render", "anim.yaml", "-o", disk / "out", "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 2, result.output
    line, = result.stderr.strip().splitlines()
    assert line == (f"error: {display_path(disk / 'out')}: cannot write: read-only file system (the file system "
                    "is read-only; write elsewhere with -o)")
    assert not (disk / "out").exists()


# ---------------------------------------------------------------------------------------
# destinations no file can be written to: every command, every output option

needs_proc = pytest.mark.skipif(not Path("/proc/self").is_dir(), reason="needs /proc, which takes no new files")


@pytest.mark.parametrize("final, named", [("afile/x.json", "afile"), ("afile/sub/x.json", "afile/sub"),
                                          ("folder", "folder")])
def test_atomic_path_names_the_obstacle_and_the_option(scene, final, named):
    """mkdir says EEXIST for a file standing where the last folder should be: that is the
    same mistake as one further up, not a bug."""
    (scene / "afile").write_text("mine")
    (scene / "folder").mkdir()
    with pytest.raises(UserError) as info:
        with base_module.atomic_path(Path(final), "--report") as temp:
            temp.write_text("{}")
    assert str(info.value).startswith(f"{named}: cannot write: ")
    assert str(info.value).endswith("write elsewhere with --report)")
    assert (scene / "afile").read_text() == "mine" and os.listdir(scene / "folder") == []


@needs_proc
def test_a_folder_that_takes_no_new_files(tmp_path):
    with pytest.raises(UserError) as info:
        with base_module.atomic_path(Path("/proc/x.json")) as temp:
            temp.write_text("{}")
    assert str(info.value) == ("/proc/x.json: cannot write: no such file or directory (the folder it would go in "
                               "does not take new files; write elsewhere with -o)")


@needs_proc
def test_render_into_proc_is_exit_2_before_rendering(scene):
    result = cli("render", "anim.yaml", "-o", "/proc/scenerender-out", "-q")
    assert result.exit_code == 2, result.output
    assert result.stderr == ("error: /proc/scenerender-out: cannot write: no such file or directory (the folder it "
                             "would go in does not take new files; write elsewhere with -o)\n")


@pytest.mark.gl
@needs_proc
@pytest.mark.parametrize("output", ["/proc/x.mp4", "/proc/x.png"])
def test_render_a_file_into_proc(scene, output):
    result = cli("render", "anim.yaml", "-o", output, "--frames", "0", "-q")
    skip_without_gl(result.exit_code, result.stderr)
    assert result.exit_code == 2, result.output
    line, = result.stderr.splitlines()
    assert line.startswith("error: /proc/") and line.endswith("write elsewhere with -o)"), line


@needs_proc
def test_reference_into_proc(scene):
    result = cli("reference", "anim.yaml", "-o", "/proc/scenerender-ref", "--size", "8x6", "--spp", "1")
    assert result.exit_code == 2, result.output
    assert result.stderr.splitlines()[-1].startswith("error: /proc/scenerender-ref")
    assert "internal error" not in result.stderr


# ---------------------------------------------------------------------------------------
# file modes follow the umask


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o077, 0o600), (0o002, 0o664)])
@pytest.mark.parametrize("fmt", ["png", "exr", "mp4"])
def test_output_modes_follow_the_umask(tmp_path, umask, mode, fmt):
    previous = os.umask(umask)
    try:
        if fmt == "mp4":
            sink = VideoSink(tmp_path / "v.mp4", "mp4", fps=10, size=(W, H))
            sink.write(frame())
            sink.close()
            path = sink.path
        else:
            sink = ImageSequenceSink(tmp_path, fmt, "f_{frame}")
            sink.write(frame())
            path = sink.path_for(0)
    finally:
        os.umask(previous)
    assert stat.S_IMODE(path.stat().st_mode) == mode


# ---------------------------------------------------------------------------------------
# what -o means


@pytest.mark.parametrize("output, fmt, explicit, frames, kind, target_fmt, file", [
    ("still.png", "png", False, 1, "image", "png", "still.png"),
    ("still.jpeg", "png", False, 1, "image", "jpg", "still.jpeg"),    # the suffix decides...
    ("still.JPG", "jpg", True, 1, "image", "jpg", "still.JPG"),       # ...and may agree with --format
    ("still.exr", "png", False, 1, "image", "exr", "still.exr"),
    ("still.tga", "png", False, 1, "image", "tga", "still.tga"),
    ("clip.mp4", "png", False, 30, "video", "mp4", "clip.mp4"),
    ("clip.gif", "gif", True, 30, "video", "gif", "clip.gif"),
    ("out", "png", False, 30, "sequence", "png", None),
    ("out.d", "png", False, 30, "sequence", "png", None),
    ("out", "mp4", True, 30, "video", "mp4", "out/shot.mp4"),
])
def test_resolve_output(tmp_path, output, fmt, explicit, frames, kind, target_fmt, file):
    target = resolve_output(tmp_path / output, fmt, explicit, frames, "shot")
    assert (target.kind, target.fmt) == (kind, target_fmt)
    assert target.file == (tmp_path / file if file else None)
    assert target.folder == (tmp_path / output if kind == "sequence" or output == "out" else tmp_path)


@pytest.mark.parametrize("output, fmt, explicit, frames, message", [
    ("still.png", "png", False, 12, "still.png names one image but the render has 12 frames"),
    ("still.png", "jpg", True, 1, "still.png ends in .png, which means png, but --format or output.format says jpg"),
    ("clip.mp4", "gif", True, 12, "clip.mp4 ends in .mp4, which means mp4, but --format or output.format says gif; "
                                  "make them agree (e.g. add --format mp4)"),
    ("clip.mp4", "png", True, 12, "clip.mp4 ends in .mp4, which means mp4, but --format or output.format says png"),
    ("folder.mp4", "mp4", False, 12, "folder.mp4 is a folder, but its name ends in .mp4"),
    ("folder.mp4", "png", False, 12, "folder.mp4 is a folder"),
    ("afile", "png", False, 12, "afile is a file, not a folder"),
    ("afile", "mp4", True, 12, "afile is a file, not a folder"),
    ("afile/sub", "png", False, 12, "afile is a file, so nothing can be written under it"),
    ("afile/x.png", "png", False, 1, "afile is a file, so nothing can be written under it"),
])
def test_resolve_output_rejects(tmp_path, monkeypatch, output, fmt, explicit, frames, message):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "folder.mp4").mkdir()
    (tmp_path / "afile").write_text("mine")
    with pytest.raises(UserError) as info:
        resolve_output(Path(output), fmt, explicit, frames, "shot")
    assert str(info.value).startswith("-o: ") and message in str(info.value)
    assert (tmp_path / "afile").read_text() == "mine"


@pytest.mark.gl
def test_image_suffix_writes_exactly_that_file(scene):
    render_ok("anim.yaml", "-o", "still.png", "--frames", "5")
    render_ok("anim.yaml", "-o", "shots/still.jpeg", "--frames", "0")
    with Image.open(scene / "still.png") as image:
        assert image.format == "PNG" and image.size == (W, H)
    with Image.open(scene / "shots" / "still.jpeg") as image:
        assert image.format == "JPEG"
    assert outputs(scene / "shots") == ["still.jpeg"]
    assert not (scene / "still.png").is_dir()


@pytest.mark.gl
def test_video_suffix_writes_that_video(scene):
    render_ok("anim.yaml", "-o", "clip.mp4", "--frames", "0:3")
    assert (scene / "clip.mp4").is_file()
    assert VideoSink(scene / "clip.mp4", "mp4", fps=12, size=(W, H)).is_complete()


@pytest.mark.parametrize("args, message", [
    (["-o", "still.png"], "-o: still.png names one image but the render has 12 frames"),
    (["-o", "folder.mp4"], "-o: folder.mp4 is a folder"),
    (["-o", "afile"], "-o: afile is a file, not a folder"),
    (["-o", "still.png", "--frames", "0", "--format", "jpg"],
     "-o: still.png ends in .png, which means png, but --format"),
])
def test_bad_output_is_a_clear_error_before_rendering(scene, args, message):
    (scene / "folder.mp4").mkdir()
    (scene / "afile").write_text("mine")
    result = cli("render", "anim.yaml", *args, "-q")
    assert result.exit_code == 2, result.output
    line, = result.stderr.strip().splitlines()
    assert line.startswith(f"error: {message}")
    assert (scene / "afile").read_text() == "mine"
    assert os.listdir(scene / "folder.mp4") == []


# ---------------------------------------------------------------------------------------
# output.name stays inside -o


@pytest.mark.parametrize("name, message", [
    ("../../x_{frame}", "a frame name cannot contain '/'"),
    ("a/b_{frame}", "a frame name cannot contain '/'"),
    ("a\\\\b_{frame}", "a frame name cannot contain '/' or '\\'"),
    ("{frame:/>8}", "frame 0 would be '///////0'"),
    ("{frame.__class__}", "only {frame} may appear in the name, got {frame.__class__}"),
    ("{frame.__class__.__init__.__globals__}", "only {frame} may appear"),
    ("{frame[0]}", "only {frame} may appear"),
    ("{0}", "only {frame} may appear in the name, got {0}"),
    ("{}", "only {frame} may appear"),
    ("{x}", "got {x}"),
    ("{frame!r}", "conversions such as !r are not allowed"),
    ("{frame:c}", "not an integer format spec"),
    ("{frame:{x}}", "not an integer format spec"),
    ("{frame:999999999}", "width 999999999 is more than 32"),
    ("f_{frame", "expected '}' before end of string"),
    ("..", "a frame name cannot be '..'"),
    ("x" * 300 + "_{frame}", "bytes long; at most 200"),
    ("shot", "must contain {frame} when there is more than one frame"),
    ("{frame}.png", "leave out '.png' (the format adds it)"),
    ("frame_{frame:04d}.EXR", "leave out '.EXR'"),
])
def test_bad_output_names_are_validation_errors_at_the_line(scene, name, message):
    frames = 1 if name == ".." else 3  # a name without {frame} is valid for one frame only
    (scene / "named.yaml").write_text(f"objects: []\noutput:\n  frames: {frames}\n  name: '{name}'\n",
                                      encoding="utf-8")
    result = cli("validate", "named.yaml", "--no-assets")
    assert result.exit_code == 2, result.output
    line, = result.stderr.strip().splitlines()
    assert line.startswith("error: named.yaml:4:3: output.name: ")
    assert message in line
    assert "Traceback" not in result.output


@pytest.mark.parametrize("name", ["frame_{frame:04d}", "{frame}", "shot-{frame:>6}", "f{frame:x}.v2", "{{x}}_{frame}"])
def test_good_output_names(name):
    assert name_template_problem(name, 10) is None


def test_single_frame_name_needs_no_field():
    assert name_template_problem("poster", 1) is None


def test_sinks_refuse_bad_patterns_from_code(tmp_path):
    with pytest.raises(ValueError, match="cannot contain"):
        ImageSequenceSink(tmp_path, "png", "../{frame}")


def test_single_image_sink_names_one_file(tmp_path):
    sink = SingleImageSink(tmp_path / "poster.jpeg", "jpg")
    sink.write(frame(7))
    assert os.listdir(tmp_path) == ["poster.jpeg"]
    assert sink.is_complete(7)


@pytest.mark.gl
def test_default_camera_frames_frame_zero_in_partial_runs(scene):
    """A resumed run starts at a later frame; the default camera must not frame that one."""
    render_ok("anim.yaml", "-o", "full")
    render_ok("anim.yaml", "-o", "part", "--frames", "5:7")
    for name in ("frame_0005.png", "frame_0006.png"):
        assert (scene / "part" / name).read_bytes() == (scene / "full" / name).read_bytes()


@pytest.mark.gl
def test_single_images_side_by_side_keep_each_other(scene):
    (scene / "box.yaml").write_text("render: {size: [32, 24]}\nobjects:\n  - mesh: {primitive: box}\n")
    (scene / "ball.yaml").write_text("render: {size: [32, 24]}\nobjects:\n  - mesh: {primitive: sphere}\n")
    render_ok("box.yaml", "-o", "stills/box.png")
    render_ok("ball.yaml", "-o", "stills/ball.png")
    assert outputs(scene / "stills") == ["ball.png", "box.png"]


@given(st.text(alphabet=st.sampled_from(list("{}:!.[]/\\_-<>=^+ 0123456789dxXbocsrfame%,")), max_size=24)
       | st.builds(lambda spec: "f_{frame:" + spec + "}", st.text(max_size=8)))
@settings(max_examples=300, deadline=None)
def test_any_name_template_is_refused_or_stays_inside(template):
    """Whatever the template: a message, or names that are plain file names."""
    problem = name_template_problem(template, 12)
    if problem is None:
        for index in range(12):
            name = template.format(frame=index)
            assert name not in ("", ".", "..") and "/" not in name and "\\" not in name
