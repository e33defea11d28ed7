"""The package itself: its version is the CMake project's."""
import re
from pathlib import Path

import tensormass as tm


def test_version_is_the_cmake_project_version():
    cmake = (Path(__file__).resolve().parents[2] / "CMakeLists.txt").read_text()
    declared = re.search(r"project\(tensormass VERSION ([0-9.]+)", cmake).group(1)
    assert tm.__version__ == declared
