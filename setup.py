"""Builds the binding's native module (_rotleap_native.so: the library and app/'s deck code,
python/rotleap/native.c) with CMake and puts it into the package.  ROTLEAP_BUILD_DIR names an
existing CMake build of this tree to take it from (built there, target rotleap_py); otherwise
build-python/ is configured (Release, no tests) and built.  ROTLEAP_CMAKE_ARGS adds arguments to
that configuration; ccache is used when it is installed."""
import os
import shlex
import shutil
import subprocess

from setuptools import setup
from setuptools.command.build_py import build_py
from setuptools.dist import Distribution

HERE = os.path.dirname(os.path.abspath(__file__))


class BuildNative(build_py):
    def run(self):
        build = os.environ.get("ROTLEAP_BUILD_DIR")
        if not build:
            build = os.path.join(HERE, "build-python")
            args = ["cmake", "-S", HERE, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DROTLEAP_TESTS=OFF"]
            if shutil.which("ccache"):
                args.append("-DCMAKE_C_COMPILER_LAUNCHER=ccache")
            args += shlex.split(os.environ.get("ROTLEAP_CMAKE_ARGS", ""))
            subprocess.check_call(args)
        jobs = str(os.cpu_count() or 1)
        subprocess.check_call(["cmake", "--build", build, "--target", "rotleap_py", "-j", jobs])
        super().run()
        dest = os.path.join(self.build_lib, "rotleap")
        os.makedirs(dest, exist_ok=True)
        shutil.copy2(os.path.join(build, "_rotleap_native.so"), os.path.join(dest, "_rotleap_native.so"))


class BinaryDistribution(Distribution):
    """A platform wheel: the package holds a native module."""

    def has_ext_modules(self):
        return True


# setuptools' own build folder apart from CMake's build/ (the README's build folder)
setup(package_dir={"": "python"}, packages=["rotleap"], cmdclass={"build_py": BuildNative},
      distclass=BinaryDistribution, exclude_package_data={"rotleap": ["*.c"]},
      options={"build": {"build_base": os.path.join("build-python", "setuptools")}})
