"""The documented install command (docs/python.md) puts a working package in place:
`cmake --install <build> --component python`, here into a DESTDIR, then imported from there
by a fresh interpreter that sees neither the build nor the source tree."""

import os
import pathlib
import subprocess
import sys
import sysconfig

from conftest import BUILD_DIR, STREAMS, md5_file_lines


def test_install_component(tmp_path):
    build = str(BUILD_DIR)
    site = os.environ.get("TDVO_PYTHON_SITE_PACKAGES", sysconfig.get_path("platlib"))
    env = dict(os.environ, DESTDIR=str(tmp_path))
    cmake = os.environ.get("TDVO_CMAKE", "cmake")
    subprocess.run([cmake, "--install", build, "--component", "python"], check=True, env=env,
                   capture_output=True)
    package = pathlib.Path(str(tmp_path) + site) / "tdvo"
    installed = sorted(p.name for p in package.iterdir())
    assert "__init__.py" in installed
    assert any(name.startswith("_tdvo.") and name.endswith(".so") for name in installed)
    # Only what the install put there: the build's package folder is not on the path.
    clean = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    clean["PYTHONPATH"] = str(package.parent)
    stream = next(s for s in STREAMS if s.stem.startswith("texture_"))
    script = ("import sys, tdvo; print(tdvo.__file__); "
              "print('\\n'.join(tdvo.md5_lines(sys.argv[1])))")
    out = subprocess.run([sys.executable, "-c", script, str(stream)], check=True, env=clean,
                         cwd=tmp_path, capture_output=True, text=True).stdout.splitlines()
    assert out[0].startswith(str(package))
    assert out[1:] == md5_file_lines(stream)
    # Self-contained: the 3DVO libraries are linked in, no path into the build tree.
    extension = next(package.glob("_tdvo.*.so"))
    ldd = subprocess.run(["ldd", str(extension)], check=True, capture_output=True,
                         text=True).stdout
    assert "libtdvo" not in ldd and "not found" not in ldd
    readelf = subprocess.run(["readelf", "-d", str(extension)], check=True, capture_output=True,
                             text=True).stdout
    assert build not in readelf
