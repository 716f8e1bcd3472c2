"""Shared fixtures: small scenarios and the `spraysim` command to compare against."""

import os
import pathlib
import shutil

import pytest

import spraysim

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def cli() -> str:
    """The `spraysim` command: $SPRAYSIM_CLI (which must exist when set), else the
    workspace's release build, else `spraysim` on the PATH; skips when there is none."""
    given = os.environ.get("SPRAYSIM_CLI")
    if given:
        assert pathlib.Path(given).is_file(), f"SPRAYSIM_CLI={given} does not exist"
        return given
    built = REPO / "target" / "release" / "spraysim"
    if built.is_file():
        return str(built)
    found = shutil.which("spraysim")
    if found:
        return found
    pytest.skip("no spraysim command: run `cargo build --release` or set SPRAYSIM_CLI")


@pytest.fixture
def short() -> spraysim.Scenario:
    """The default scene cut to 0.2 s with a 256 × 256 wall: quick, with a real deposit."""
    return spraysim.Scenario().set_many(
        {"simulation.duration": 0.2, "target[0].resolution": [256, 256]}
    )
