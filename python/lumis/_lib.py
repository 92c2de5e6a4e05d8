"""Loading liblumis and liblumis-io through cffi's ABI mode, the error sink, and the checks
on numpy arguments that every binding shares."""

import os
import warnings

import numpy as np
from cffi import FFI

from ._cdefs import CDEFS, IO_CDEFS, RENDER_CDEFS

ffi = FFI()
ffi.cdef(CDEFS)
ffi.cdef(IO_CDEFS)
ffi.cdef(RENDER_CDEFS)

_HERE = os.path.dirname(os.path.abspath(__file__))
_SONAMES = ("liblumis.so.0", "liblumis-io.so.0")
_RENDER_SONAME = "liblumis-render.so.0"  # optional: lumis.render needs it

# The libraries stay loaded until the process ends, as libraries a program links do.  cffi
# closes what ffi.dlopen opened when its lib object is freed, which the interpreter does at
# exit while clearing modules; that unmapped liblumis-render.so and with it libgomp, whose
# idle worker threads (the renderer's OpenMP pool) were still spinning in its code: 3-5 %
# of interpreters that rendered died of SIGSEGV at exit, every one with
# OMP_WAIT_POLICY=ACTIVE (a core shows the crashing worker's pc in no mapped library and
# the main thread in _PyModule_ClearDict), and every one that built a scene unless TBB
# (Embree's threads) was loaded by ctypes first, which never unloads it.  RTLD_NODELETE
# keeps them all mapped, so neither the wait policy nor the order of loading matters
# (tests/python/test_render.py, test_the_interpreter_exits_cleanly_after_a_render).
_DLFLAGS = ffi.RTLD_NOW | ffi.RTLD_NODELETE


def _dlopen(path):
    return ffi.dlopen(path, _DLFLAGS)


def _candidate_dirs():
    """Where the libraries are looked for, in order (docs/python.md, "Finding the
    libraries")."""
    env = os.environ.get("LUMIS_LIBRARY_PATH")
    if env:
        return [d for d in env.split(os.pathsep) if d], "LUMIS_LIBRARY_PATH"
    dirs = []
    try:  # written by `make install` / `cmake --install`: the libraries' folder
        from . import _install  # noqa: PLC0415

        dirs.append(os.path.normpath(os.path.join(_HERE, _install.LIBDIR_FROM_PACKAGE)))
    except ImportError:
        # the source tree's python/lumis: the build folder beside it (make, make run)
        dirs.append(os.path.normpath(os.path.join(_HERE, "..", "..", "build")))
    return dirs, None


def _load():
    dirs, forced = _candidate_dirs()
    tried = []
    for d in dirs:
        paths = [os.path.join(d, s) for s in _SONAMES]
        if all(os.path.exists(p) for p in paths):
            # liblumis first: liblumis-io's DT_NEEDED then finds it by its soname.
            return _dlopen(paths[0]), _dlopen(paths[1]), d
        tried.append(d)
    if forced:
        raise ImportError(
            "lumis: LUMIS_LIBRARY_PATH=%s holds no %s and %s (build them with `make` or "
            "`make install`)" % (os.environ["LUMIS_LIBRARY_PATH"], *_SONAMES))
    try:  # installed where the system's loader looks (ldconfig'd prefix)
        return _dlopen(_SONAMES[0]), _dlopen(_SONAMES[1]), None
    except OSError as e:
        raise ImportError(
            "lumis: cannot find %s and %s (looked in %s and the system's library path: %s). "
            "Build them (`make run` or `make`), install them (`make install`), or point "
            "LUMIS_LIBRARY_PATH at their folder." % (*_SONAMES, ", ".join(tried), e)) from e


lib, iolib, _libdir = _load()


def _load_render():
    """liblumis-render.so beside the other two (or from the system's loader), else None and
    the reason: the rest of the package works without it."""
    try:
        return _dlopen(os.path.join(_libdir, _RENDER_SONAME) if _libdir else _RENDER_SONAME), None
    except OSError as e:
        return None, str(e)


renderlib, render_missing = _load_render()


# ---- errors ------------------------------------------------------------------------------

