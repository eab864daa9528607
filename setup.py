"""The compiled parts of softarm: the recorder's frame encoder (softarm/record/_frames.c) and the reader's node
parser (softarm/record/_nodes.c).

Optional: without a C compiler the install still succeeds; recordings are then written by the Python encoder,
byte for byte the same, and read by orjson, to the same values, only slower. Everything else is configured in
pyproject.toml.
"""

from setuptools import Extension, setup

setup(ext_modules=[Extension("softarm.record._frames", ["softarm/record/_frames.c"], optional=True,
                             extra_compile_args=["-O3", "-ffp-contract=off"]),
                   Extension("softarm.record._nodes", ["softarm/record/_nodes.c"], optional=True,
                             extra_compile_args=["-O3"])])
