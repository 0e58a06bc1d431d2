"""Python binding of libunimesh (ctypes; numpy for array arguments).

    import unimesh

    with unimesh.Context(threads=4) as ctx:
        with unimesh.Options(ctx, refine_alpha=1.3, optim_outer_iterations=8) as opts:
            opts["refine_rho"] = 1.1
            print(opts["refine_alpha"], opts.get(unimesh.Option.OPTIM_WEIGHTS))

Every failure raises UnimeshError(status, message). The message is the one
the context recorded (it names the argument and the value); it is moved into
the exception, i.e. the context's kept error is cleared, so every exception
carries its own message rather than the first one of the context's life.

The library is found through $UNIMESH_LIBRARY, else next to this package or in
the source tree's build/lib, else on the system search path (see _capi.py).
Objects are released by close() or a with-block; garbage collection closes
them as a last resort.
"""

import enum
import operator
import weakref
from collections import namedtuple
from ctypes import byref, c_double, c_int32, c_int64, c_void_p, create_string_buffer

from ._capi import C, LOG_FN, PROGRESS_FN, library_path, missing_functions

__all__ = [
    "VERSION_MAJOR", "VERSION_MINOR", "VERSION_PATCH", "VERSION_NUMBER", "VERSION_STRING",
    "Status", "Option", "OptionType", "LogLevel", "ErrorMode", "OptionInfo", "UnimeshError",
    "Context", "Options", "version", "version_number", "version_string", "status_string",
    "status_class", "option_info", "option_name", "option_key", "library_path",
    "missing_functions",
]

# ----------------------------------------------------------------- constants
# Transcribed from include/unimesh.h; the tests compare them with it.

VERSION_MAJOR = 0
VERSION_MINOR = 1
VERSION_PATCH = 0
VERSION_NUMBER = VERSION_MAJOR * 10000 + VERSION_MINOR * 100 + VERSION_PATCH
VERSION_STRING = "0.1.0"
__version__ = VERSION_STRING


class Status(enum.IntEnum):
    """um_status: 0 ok; bands 100 usage, 200 input data, 300 numerical,
    400 resources, 500 I/O, 600 interrupted, 900 internal."""
    OK = 0
    ERR_USAGE = 100
    ERR_NULL_ARGUMENT = 101
    ERR_INVALID_HANDLE = 102
    ERR_INVALID_ARGUMENT = 103
    ERR_UNKNOWN_OPTION = 104
    ERR_OPTION_TYPE = 105
    ERR_BUFFER_TOO_SMALL = 106
    ERR_WRONG_ORDER = 107
    ERR_INPUT = 200
    ERR_NONFINITE_INPUT = 201
    ERR_COORDINATE_RANGE = 202
    ERR_DUPLICATE_POINTS = 203
    ERR_TOO_FEW_POINTS = 204
    ERR_DEGENERATE_INPUT = 205
    ERR_NUMERICAL = 300
    ERR_OUT_OF_MEMORY = 400
    ERR_MEMORY_CAP = 401
    ERR_LIMIT = 402
    ERR_IO = 500
    ERR_FILE_FORMAT = 501
    CANCELLED = 600
    ERR_INTERNAL = 900


class Option(enum.IntEnum):
    """um_option keys (UM_OPT_*)."""
    SPHERE_RADIUS = 1
    REFINE_ALPHA = 100
    REFINE_BETA = 101
    REFINE_RHO = 102
    REFINE_TOPOLOGY_CHECK = 103
    OPTIM_OUTER_ITERATIONS = 200
    OPTIM_INNER_ITERATIONS = 201
    OPTIM_TOLERANCE = 202
    OPTIM_WEIGHTS = 203
    OPTIM_FIX_BOUNDARY = 204
    OPTIM_COLLAPSE_RATIO = 205
    OPTIM_SPLIT_RATIO = 206


class OptionType(enum.IntEnum):
    INT = 1
    REAL = 2


class LogLevel(enum.IntEnum):
    DEBUG = 10
    INFO = 20
    WARNING = 30
    ERROR = 40


