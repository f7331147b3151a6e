"""grip.__version__ is the C++ library's version, as its files state it: the macros of
include/grip/core/version.hpp, the version CMake's project() gives (read from that header), and
the package's (python/pyproject.toml's, or setup.py's from that header when it is dynamic).
Each file is read here on its own, not through the module."""

import ast
import importlib.metadata
import os
import pathlib
import re

import pytest

import grip

ROOT = pathlib.Path(__file__).resolve().parents[2]


def read(relative):
    return (ROOT / relative).read_text()


def header_version():
    text = read("include/grip/core/version.hpp")
    parts = [re.search(rf"^#define GRIP_VERSION_{p} (\d+)$", text, re.M).group(1) for p in ("MAJOR", "MINOR", "PATCH")]
    string = re.search(r'^#define GRIP_VERSION_STRING "([^"]+)"$', text, re.M).group(1)
    return ".".join(parts), string


def test_version_is_a_string_equal_to_the_headers_macros():
    numbers, string = header_version()
    assert isinstance(grip.__version__, str)
    assert re.fullmatch(r"\d+\.\d+\.\d+", grip.__version__)
    assert grip.__version__ == numbers == string


def test_version_equals_the_cmake_projects():
    text = read("CMakeLists.txt")
    project = re.search(r"^project\(grip\s+VERSION\s+(\S+)", text, re.M)
    assert project, "CMakeLists.txt: no project(grip VERSION ...)"
    version = project.group(1)
    if re.fullmatch(r"\d+\.\d+\.\d+", version):
        assert version == grip.__version__
    else:
        # project(grip VERSION ${grip_version_MAJOR}...) with the parts read from version.hpp:
        # do what CMake does (file(STRINGS ... REGEX), string(REGEX MATCH)) and compare.
        assert version == "${grip_version_MAJOR}.${grip_version_MINOR}.${grip_version_PATCH}", version
        strings = re.search(r'file\(STRINGS\s+"\$\{CMAKE_CURRENT_SOURCE_DIR\}/([^"]+)"\s+grip_version_lines\s+'
                            r'REGEX\s+"([^"]+)"\)', text)
        assert strings, "CMakeLists.txt: the version's parts are not read with file(STRINGS) into grip_version_lines"
        header = read(strings.group(1))
        lines = [line for line in header.splitlines() if re.search(strings.group(2), line)]
        joined = ";".join(lines)
        parts = [re.search(rf"GRIP_VERSION_{p} ([0-9]+)", joined).group(1) for p in ("MAJOR", "MINOR", "PATCH")]
        assert ".".join(parts) == grip.__version__
    # The value CMake computed, when the suite runs as the CTest test of a CMake build.
    if os.environ.get("GRIP_PROJECT_VERSION"):
        assert os.environ["GRIP_PROJECT_VERSION"] == grip.__version__


def test_version_equals_the_python_packages():
    text = read("python/pyproject.toml")
    project = re.search(r"^\[project\]\n(.*?)(?=^\[|\Z)", text, re.M | re.S).group(1)
    static = re.search(r'^version\s*=\s*"([^"]+)"', project, re.M)
    if static:
        assert static.group(1) == grip.__version__
    else:
        # dynamic = ["version"]: setup.py supplies it, from version.hpp's macros.
        assert re.search(r'^dynamic\s*=\s*\[[^\]]*"version"', project, re.M), "pyproject.toml: no version"
        assert setup_py_version() == grip.__version__


def setup_py_version():
    """The version python/setup.py gives setup(): its version() function run on its own, the
    call setup(version=version()) checked to be there."""
    tree = ast.parse(read("python/setup.py"))
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call) and getattr(n.func, "id", None) == "setup"]
    assert len(calls) == 1
    given = [k.value for k in calls[0].keywords if k.arg == "version"]
    assert len(given) == 1 and isinstance(given[0], ast.Call) and given[0].func.id == "version" and not given[0].args
    function = next(n for n in tree.body if isinstance(n, ast.FunctionDef) and n.name == "version")
    scope = {"os": os, "re": re, "INCLUDE": str(ROOT / "include")}
    exec(compile(ast.Module(body=[function], type_ignores=[]), "python/setup.py", "exec"), scope)
    return scope["version"]()


def test_version_equals_the_installed_distributions():
    """When the grip imported here was installed by pip, its metadata (built from
    pyproject.toml and setup.py) carries the same version."""
    try:
        dist = importlib.metadata.distribution("grip")
    except importlib.metadata.PackageNotFoundError:
        pytest.skip("grip is not installed as a distribution here (the CMake build's module)")
    module = pathlib.Path(grip.__file__).resolve()
    if not any(pathlib.Path(dist.locate_file(f)).resolve() == module for f in dist.files or []):
        pytest.skip("the installed distribution grip is not the package imported here")
    assert dist.version == grip.__version__
