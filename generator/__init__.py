"""tensormass kernel generator: reference elements and laws to C++ kernels.

Run `python3 -m generator --help`; the stages are described in compiler.py."""