class ErrorMode(enum.IntEnum):
    """Kept for completeness: this binding reports errors by exceptions, so
    it never switches a context to ABORT mode."""
    RETURN = 0
    ABORT = 1


OptionInfo = namedtuple("OptionInfo", "type min max default")


def _enum_or_int(enum_type, value):
    """A member when the value is known, else the plain int (a newer library
    may return values this binding predates)."""
    try:
        return enum_type(value)
    except ValueError:
        return int(value)


def _text(raw):
    return raw.decode("utf-8", "replace") if raw else ""


# -------------------------------------------------------------------- errors

class UnimeshError(Exception):
    """A failed libunimesh call: .status (a Status when known) and .message."""

    def __init__(self, status, message):
        super().__init__(status, message)  # args as given, so the error pickles
        self.status = _enum_or_int(Status, status)
        self.message = message

    @property
    def status_class(self):
        """The band: 0, 100, 200, ..., 900."""
        return status_class(self.status)

    def __str__(self):
        name = self.status.name if isinstance(self.status, Status) else "status"
        return f"{self.message} [{name} = {int(self.status)}]"


def _raise_for(status, context=None, what=None):
    """Raises UnimeshError unless status is UM_OK. The message is the one
    `context` recorded for this status (taken out of it), else the status
    text prefixed by `what` (calls without a context have nowhere to keep a
    message)."""
    if status == Status.OK:
        return
    message = context._take_error(status) if context is not None else ""
    if not message:
        message = status_string(status)
        if what:
            message = f"{what}: {message}"
    raise UnimeshError(status, message)


def _copy_out(function, *leading, what, context=None):
    """A string from a C function with the (buf, capacity, needed) protocol:
    ask for the length, then copy into a buffer of exactly that size."""
    needed = c_int64(0)
    status = function(*leading, None, 0, byref(needed))
    if status not in (Status.OK, Status.ERR_BUFFER_TOO_SMALL):
        _raise_for(status, context, what)
    buffer = create_string_buffer(max(needed.value, 1))
    _raise_for(function(*leading, buffer, len(buffer), byref(needed)), context, what)
    return _text(buffer.value)


# ---------------------------------------------------------- version, status

def version():
    """(major, minor, patch) of the loaded library."""
    parts = c_int32(), c_int32(), c_int32()
    C.um_version(*(byref(p) for p in parts))
    return tuple(p.value for p in parts)


def version_number():
    """MAJOR*10000 + MINOR*100 + PATCH of the loaded library."""
    return C.um_version_number()


def version_string():
    return _text(C.um_version_string())


def status_string(status):
    """A short description of a status ("unknown status" if not one)."""
    return _text(C.um_status_string(int(status)))


def status_class(status):
    """The band of a status: 0, 100, 200, ..., 900."""
    return C.um_status_class(int(status))


# The signatures of a library with another major version may differ from the
# table: refuse it rather than call it wrongly.
if version()[0] != VERSION_MAJOR:
    raise ImportError(f"unimesh: {library_path} is version {version_string()}, this binding "
                      f"needs major version {VERSION_MAJOR}")


# ------------------------------------------------------------- option table

def option_key(name):
    """The Option of a name as used in "name=value" strings."""
    key = c_int32(0)
    _raise_for(C.um_option_key(str(name).encode(), byref(key)), what=f"option_key({name!r})")
    return _enum_or_int(Option, key.value)


def _key(key):
    """An option key from an Option, an int or a name."""
    return option_key(key) if isinstance(key, str) else _enum_or_int(Option, operator.index(key))


def option_name(key):
    """The name of an option key, as used in "name=value" strings."""
    key = _key(key)
    return _copy_out(C.um_option_name, int(key), what=f"option_name({key!r})")


def option_info(key):
    """OptionInfo(type, min, max, default) of an option; bounds are inclusive."""
    key = _key(key)
    kind, low, high, default = c_int32(), c_double(), c_double(), c_double()
    _raise_for(C.um_option_info(int(key), byref(kind), byref(low), byref(high), byref(default)),
               what=f"option_info({key!r})")
    kind = _enum_or_int(OptionType, kind.value)
    if kind == OptionType.INT:
        return OptionInfo(kind, int(low.value), int(high.value), int(default.value))
    return OptionInfo(kind, low.value, high.value, default.value)


