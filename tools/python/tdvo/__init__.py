"""3DVO for Python: decode .3dvo streams into numpy arrays, encode numpy mesh sequences.

    import tdvo
    for frame in tdvo.Decoder("object.3dvo"):
        frame.positions      # float64 (N, 3), read-only view of the decoded frame
        frame.triangles      # uint32 (M, 3)
    coded = tdvo.encode([(positions, triangles), ...], {"GOMSize": 12, "GridBits": 12})
    open("x.3dvo", "wb").write(coded.stream)

The classes and functions live in the extension module tdvo._tdvo (tools/python/tdvo_module.cpp
in the 3DVO repository); docs/python.md is the tutorial. Every error of the codec is raised as
tdvo.Error with the message 3dvo-dec and 3dvo-enc print after "<app>: error: ".
"""

from ._tdvo import (  # noqa: F401  (the package's API)
    Camera,
    Decoder,
    Encoded,
    Error,
    Frame,
    Grid,
    StreamInfo,
    Texture,
    encode,
    md5_lines,
)

try:
    from ._tdvo import __version__  # noqa: F401
except ImportError:  # built without a version
    __version__ = "unknown"

__all__ = [
    "Camera",
    "Decoder",
    "Encoded",
    "Error",
    "Frame",
    "Grid",
    "StreamInfo",
    "Texture",
    "encode",
    "md5_lines",
]
