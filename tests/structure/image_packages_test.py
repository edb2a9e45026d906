#!/usr/bin/python3
"""The container images build with what a machine builds with.

scripts/install-deps.sh names the Debian packages the build needs; docker/Dockerfile's build
stage installs its own list, and its runtime stage the shared libraries and data the binaries
load. The two drifted twice (cairo for spacetime.png, valijson for the summary check), and only
the container test, which needs root and Debian's mirror, found it. This test fails at once:
every library package (-dev) of install-deps.sh that the three images' binaries build with is
in the build stage, and the runtime stage has the libraries and fonts those packages bring at
run time (RUNTIME). Test and benchmark libraries are not built into the images (TEST_ONLY).
"""
import os
import re
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
# Built only with COMPACTION_BUILD_TESTS or COMPACTION_BUILD_BENCH, which the images turn off.
TEST_ONLY = {"libgtest-dev", "libgmock-dev", "libbenchmark-dev"}
# A build package whose binaries need something at run time: the packages the runtime stage
# must install for it (header-only libraries need nothing).
RUNTIME = {
    "libsqlite3-dev": ["libsqlite3-0"],
    "libcpp-httplib-dev": ["libcpp-httplib0.11"],
    "libspdlog-dev": ["libspdlog1.10", "libfmt9"],
    "zlib1g-dev": ["zlib1g"],
    "libcairo2-dev": ["libcairo2", "fonts-dejavu-core"],
    "nlohmann-json3-dev": [], "libcli11-dev": [], "libeigen3-dev": [], "libvalijson-dev": [],
}


def install_deps_packages(text):
    """The words of install-deps.sh's `packages=( ... )` array, comments left out."""
    body = text[text.index("packages=(") + len("packages=("):]
    body = body[:body.index("\n)")]
    return [w for line in body.splitlines() for w in line.split("#")[0].split()]


def stage_packages(text, stage):
    """The packages of the first `apt-get install` of a Dockerfile stage (`FROM ... AS stage`)."""
    start = re.search(r"^FROM .* AS %s$" % re.escape(stage), text, re.M)
    if not start:
        raise AssertionError("docker/Dockerfile has no stage %s" % stage)
    rest = text[start.end():]
    run = rest[rest.index("apt-get install"):]
    run = run[:run.index("&& rm -rf")]
    words = run.replace("\\\n", " ").split()
    return [w for w in words[2:] if not w.startswith("-")]


class ImagePackages(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        with open(os.path.join(ROOT, "scripts", "install-deps.sh")) as f:
            cls.deps = install_deps_packages(f.read())
        with open(os.path.join(ROOT, "docker", "Dockerfile")) as f:
            docker = f.read()
        cls.build = stage_packages(docker, "build")
        cls.runtime = stage_packages(docker, "runtime")

    def libraries(self):
        return [p for p in self.deps if p.endswith("-dev") and p not in TEST_ONLY]

    def test_the_build_stage_has_every_library_of_install_deps(self):
        self.assertIn("libcairo2-dev", self.libraries())  # the reading found the list
        missing = [p for p in self.libraries() if p not in self.build]
        self.assertEqual(missing, [], "docker/Dockerfile's build stage lacks these packages of "
                         "scripts/install-deps.sh")

    def test_the_runtime_stage_has_what_each_library_loads(self):
        unknown = [p for p in self.libraries() if p not in RUNTIME]
        self.assertEqual(unknown, [], "a new library in install-deps.sh: say in RUNTIME what its "
                         "binaries need at run time")
        missing = [r for p in self.libraries() for r in RUNTIME[p] if r not in self.runtime]
        self.assertEqual(missing, [], "docker/Dockerfile's runtime stage lacks these")

    def test_the_readers_see_a_missing_package(self):
        deps = install_deps_packages("packages=(\n  a-dev b  # c-dev\n  d-dev\n)\n")
        self.assertEqual(deps, ["a-dev", "b", "d-dev"])
        docker = ("FROM x AS build\nRUN apt-get update && apt-get install -y --no-install-recommends"
                  " \\\n      a-dev \\\n    && rm -rf /var/lib/apt/lists/*\n")
        self.assertEqual(stage_packages(docker, "build"), ["a-dev"])
        self.assertNotIn("d-dev", stage_packages(docker, "build"))


if __name__ == "__main__":
    unittest.main()