# ------------------------------------------------------------------ handles

class _Handle:
    """What every wrapped object shares: the C pointer, close() with its
    destroy function, the with-statement, and a closed check."""

    _destroy = None  # the C destroy function, set by each subclass
    _ptr = None

    @property
    def closed(self):
        return self._ptr is None

    @property
    def _handle(self):
        if self._ptr is None:
            raise UnimeshError(Status.ERR_INVALID_HANDLE, f"the {type(self).__name__} is closed")
        return self._ptr

    def close(self):
        """Destroys the C object; closing twice is fine."""
        ptr, self._ptr = self._ptr, None
        if ptr is not None:
            type(self)._destroy(ptr)

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()

    def __del__(self):
        # Last resort only: at interpreter exit the module may be half gone.
        try:
            self.close()
        except Exception:
            pass


class Context(_Handle):
    """A um_context: thread count, memory cap, error state and callbacks.

    One thread at a time may use a context and the objects made from it.
    """

    _destroy = staticmethod(C.um_context_destroy)

    def __init__(self, threads=None, memory_cap=None):
        # Callback objects must live as long as C may call them.
        self._callbacks = {}
        self._callback_error = None
        ptr = c_void_p()
        _raise_for(C.um_context_create(byref(ptr)), what="um_context_create")
        self._ptr = ptr.value
        try:
            if threads is not None:
                self.threads = threads
            if memory_cap is not None:
                self.memory_cap = memory_cap
        except BaseException:
            self.close()
            raise

    def close(self):
        super().close()
        self._callbacks.clear()

    def _check(self, status, what=None):
        """Raises for a failed call on this context; an exception raised by a
        Python callback during the call wins, being the real cause."""
        pending, self._callback_error = self._callback_error, None
        if pending is not None:
            if status != Status.OK:
                self._take_error(status)  # the C side only saw a cancellation
            raise pending
        _raise_for(status, self, what)

    def _take_error(self, status):
        """The kept message if it belongs to `status`, then cleared ("" if the
        context is closed or holds an older error of another status)."""
        if self._ptr is None or C.um_context_last_status(self._ptr) != int(status):
            return ""
        message = self.last_error
        C.um_context_clear_error(self._ptr)
        return message

    @property
    def threads(self):
        """Threads for parallel work; setting 0 means all cores (reading gives
        the resolved count)."""
        n = c_int32(0)
        self._check(C.um_context_get_threads(self._handle, byref(n)))
        return n.value

    @threads.setter
    def threads(self, n):
        self._check(C.um_context_set_threads(self._handle, operator.index(n)))

    @property
    def memory_cap(self):
        """Cap in bytes on the large allocations of this context's work (0 = none)."""
        cap = c_int64(0)
        self._check(C.um_context_get_memory_cap(self._handle, byref(cap)))
        return cap.value

    @memory_cap.setter
    def memory_cap(self, n_bytes):
        self._check(C.um_context_set_memory_cap(self._handle, operator.index(n_bytes)))

    @property
    def last_error(self):
        """The kept error message ("" when none). Failed calls made through
        this binding raise and clear it; it is only set by raw C calls."""
        return _copy_out(C.um_context_copy_last_error, self._handle,
                         what="um_context_copy_last_error")

    @property
    def last_status(self):
        return _enum_or_int(Status, C.um_context_last_status(self._handle))

    def clear_error(self):
        self._check(C.um_context_clear_error(self._handle))

    def set_log(self, callback, min_level=LogLevel.WARNING):
        """callback(level: LogLevel, message: str) for messages at min_level
        or above, called on this thread; None removes it. An exception in the
        callback is raised by the call that logged."""
        c_function = LOG_FN()  # NULL: ctypes wants a function-pointer instance, not None
        if callback is not None:
            owner = weakref.ref(self)  # no cycle through the callback

            def trampoline(_user_data, level, message):
                try:
                    callback(_enum_or_int(LogLevel, level), _text(message))
                except BaseException as error:  # must not unwind through C
                    _record_callback_error(owner, error)
            c_function = LOG_FN(trampoline)
        self._check(C.um_context_set_log(self._handle, c_function, None, int(min_level)))
        self._callbacks["log"] = c_function

    def set_progress(self, callback):
        """callback(stage: str, fraction: float) during long calls; a true
        return value cancels the call (it raises UnimeshError CANCELLED).
        An exception in the callback cancels too, and is what the call raises.
        None removes it."""
        c_function = PROGRESS_FN()  # NULL
        if callback is not None:
            owner = weakref.ref(self)

            def trampoline(_user_data, stage, fraction):
                try:
                    return 1 if callback(_text(stage), fraction) else 0
                except BaseException as error:
                    _record_callback_error(owner, error)
                    return 1
            c_function = PROGRESS_FN(trampoline)
        self._check(C.um_context_set_progress(self._handle, c_function, None))
        self._callbacks["progress"] = c_function

    def __repr__(self):
        return "<unimesh.Context closed>" if self.closed else \
            f"<unimesh.Context threads={self.threads}>"


