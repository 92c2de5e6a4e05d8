"""lumis from Python: environment maps, samplers, light sets, photometric files, sequences,
image metrics and the renderer over numpy arrays, through the lumis C libraries (docs/python.md)."""

from ._lib import (FORMAT_ERRORS, Error, FormatError, InvalidArgumentError, OpenError,
                   OutOfMemoryError, ReadError, UnsupportedError, Warning, WriteError, ffi, lib)
from ._api import (LIGHT_DTYPE, LIGHT_KINDS, SEQUENCES, LightSet, Map, Photometric, Sampler,
                   compare, delta_e, errors, flip, light_methods, lights, read_image, read_map,
                   read_photometric, sampler_methods, sequence, uniform, write_image)
from ._bench import BenchError, BenchRecords, bench, read_results as read_bench
from ._render import Fixture, photometric_orient, render, render_sequence, scenes

globals().update(FORMAT_ERRORS)  # lumis.TruncatedError, lumis.BadMagicError, ...

__version__ = ffi.string(lib.lumis_version()).decode()

__all__ = ["Error", "FormatError", "InvalidArgumentError", "OpenError", "OutOfMemoryError",
           "ReadError", "UnsupportedError", "Warning", "WriteError", "LIGHT_DTYPE", "LIGHT_KINDS",
           "SEQUENCES", "BenchError", "BenchRecords", "Fixture", "bench", "read_bench", "LightSet", "Map", "Photometric", "Sampler", "compare", "delta_e",
           "errors", "flip", "light_methods", "lights", "read_image", "read_map",
           "photometric_orient", "read_photometric", "render", "render_sequence", "sampler_methods", "scenes", "sequence", "uniform",
           "write_image",
           "__version__", *sorted(FORMAT_ERRORS)]
