"""Decoding every conformance stream in Python gives 3dvo-dec's MD5 lines (issue 19, point 5)."""

import gc
import gzip
import subprocess

import numpy as np
import pytest

import tdvo
from conftest import CONFORMANCE, STREAMS, app, md5_file_lines

IDS = [s.stem for s in STREAMS]


def decoded_lines(decoder):
    """Geometry lines, texture lines (each in order) and frame numbers of a pull decode."""
    geometry, textures, numbers = [], [], []
    for frame in decoder:
        numbers.append(frame.number)
        geometry.append(frame.md5_line)
        textures += frame.texture_md5_lines
    return geometry, textures, numbers


def split(lines):
    geometry = [l for l in lines if " geometry=" in l]
    textures = [l for l in lines if " texture " in l]
    header = [l for l in lines if l.startswith("MD5 header=")]
    assert len(geometry) + len(textures) + len(header) == len(lines)
    return geometry, textures, header


@pytest.mark.parametrize("stream", STREAMS, ids=IDS)
def test_md5_lines_equal_the_committed_log(stream):
    assert tdvo.md5_lines(str(stream)) == md5_file_lines(stream)


def test_md5_lines_equal_3dvo_dec():
    for stream in STREAMS:
        out = subprocess.run([app("3dvo-dec"), "-i", str(stream)], check=True,
                             capture_output=True, text=True).stdout
        printed = [l for l in out.splitlines() if l.startswith("MD5 ")]
        assert tdvo.md5_lines(stream) == printed, stream.name


@pytest.mark.parametrize("stream", STREAMS, ids=IDS)
def test_frame_by_frame(stream):
    geometry, textures, header = split(md5_file_lines(stream))
    decoder = tdvo.Decoder(stream)
    info = decoder.info
    got_geometry, got_textures, numbers = decoded_lines(decoder)
    assert got_geometry == geometry
    assert got_textures == textures
    assert [decoder.header_md5_line] == header
    assert numbers == list(info.frame_numbers)
    assert len(numbers) == info.frame_count
    # Iteration ends for good.
    assert decoder.read() is None
    with pytest.raises(StopIteration):
        next(decoder)


@pytest.mark.parametrize("stream", STREAMS, ids=IDS)
def test_from_memory(stream):
    data = stream.read_bytes()
    expected = md5_file_lines(stream)
    for source in (data, bytearray(data), memoryview(data)):
        decoder = tdvo.Decoder(source)
        geometry, textures, _ = decoded_lines(decoder)
        assert geometry + textures + [decoder.header_md5_line] == sum(split(expected), [])
        assert tdvo.md5_lines(source) == expected


def test_frame_arrays():
    stream = next(s for s in STREAMS if s.stem == "d3dmc_q4_g5")
    decoder = tdvo.Decoder(stream)
    grid = decoder.info.grid
    assert grid.bits == 12 and grid.step > 0 and len(grid.origin) == 3
    frame = next(decoder)
    assert frame.number == 0 and frame.index == 0
    p, q, t = frame.positions, frame.grid_positions, frame.triangles
    assert p.dtype == np.float64 and q.dtype == np.int32 and t.dtype == np.uint32
    assert p.shape == q.shape == (162, 3) and t.shape == (320, 3)
    assert t.max() < len(p)
    # Positions are origin + q * step, in double: the values 3dvo-dec writes.
    np.testing.assert_array_equal(p, np.array(grid.origin) + q.astype(np.float64) * grid.step)
    # Views of the frame's own memory: not owned, read-only, and they keep the frame alive.
    for a in (p, q, t):
        assert not a.flags.owndata and not a.flags.writeable and a.flags.c_contiguous
        with pytest.raises(ValueError):
            a[0, 0] = 1
    assert p.base is frame
    copy = np.array(p)
    del frame
    gc.collect()
    np.testing.assert_array_equal(p, copy)
    assert decoder.info.frame_count == 12 and decoder.info.cameras == []
    assert decoder.info.up is None


