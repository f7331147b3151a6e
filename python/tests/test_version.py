"""grip.__version__ is the C++ library's version, as its files state it: the macros of
include/grip/core/version.hpp, the version CMake's project() gives (read from that header), and
the package's (python/pyproject.toml's, or the one its build backend reads from that header).
Each file is read here on its own, not through the module."""

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
        # dynamic = ["version"]: scikit-build-core's regex provider reads it from version.hpp.
        assert re.search(r'^dynamic\s*=\s*\[[^\]]*"version"', project, re.M), "pyproject.toml: no version"
        assert pyproject_regex_version(text) == grip.__version__


def pyproject_regex_version(text):
    """The version scikit-build-core's regex provider computes from the table
    [tool.scikit-build.metadata.version]: its regex searched in its input file (relative to
    python/), the named groups put into its result, as the provider does."""
    table = re.search(r"^\[tool\.scikit-build\.metadata\.version\]\n(.*?)(?=^\[|\Z)", text, re.M | re.S)
    assert table, "pyproject.toml: no [tool.scikit-build.metadata.version]"
    pairs = re.findall(r"""^(\w+)\s*=\s*(?:"([^"]*)"|'([^']*)')""", table.group(1), re.M)
    settings = {key: double or single for key, double, single in pairs}
    assert settings.get("provider") == "scikit_build_core.metadata.regex", settings
    source = (ROOT / "python" / settings["input"]).resolve().read_text()
    match = re.search(settings["regex"], source, re.M)
    assert match, settings["regex"]
    return settings["result"].format(*match.groups(), **match.groupdict())


def test_version_equals_the_installed_distributions():
    """When the grip imported here was installed by pip, its metadata (built from
    pyproject.toml) carries the same version."""
    try:
        dist = importlib.metadata.distribution("grip")
    except importlib.metadata.PackageNotFoundError:
        pytest.skip("grip is not installed as a distribution here (the CMake build's module)")
    module = pathlib.Path(grip.__file__).resolve()
    if not any(pathlib.Path(dist.locate_file(f)).resolve() == module for f in dist.files or []):
        pytest.skip("the installed distribution grip is not the package imported here")
    assert dist.version == grip.__version__
