"""The one compiled part of softarm: the recorder's frame encoder (softarm/record/_frames.c).

Optional: without a C compiler the install still succeeds, and recordings are written by the Python
encoder, byte for byte the same, only slower. Everything else is configured in pyproject.toml.
"""

from setuptools import Extension, setup

setup(ext_modules=[Extension("softarm.record._frames", ["softarm/record/_frames.c"], optional=True,
                             extra_compile_args=["-O3", "-ffp-contract=off"])])
