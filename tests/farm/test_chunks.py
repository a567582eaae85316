"""Cutting an animation into chunks with warm-up frames, resuming a chunk, frame files written atomically, and the
command line's frame ranges (no cluster: farm/chunks.py, io/frame_files.py, cli/farm.py)."""

from __future__ import annotations

import argparse

import numpy as np
import pytest
from restircl.cli.main import build_parser
from restircl.farm.chunks import Chunk, FrameRange, default_chunk_size, parse_frames, plan_chunks
from restircl.io.frame_files import frame_paths, write_frame, written_frames


def test_parse_frames():
    assert parse_frames("16") == 16
    assert parse_frames("3-9") == FrameRange(3, 9) and FrameRange(3, 9).count == 7
    for bad in ("0", "-3", "9-3", "a-b", "1-", "x", "1.5"):
        with pytest.raises(argparse.ArgumentTypeError):
            parse_frames(bad)


def test_chunks_cover_the_range_once_with_warmup_clipped_at_the_start():
    chunks = plan_chunks(FrameRange(2, 21), chunk_size=6, warmup=4)
    assert [list(c.kept) for c in chunks] == [list(range(2, 8)), list(range(8, 14)), list(range(14, 20)), [20, 21]]
    assert [c.start for c in chunks] == [0, 4, 10, 16]  # the first chunk's warm-up stops at frame 0
    assert plan_chunks(FrameRange(5, 9), 10, 3, earliest=-10)[0].start == 2  # a .blend has frames before 0
    with pytest.raises(ValueError):
        plan_chunks(FrameRange(0, 9), 0, 1)
    with pytest.raises(ValueError):
        plan_chunks(FrameRange(0, 9), 4, 1, earliest=3)
    assert default_chunk_size(FrameRange(0, 9), 3) == 4 and default_chunk_size(FrameRange(0, 1), 8) == 1


def test_a_resumed_chunk_restarts_at_its_first_missing_frame_with_its_own_warmup():
    c = Chunk(1, 4, 8, 15, warmup=4, earliest=0)
    assert c.resumed(set()) == c
    assert c.resumed(set(range(8, 16))) is None
    r = c.resumed({8, 9, 10, 12})  # 11 is missing, 12 was written (it is rendered again, as history, not written)
    assert (r.start, r.first, r.last) == (7, 11, 15)
    assert Chunk(0, 0, 0, 5, warmup=4).resumed({0}).start == 0


def test_frame_files_are_written_whole_or_not_at_all(tmp_path):
    from restircl import Frame

    img = np.full((4, 6, 4), 0.5, np.float32)
    f = Frame(img, img[..., :3], None, None, None, None)
    exr, png = write_frame(tmp_path, "anim", 7, f)
    assert (exr.name, png.name) == ("anim_0007.exr", "anim_0007.png")
    assert written_frames(tmp_path, "anim", range(10)) == {7}
    frame_paths(tmp_path, "anim", 8)[0].write_bytes(b"")  # an EXR without its PNG: not written
    assert written_frames(tmp_path, "anim", range(10)) == {7}
    assert not [p for p in tmp_path.iterdir() if ".tmp" in p.name]  # no temporary file left behind

    def fail(_tmp):
        raise OSError("disk full")

    from restircl.io import frame_files

    with pytest.raises(OSError):
        frame_files._atomic(tmp_path / "x.png", fail)
    assert not (tmp_path / "x.png").exists() and not [p for p in tmp_path.iterdir() if ".tmp" in p.name]


def test_render_options():
    a = build_parser().parse_args(["render", "many_lights", "--frames", "4-11", "--workers", "2", "--chunk-size", "3",
                                   "--warmup-frames", "5"])
    assert (a.frames, a.workers, a.chunk_size, a.warmup_frames) == (FrameRange(4, 11), 2, 3, 5)
    a = build_parser().parse_args(["render", "many_lights"])
    assert (a.frames, a.workers, a.scheduler) == (16, None, None)


def test_render_errors_name_the_problem(tmp_path, capsys):
    from restircl.cli.main import main

    assert main(["render", "cornell_box", "--frames", "0-3", "--out", str(tmp_path)]) == 2
    assert "has one frame" in capsys.readouterr().err
    assert main(["render", "moving_box", "--frames", "10-20", "--out", str(tmp_path)]) == 2
    assert "frames 0-15" in capsys.readouterr().err
    assert main(["render", str(tmp_path / "none.blend"), "--frames", "1-2", "--out", str(tmp_path)]) == 2
    assert "no such .blend" in capsys.readouterr().err
    assert main(["render", "many_lights", "--frames", "0-3", "--mode", "still", "--out", str(tmp_path)]) == 2