def test_textures():
    stream = next(s for s in STREAMS if s.stem == "texture_bbox_mb128_g3")
    decoder = tdvo.Decoder(stream)
    cameras = decoder.info.cameras
    assert len(cameras) == 3
    for c in cameras:
        assert c.name and c.width > 0 and c.height > 0
        assert c.K.shape == (3, 3) and c.R.shape == (3, 3) and c.t.shape == (3,)
        assert c.K[2, 2] == 1 and len(c.distortion) == 5
        x, y, w, h = c.texture_box
        assert w % 16 == 0 and h % 16 == 0
    frame = next(decoder)
    assert len(frame.textures) == 3
    for texture in frame.textures:
        c = cameras[texture.camera]
        x, y, w, h = texture.box
        assert texture.box == c.texture_box
        assert texture.y.shape == (h, w) and texture.y.dtype == np.uint8
        assert texture.u.shape == texture.v.shape == (h // 2, w // 2)
        assert texture.shape.shape == (c.height, c.width)
        assert set(np.unique(texture.shape)) <= {0, 255}
        assert not texture.y.flags.owndata and not texture.y.flags.writeable
    # A texture's arrays keep the frame alive.
    y = frame.textures[0].y
    copy = np.array(y)
    del frame
    gc.collect()
    np.testing.assert_array_equal(y, copy)
    # Without the picture decoder, texture units are read and checked, not decoded.
    geometry_only = tdvo.Decoder(stream, textures=False)
    frames = list(geometry_only)
    assert all(f.textures == [] for f in frames) and len(frames) == 6


def test_seek():
    for stream in STREAMS:
        decoder = tdvo.Decoder(stream)
        frames = {f.number: f.md5_line for f in decoder}
        starts = decoder.gom_starts
        assert starts and starts[0] == decoder.info.first_frame
        assert starts == sorted(starts)
        for target in sorted(set(starts + [max(frames)])):
            decoder.seek(target)
            rest = [(f.number, f.md5_line) for f in decoder]
            assert rest == [(n, frames[n]) for n in sorted(frames) if n >= target], stream.name


def test_gil_released_while_decoding():
    # Two threads decoding at once give the same lines as one after the other.
    import threading
    results = {}

    def run(stream):
        results[stream] = tdvo.md5_lines(stream)

    threads = [threading.Thread(target=run, args=(s,)) for s in STREAMS[:4]]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for s in STREAMS[:4]:
        assert results[s] == md5_file_lines(s)


def test_one_decoder_shared_by_threads():
    # Threads pulling frames from one decoder take turns: every frame comes out once.
    import threading
    stream = next(s for s in STREAMS if s.stem == "d3dmc_lossless_g8")
    decoder = tdvo.Decoder(stream)
    numbers = []

    def pull():
        for frame in decoder:
            numbers.append(frame.number)

    threads = [threading.Thread(target=pull) for _ in range(3)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(numbers) == list(decoder.info.frame_numbers)


def read_obj_attributes(path):
    """The vt and vn values and the per-corner vt/vn indices of a (gzip) OBJ file, as float32 and
    uint32 arrays (None for an attribute the file does not give)."""
    opener = gzip.open if str(path).endswith(".gz") else open
    uvs, normals, uv_tris, normal_tris = [], [], [], []
    with opener(path, "rt") as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "vt":
                uvs.append([float(w) for w in words[1:3]])
            elif words[0] == "vn":
                normals.append([float(w) for w in words[1:4]])
            elif words[0] == "f":
                corners = [w.split("/") for w in words[1:]]
                if len(corners[0]) > 1 and corners[0][1]:
                    uv_tris.append([int(c[1]) - 1 for c in corners])
                if len(corners[0]) > 2 and corners[0][2]:
                    normal_tris.append([int(c[2]) - 1 for c in corners])

    def array(rows, dtype):
        return np.array(rows, dtype=dtype) if rows else None
    return (array(uvs, np.float32), array(uv_tris, np.uint32), array(normals, np.float32),
            array(normal_tris, np.uint32))


def test_texture_coordinates_and_normals():
    """A stream with texture coordinates and normals gives them as the input OBJ has them,
    bit for bit (frames made from an I mesh carry its values); one without gives None."""
    stream = CONFORMANCE / "streams" / "d3dmc_attributes_g3_ra2.3dvo"
    decoder = tdvo.Decoder(str(stream))
    frame = next(iter(decoder))
    uvs, uv_tris, normals, normal_tris = read_obj_attributes(
        CONFORMANCE / "inputs" / "blob-uv" / f"{frame.number:04d}.obj.gz")
    assert uvs is not None
    assert frame.uvs.dtype == np.float32 and frame.uvs.shape == uvs.shape
    assert frame.uv_triangles.dtype == np.uint32
    np.testing.assert_array_equal(frame.uvs, uvs)
    np.testing.assert_array_equal(frame.uv_triangles, uv_tris)
    if normals is not None and frame.normals is not None and normal_tris is not None:
        assert frame.normals.shape[1] == 3
        assert int(frame.normal_triangles.max()) < len(frame.normals)
    assert not frame.uvs.flags.writeable
    assert frame.uv_origin == "bottom"  # OBJ's: v = 0 at the image's bottom row
    gltf = next(iter(tdvo.Decoder(str(CONFORMANCE / "streams" / "d3dmc_attributes_gltf_g6.3dvo"))))
    assert gltf.uv_origin == "top"  # glTF's
    plain = next(iter(tdvo.Decoder(str(CONFORMANCE / "streams" / "d3dmc_q4_g5.3dvo"))))
    assert plain.uvs is None and plain.normals is None and plain.uv_triangles is None
    assert plain.uv_origin is None

