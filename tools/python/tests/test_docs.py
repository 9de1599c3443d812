"""The examples of docs/python.md run as they are written: every ```python block, in order, in
one scratch folder (where `conformance` leads to the repository's), each in a fresh
interpreter, so that the tutorial cannot drift from the module."""

import os
import pathlib
import re
import subprocess
import sys

import tdvo
from conftest import CONFORMANCE, SOURCE_DIR


def test_examples(tmp_path):
    page = (SOURCE_DIR / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, re.S)
    assert len(blocks) >= 3, "docs/python.md has no examples"
    (tmp_path / "conformance").symlink_to(CONFORMANCE)
    # The package this test imported, wherever PYTHONPATH (perhaps relative) found it.
    env = dict(os.environ, PYTHONPATH=str(pathlib.Path(tdvo.__file__).resolve().parents[1]))
    for number, block in enumerate(blocks):
        run = subprocess.run([sys.executable, "-c", block], cwd=tmp_path, env=env,
                             capture_output=True, text=True)
        assert run.returncode == 0, f"example {number + 1}:\n{block}\n{run.stderr}"
