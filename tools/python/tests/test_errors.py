"""The Python rows of docs/errors.md, one test per row, read from the page itself (like
tests/errors_test.cpp for the apps): a row without a test, or a test without a row, fails."""

import re
import subprocess

import numpy as np
import pytest

import tdvo
from conftest import CONFORMANCE, SOURCE_DIR, STREAMS, app, deforming_sequence


def catalogue():
    """{id: stable message or None (the app's own message)} of the PY rows."""
    rows = {}
    for line in (SOURCE_DIR / "docs" / "errors.md").read_text().splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split(" | ")]
        if len(cells) != 4 or not re.fullmatch(r"PY\d\d", cells[0]):
            continue
        assert cells[0] not in rows, f"row {cells[0]} appears twice"
        message = cells[2]
        rows[cells[0]] = message[message.find("`") + 1:message.rfind("`")] \
            if message.count("`") >= 2 else None
        assert cells[3] == "`tdvo.Error`", cells[0]
    return rows


ROWS = catalogue()
TESTED = set()


def row(id):
    """Registers a test for catalogue row `id`."""
    TESTED.add(id)
    return lambda test: test


def expect(id, call):
    """`call` raises tdvo.Error whose message contains row `id`'s stable part."""
    with pytest.raises(tdvo.Error) as raised:
        call()
    assert ROWS[id] in str(raised.value), f"{id}: got {raised.value}"
    assert isinstance(raised.value, RuntimeError)


def small_frame():
    """A valid frame of 42 vertices: the first rows of the test torus."""
    positions, triangles = deforming_sequence(frames=1)[0]
    return positions[:42].astype(np.float64), triangles[(triangles < 42).all(axis=1)][:40]


def frame_with(positions=None, triangles=None):
    p, t = small_frame()
    return (p if positions is None else positions, t if triangles is None else triangles)


@row("PY01")
def test_frames_not_a_sequence():
    for frames in ((f for f in [frame_with()]), 3, "frames"):
        expect("PY01", lambda: tdvo.encode(frames))


@row("PY02")
def test_no_frames():
    expect("PY02", lambda: tdvo.encode([]))


@row("PY03")
def test_frame_not_a_pair():
    good = frame_with()
    expect("PY03", lambda: tdvo.encode([good, 7]))
    expect("PY03", lambda: tdvo.encode([good, good + (None,)]))


@row("PY04")
def test_positions_shape():
    good = frame_with()
    p, _ = good
    expect("PY04", lambda: tdvo.encode([good, frame_with(positions=p[:, :2])]))
    for bad in (p[:, 0], p[:, :, None], [[0.0, 1.0]] * 3):
        with pytest.raises(tdvo.Error, match=r"frame 1: positions: expected an array of shape"):
            tdvo.encode([good, frame_with(positions=bad)])


@row("PY05")
def test_positions_dtype():
    p, _ = small_frame()
    for bad in (p.astype(np.complex128), p > 0, p.astype(str), p.astype(object)):
        expect("PY05", lambda: tdvo.encode([frame_with(positions=bad)]))


@row("PY06")
def test_triangles_dtype():
    _, t = small_frame()
    expect("PY06", lambda: tdvo.encode([frame_with(triangles=t.astype(np.float64))]))


@row("PY07")
def test_not_finite():
    good = frame_with()
    for dtype in (np.float64, np.float32):
        for value in (np.nan, np.inf, -np.inf):
            p = small_frame()[0].astype(dtype)
            p[5, 1] = value
            with pytest.raises(tdvo.Error) as raised:
                tdvo.encode([good, good, frame_with(positions=p)])
            message = str(raised.value)
            assert message.startswith("frame 2: positions[5, 1] is not finite (")
            if np.isnan(value):
                assert ROWS["PY07"] in message


@row("PY18")
def test_beyond_coordinate_range():
    good = frame_with()
    for value in (1e301, -1e301):
        p = small_frame()[0]
        p[5, 1] = value
        with pytest.raises(tdvo.Error) as raised:
            tdvo.encode([good, good, frame_with(positions=p)])
        if value > 0:
            assert ROWS["PY18"] in str(raised.value)
        else:
            assert str(raised.value).startswith("frame 2: positions[5, 1] = -1e+301 is beyond")


@row("PY08")
def test_index_out_of_range():
    _, t = small_frame()
    for bad, dtype in ((42, np.uint32), (-1, np.int64), (2**40, np.int64), (2**64 - 1, np.uint64)):
        tt = t.astype(dtype)
        tt[3, 2] = bad
        with pytest.raises(tdvo.Error) as raised:
            tdvo.encode([frame_with(triangles=tt)])
        assert str(raised.value) == (f"frame 0: triangles[3, 2]: vertex index {bad} out of range "
                                     "(the frame has 42 vertices)")
        if bad == 42:
            assert ROWS["PY08"] in str(raised.value)


@row("PY09")
def test_empty_frame():
    expect("PY09", lambda: tdvo.encode([frame_with(positions=np.zeros((0, 3)))]))
    with pytest.raises(tdvo.Error, match="frame 0: triangles: no faces"):
        tdvo.encode([frame_with(triangles=np.zeros((0, 3), dtype=np.int32))])


@row("PY10")
def test_all_degenerate():
    expect("PY10", lambda: tdvo.encode([frame_with(triangles=np.array([[0, 1, 1], [2, 2, 2]]))]))


@row("PY11")
def test_size_limits():
    # Views of one row: no memory, refused from the shape before anything is read.
    many = np.broadcast_to(np.zeros(3), (2**26 + 1, 3))
    expect("PY11", lambda: tdvo.encode([frame_with(positions=many)]))
    triangles = np.broadcast_to(np.array([0, 1, 2]), (2**27 + 1, 3))
    with pytest.raises(tdvo.Error, match="frame 0: triangles: more than 134217728 triangles"):
        tdvo.encode([frame_with(triangles=triangles)])


