"""Fixtures of the brdfkit Python tests: the `brdf` binary and the data directory.

ctest (test python_brdfkit) sets BRDF_BINARY, BRDFKIT_DATA_DIR and PYTHONPATH (the built
module in build/python); run by hand, export them the same way (docs/python.md).
"""
import json
import os
import pathlib
import subprocess

import pytest


@pytest.fixture(scope="session")
def brdf_binary():
    binary = os.environ.get("BRDF_BINARY")
    if not binary or not os.access(binary, os.X_OK):
        pytest.fail("BRDF_BINARY must name the built brdf executable")
    return binary


@pytest.fixture(scope="session")
def data_dir():
    directory = os.environ.get("BRDFKIT_DATA_DIR")
    if not directory or not os.path.isdir(directory):
        pytest.fail("BRDFKIT_DATA_DIR must name the repository's data/ directory")
    return pathlib.Path(directory)


@pytest.fixture(scope="session")
def brdf(brdf_binary):
    """Runs `brdf ARGS...`, fails the test on a non-zero exit status, returns stdout."""

    def run(*arguments):
        completed = subprocess.run([brdf_binary, *map(str, arguments)], capture_output=True,
                                   text=True)
        assert completed.returncode == 0, (arguments, completed.stderr)
        return completed.stdout

    return run


def without_times(value):
    """A report without its wall-clock fields (time_s), the only part that differs by run."""
    if isinstance(value, dict):
        return {key: without_times(item) for key, item in value.items() if key != "time_s"}
    if isinstance(value, list):
        return [without_times(item) for item in value]
    return value


def cli_json(text):
    return without_times(json.loads(text))