def _record_callback_error(owner, error):
    context = owner()
    if context is not None and context._callback_error is None:
        context._callback_error = error


class Options(_Handle):
    """A um_options object: typed, bounds-checked settings.

        opts = Options(ctx, "refine_alpha=1.3", optim_outer_iterations=8)
        opts["refine_rho"] = 1.1          # by name
        opts.set(Option.OPTIM_WEIGHTS, 0)  # or by key
        opts.get("refine_alpha")          # int or float by the option's type

    Keyword and string settings are all-or-nothing. The options stay usable
    after their context is closed (errors then carry only the status text).
    """

    _destroy = staticmethod(C.um_options_destroy)

    def __init__(self, context, assignments=None, **values):
        self._context = context
        ptr = c_void_p()
        context._check(C.um_options_create(context._handle, byref(ptr)))
        self._ptr = ptr.value
        try:
            if assignments:
                self.set_string(assignments)
            if values:
                self.update(values)
        except BaseException:
            self.close()
            raise

    def _check(self, status):
        self._context._check(status)

    # Typed access, as in C.
    def set_double(self, key, value):
        self._check(C.um_options_set_double(self._handle, int(_key(key)), float(value)))

    def set_int(self, key, value):
        self._check(C.um_options_set_int(self._handle, int(_key(key)), operator.index(value)))

    def get_double(self, key):
        value = c_double(0)
        self._check(C.um_options_get_double(self._handle, int(_key(key)), byref(value)))
        return value.value

    def get_int(self, key):
        value = c_int64(0)
        self._check(C.um_options_get_int(self._handle, int(_key(key)), byref(value)))
        return value.value

    def set_string(self, assignments):
        """Sets options from "name=value;name=value" (all-or-nothing)."""
        self._check(C.um_options_set_string(self._handle, str(assignments).encode()))

    # Access by the option's own type.
    def set(self, key, value):
        key = _key(key)
        if option_info(key).type == OptionType.INT:
            self.set_int(key, value)  # a float is refused, not truncated
        else:
            self.set_double(key, value)

    def get(self, key):
        key = _key(key)
        return self.get_int(key) if option_info(key).type == OptionType.INT \
            else self.get_double(key)

    __setitem__ = set
    __getitem__ = get

    def update(self, values=(), **more):
        """Sets several options by name or key, all-or-nothing (one
        um_options_set_string call)."""
        items = list(dict(values).items()) + list(more.items())
        self.set_string(";".join(f"{_name_of(k)}={_format_value(v)}" for k, v in items))

    def to_dict(self):
        """{name: value} of every option this binding knows."""
        return {option_name(key): self.get(key) for key in Option}

    def __repr__(self):
        return "<unimesh.Options closed>" if self.closed else f"<unimesh.Options {self.to_dict()}>"


def _name_of(key):
    return key if isinstance(key, str) else option_name(key)


def _format_value(value):
    """A value as C parses it: integers as digits, reals round-tripping."""
    if isinstance(value, bool):
        return "1" if value else "0"
    try:
        return str(operator.index(value))  # int and numpy integers
    except TypeError:
        return repr(float(value))  # shortest text that reads back the same double
