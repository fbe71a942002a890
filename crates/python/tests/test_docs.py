"""Every Python example of docs/python.md and examples/python/ runs."""

import os
import re
import subprocess
import sys

from conftest import REPO


def test_docs_python_examples_run(tmp_path, monkeypatch):
    text = (REPO / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) >= 8
    os.symlink(REPO / "crates", tmp_path / "crates")
    monkeypatch.chdir(tmp_path)
    ns = {}
    for i, code in enumerate(blocks):
        try:
            exec(compile(code, "docs/python.md block %d" % (i + 1), "exec"), ns)
        except Exception as e:  # pragma: no cover - the message names the block
            raise AssertionError("docs/python.md python block %d failed: %r\n%s" % (i + 1, e, code))


def test_course_assignment_runs(tmp_path):
    r = subprocess.run([sys.executable, str(REPO / "examples" / "python" / "course_assignment.py"),
                        "--small", "--out", str(tmp_path)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "rays" in r.stdout and "final residual" in r.stdout
    assert (tmp_path / "whitted.png").is_file() and (tmp_path / "path.png").is_file()


def test_sort_last_volume_runs_without_mpi(tmp_path):
    r = subprocess.run([sys.executable, str(REPO / "examples" / "python" / "sort_last_volume.py"),
                        "--size", "32", "--ranks", "3", "--out", str(tmp_path / "v.png")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert "max difference" in r.stdout and (tmp_path / "v.png").is_file()