@row("PY12")
def test_too_many_frames():
    frame = frame_with()
    expect("PY12", lambda: tdvo.encode([frame] * 1000001))


@row("PY13")
def test_cfg_values():
    frames = [frame_with()]
    for cfg in ({"GOMSize": [1]}, {"GOMSize": None}):
        expect("PY13", lambda: tdvo.encode(frames, cfg))
    with pytest.raises(tdvo.Error, match="cfg: keys must be str"):
        tdvo.encode(frames, {3: "x"})


@row("PY14")
def test_decoder_source():
    for source in (3, [1, 2]):
        expect("PY14", lambda: tdvo.Decoder(source))


def dec_error(path):
    """3dvo-dec's message for a stream file (after its "3dvo-dec: error: " prefix)."""
    run = subprocess.run([app("3dvo-dec"), "-i", str(path)], capture_output=True, text=True)
    assert run.returncode == 1, run.stderr
    prefix = "3dvo-dec: error: "
    line = run.stderr.strip().splitlines()[-1]
    assert line.startswith(prefix), line
    return line[len(prefix):]


def decode_all(source, **kwargs):
    decoder = tdvo.Decoder(source, **kwargs)
    for _ in decoder:
        pass


@row("PY15")
def test_stream_errors_as_3dvo_dec(tmp_path):
    """Cut and corrupted conformance streams: the Python message is 3dvo-dec's, from the
    pull decoder, from md5_lines, from a file and from bytes named like the file."""
    cases = [tmp_path / "missing.3dvo"]
    for stream in (STREAMS[0], next(s for s in STREAMS if s.stem.startswith("texture_"))):
        data = stream.read_bytes()
        cuts = {"head": data[:3], "magic": data[:4], "header": data[:20],
                "half": data[:len(data) // 2], "last": data[:-1],
                "flip": data[:len(data) // 3] + bytes([data[len(data) // 3] ^ 0x10]) +
                data[len(data) // 3 + 1:],
                "more": data + data[4:40]}
        for name, cut in cuts.items():
            path = tmp_path / f"{stream.stem}-{name}.3dvo"
            path.write_bytes(cut)
            cases.append(path)
    for path in cases:
        expected = dec_error(path)
        with pytest.raises(tdvo.Error) as raised:
            decode_all(str(path))
        assert str(raised.value) == expected
        with pytest.raises(tdvo.Error) as raised:
            tdvo.md5_lines(str(path))
        assert str(raised.value) == expected
        if path.exists():
            with pytest.raises(tdvo.Error) as raised:
                decode_all(path.read_bytes(), name=str(path))
            assert str(raised.value) == expected


@row("PY16")
def test_unknown_cfg_key(tmp_path):
    run = subprocess.run([app("3dvo-enc"), "--Frobnicate=1"], capture_output=True, text=True)
    assert run.returncode == 1
    line = run.stderr.strip().splitlines()[-1]
    expected = line[len("3dvo-enc: error: "):]
    with pytest.raises(tdvo.Error) as raised:
        tdvo.encode([frame_with()], {"Frobnicate": 1})
    assert str(raised.value) == expected


@row("PY17")
def test_frame_with_texture_coordinates_is_refused_not_stripped():
    stream = CONFORMANCE / "streams" / "d3dmc_attributes_g3_ra2.3dvo"
    frame = next(iter(tdvo.Decoder(str(stream))))
    expect("PY17", lambda: tdvo.encode([frame], {"GOMSize": 1}))
    # The geometry alone, asked for as a pair, is coded.
    assert len(tdvo.encode([(frame.positions, frame.triangles)], {"GOMSize": 1}).stream) > 0


def test_seek_outside_the_stream():
    decoder = tdvo.Decoder(STREAMS[0])
    last = decoder.info.first_frame + decoder.info.frame_count - 1
    for target in (decoder.info.first_frame - 1, last + 1):
        with pytest.raises(tdvo.Error):
            decoder.seek(target)
    # The decoder still works after the refused seek.
    decoder.seek(decoder.info.first_frame)
    assert next(decoder).number == decoder.info.first_frame


def test_every_row_has_a_test_and_every_test_a_row():
    assert len(ROWS) >= 16, "docs/errors.md has no Python rows"
    assert set(ROWS) == TESTED


def test_decoder_limits_as_3dvo_dec(tmp_path):
    """The decoder's limits, set from Python, refuse what 3dvo-dec refuses with them."""
    stream = next(s for s in STREAMS if s.stem == "d3dmc_lossless_g8")
    texture = next(s for s in STREAMS if s.stem.startswith("texture_"))
    for path, option, keyword in (
            (stream, "--MaxVertexFramesPerByte=1", "max_vertex_frames_per_byte"),
            (stream, "--MaxMeshMemoryPerByte=1", "max_mesh_memory_per_byte"),
            (texture, "--MaxTexturePixelsPerByte=1", "max_texture_pixels_per_byte")):
        run = subprocess.run([app("3dvo-dec"), "-i", str(path), option], capture_output=True,
                             text=True)
        if run.returncode == 0:  # the limit is above what this stream needs
            decode_all(str(path), **{keyword: 1})
            continue
        expected = run.stderr.strip().splitlines()[-1][len("3dvo-dec: error: "):]
        with pytest.raises(tdvo.Error) as raised:
            decode_all(str(path), **{keyword: 1})
        assert str(raised.value) == expected
    # 0 lifts a limit.
    decode_all(str(stream), max_vertex_frames_per_byte=0)