class Error(Exception):
    """A failure the library reported: .status (the lumis_status code), .status_name (its
    short name, e.g. "truncated") and .message (the library's message, with context)."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = int(status)
        self.status_name = ffi.string(lib.lumis_status_name(status)).decode()
        self.message = message


class FormatError(Error):
    """A file that is not what its format says (every reader failure but open and read)."""


class InvalidArgumentError(Error, ValueError):
    pass


class OutOfMemoryError(Error, MemoryError):
    pass


class OpenError(Error, OSError):
    pass


class ReadError(Error, OSError):
    pass


class WriteError(Error, OSError):
    pass


class UnsupportedError(Error):
    pass


class Warning(UserWarning):  # noqa: A001 - lumis.Warning, as lumis.Error
    """A warning the library gave (a message with status ok), e.g. a uniform fallback."""


def _format_class(name, doc):
    return type(name, (FormatError,), {"__doc__": doc, "__module__": "lumis"})


_CLASSES = {
    lib.LUMIS_ERR_INVALID_ARGUMENT: InvalidArgumentError,
    lib.LUMIS_ERR_OUT_OF_MEMORY: OutOfMemoryError,
    lib.LUMIS_ERR_OPEN: OpenError,
    lib.LUMIS_ERR_READ: ReadError,
    lib.LUMIS_ERR_WRITE: WriteError,
    lib.LUMIS_ERR_UNSUPPORTED: UnsupportedError,
}
FORMAT_ERRORS = {}
for _code, _name in [(lib.LUMIS_ERR_EMPTY_FILE, "EmptyFileError"),
                     (lib.LUMIS_ERR_UNKNOWN_FORMAT, "UnknownFormatError"),
                     (lib.LUMIS_ERR_BAD_MAGIC, "BadMagicError"),
                     (lib.LUMIS_ERR_BAD_HEADER, "BadHeaderError"),
                     (lib.LUMIS_ERR_BAD_DIMENSIONS, "BadDimensionsError"),
                     (lib.LUMIS_ERR_TOO_LARGE, "TooLargeError"),
                     (lib.LUMIS_ERR_TRUNCATED, "TruncatedError"),
                     (lib.LUMIS_ERR_CORRUPT, "CorruptError"),
                     (lib.LUMIS_ERR_MISSING_CHANNELS, "MissingChannelsError")]:
    _cls = _format_class(_name, "status %s" % ffi.string(lib.lumis_status_name(_code)).decode())
    _CLASSES[_code] = _cls
    FORMAT_ERRORS[_name] = _cls
for _c in (Error, FormatError, InvalidArgumentError, OutOfMemoryError, OpenError, ReadError,
           WriteError, UnsupportedError, Warning):
    _c.__module__ = "lumis"


def error(status, message=None):
    """The exception for a status, with the library's message (or its default text)."""
    if message is None:
        message = ffi.string(lib.lumis_status_string(status)).decode()
    return _CLASSES.get(int(status), Error)(status, message)


def invalid(message):
    return InvalidArgumentError(lib.LUMIS_ERR_INVALID_ARGUMENT, message)


@ffi.callback("lumis_error_fn")
def _on_message(user, status, message):
    try:
        ffi.from_handle(user).append(
            (int(status), ffi.string(message).decode("utf-8", "replace") if message else ""))
    except Exception:  # noqa: BLE001 - never let an exception cross into C
        pass


class Sink:
    """One call's error sink: collects the library's messages, raises the failure with its
    message, and passes warnings (messages with status ok) on to Python's warnings."""

    def __init__(self):
        self.messages = []
        self._handle = ffi.new_handle(self.messages)
        self.c = ffi.new("lumis_error_sink *", {"fn": _on_message, "user": self._handle})

    @property
    def value(self):
        return self.c[0]

    def check(self, status, context=None):
        for st, msg in self.messages:
            if st == lib.LUMIS_OK:
                warnings.warn(msg, Warning, stacklevel=3)
        if status != lib.LUMIS_OK:
            msgs = [m for st, m in self.messages if st != lib.LUMIS_OK and m]
            text = "; ".join(msgs) if msgs else None
            if text is None:
                text = ffi.string(lib.lumis_status_string(status)).decode()
                if context:
                    text = "%s: %s" % (context, text)
            raise error(status, text)
        self.messages.clear()


def check(status, context):
    """For calls without a sink: the status's default text, after context."""
    if status != lib.LUMIS_OK:
        raise error(status, "%s: %s" % (context, ffi.string(lib.lumis_status_string(status)).decode()))


# ---- numpy arguments -------------------------------------------------------------------

def float_array(x, dtype, tail, name):
    """x as a C-contiguous array of dtype (float64 or float32) with shape (N,) + tail; a
    real floating array of another precision is converted, anything else is refused."""
    a = np.asarray(x)
    if a.dtype.kind != "f":
        raise invalid("%s: expected a floating-point array, got dtype %s" % (name, a.dtype))
    if a.ndim != 1 + len(tail) or tuple(a.shape[1:]) != tuple(tail):
        raise invalid("%s: expected shape (N, %s), got %s" % (
            name, ", ".join(str(t) for t in tail), tuple(a.shape)))
    return np.ascontiguousarray(a, dtype=dtype)


def image_array(x, name):
    """An H x W x 3 float32 image (row 0 the top), C-contiguous."""
    a = np.asarray(x)
    if a.dtype.kind != "f":
        raise invalid("%s: expected a floating-point H x W x 3 array, got dtype %s" % (name, a.dtype))
    if a.ndim != 3 or a.shape[2] != 3 or a.shape[0] < 1 or a.shape[1] < 1:
        raise invalid("%s: expected shape (H, W, 3) with H, W >= 1, got %s" % (name, tuple(a.shape)))
    return np.ascontiguousarray(a, dtype=np.float32)


def image_struct(a):
    """A lumis_image borrowing the pixels of an image_array (keep a alive while it is used)."""
    img = ffi.new("lumis_image *")
    img.width = a.shape[1]
    img.height = a.shape[0]
    img.pixels = ffi.cast("float *", ffi.from_buffer(a))
    return img


def cstr(s):
    return s.encode() if isinstance(s, str) else bytes(s)


def pystr(p):
    return ffi.string(p).decode("utf-8", "replace") if p != ffi.NULL else None


class Handle:
    """Owns one C handle: close() frees it (idempotent), as do `with` and the finalizer."""

    _destroy = None  # name of the C function that frees the handle

    def __init__(self, ptr, destroy):
        self._ptr = ptr
        self._destroy_fn = destroy

    @property
    def ptr(self):
        if self._ptr is None:
            raise invalid("%s: used after close()" % type(self).__name__)
        return self._ptr

    @property
    def closed(self):
        return self._ptr is None

    def close(self):
        p, self._ptr = self._ptr, None
        if p is not None:
            self._destroy_fn(p)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __del__(self):
        try:
            self.close()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass
