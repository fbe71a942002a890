"""Shared fixtures: the `irradia` command the arrays are compared with, and the
repository's test data."""

import os
import pathlib
import shutil
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
DATA = REPO / "crates" / "import" / "tests" / "data"


def _find_cli():
    env = os.environ.get("IRRADIA_BIN")
    if env:
        return env
    targets = [os.environ.get("CARGO_TARGET_DIR"), str(REPO / "target")]
    for t in filter(None, targets):
        for profile in ("debug", "release"):
            p = pathlib.Path(t) / profile / "irradia"
            if p.is_file():
                return str(p)
    return shutil.which("irradia")


@pytest.fixture(scope="session")
def cli():
    """Runs the `irradia` command: cli(*args) -> CompletedProcess (text)."""
    exe = _find_cli()
    if exe is None:
        if os.environ.get("IRRADIA_REQUIRE_CLI") == "1":
            pytest.fail("the irradia command is needed (set IRRADIA_BIN or build it: cargo build -p irradia)")
        pytest.skip("the irradia command is not built (set IRRADIA_BIN)")

    def run(*args, check=True):
        r = subprocess.run([exe, *map(str, args)], capture_output=True, text=True)
        if check and r.returncode != 0:
            raise AssertionError("irradia %s failed (%d): %s" % (" ".join(map(str, args)), r.returncode, r.stderr))
        return r

    return run


@pytest.fixture(scope="session")
def data():
    return DATA
