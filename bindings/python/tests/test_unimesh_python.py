"""Tests of the ctypes binding (plain unittest).

    UNIMESH_LIBRARY=build/lib/libunimesh.so /usr/bin/python3 -m unittest -v \
        bindings/python/tests/test_unimesh_python.py

The signature table and the constants are compared with include/unimesh.h
itself (read by bindings/scripts/unimesh_header.py), so a function or value
added to the header fails here until the binding has it.
"""

import gc
import os
import pickle
import sys
import unittest
from ctypes import POINTER, c_char, c_char_p, c_double, c_int32, c_int64, c_void_p
from pathlib import Path

HERE = Path(__file__).resolve().parent
BINDINGS = HERE.parents[1]
sys.path.insert(0, str(BINDINGS / "python"))  # the package, when run without PYTHONPATH
sys.path.insert(0, str(BINDINGS / "scripts"))

import unimesh  # noqa: E402  (paths set just above)
import unimesh_header  # noqa: E402
from unimesh import Option, Status, UnimeshError, _arrays, _capi  # noqa: E402

HEADER_PATH = Path(os.environ.get("UNIMESH_HEADER", BINDINGS.parent / "include" / "unimesh.h"))
HEADER = unimesh_header.Header(HEADER_PATH)

try:
    import numpy
except ImportError:  # the binding works without it; only the array tests need it
    numpy = None


class SignatureTable(unittest.TestCase):
    """The one table of C signatures against the header."""

    # unimesh_header's categories of C types and the ctypes type each needs.
    SCALARS = {"int32": c_int32, "int64": c_int64, "double": c_double}

    def expected_ctype(self, ctype):
        kind = ctype.kind()
        if kind in self.SCALARS:
            return self.SCALARS[kind]
        if kind.endswith("*") and kind[:-1] in self.SCALARS:
            return POINTER(self.SCALARS[kind[:-1]])
        if kind == "string":
            # const char * is read by C; char * is a buffer C writes into.
            return c_char_p if ctype.const else POINTER(c_char)
        if kind in ("opaque", "handle"):
            return c_void_p
        if kind == "handle*":
            return POINTER(c_void_p)
        if kind == "callback":
            return _capi.CALLBACK_TYPES[ctype.base]
        if kind == "void":
            return None
        self.fail(f"no ctypes type for {ctype}")

    def test_table_covers_every_function_of_the_header(self):
        table = [name for name, _, _ in _capi.SIGNATURES]
        self.assertEqual(len(table), len(set(table)), "a function is listed twice")
        self.assertEqual(set(table) - set(HEADER.functions), set(), "not in the header")
        self.assertEqual(set(HEADER.functions) - set(table), set(), "missing from SIGNATURES")

    def test_table_types_match_the_header(self):
        for name, restype, argtypes in _capi.SIGNATURES:
            function = HEADER.functions[name]
            with self.subTest(function=name):
                self.assertIs(restype, self.expected_ctype(function.returns), "restype")
                self.assertEqual(len(argtypes), len(function.parameters), "argument count")
                for parameter, argtype in zip(function.parameters, argtypes):
                    self.assertIs(argtype, self.expected_ctype(parameter.type), parameter.name)

    def test_callback_types_match_the_header(self):
        self.assertEqual(set(_capi.CALLBACK_TYPES), set(HEADER.callbacks))
        for name, callback in HEADER.callbacks.items():
            ctype = _capi.CALLBACK_TYPES[name]
            with self.subTest(callback=name):
                self.assertIs(ctype._restype_, self.expected_ctype(callback.returns))
                self.assertEqual(ctype._argtypes_,
                                 tuple(self.expected_ctype(p.type) for p in callback.parameters))

    def test_loaded_library_has_every_function_and_the_table_was_applied(self):
        self.assertEqual(_capi.missing_functions, [])
        for name, restype, argtypes in _capi.SIGNATURES:
            bound = getattr(_capi.C, name)
            with self.subTest(function=name):
                self.assertIs(bound.restype, restype)
                self.assertEqual(tuple(bound.argtypes), tuple(argtypes))

    def test_namespace_holds_only_table_functions(self):
        # Anything else would be callable with ctypes' default int restype.
        self.assertEqual(set(vars(_capi.C)), {name for name, _, _ in _capi.SIGNATURES})

    def test_library_location(self):
        expected = os.environ.get("UNIMESH_LIBRARY")
        if not expected:
            self.skipTest("UNIMESH_LIBRARY is not set")
        self.assertEqual(unimesh.library_path, expected)


class Constants(unittest.TestCase):
    """Every constant of the header is in the binding with its value."""

    # Header prefix -> where the binding keeps those constants. Longest first:
    # UM_OPTION_TYPE_ must not be taken for an UM_OPT_ key.
    HOMES = (
        ("UM_OPTION_TYPE_", unimesh.OptionType),
        ("UM_ERROR_MODE_", unimesh.ErrorMode),
        ("UM_VERSION_", None),
        ("UM_OPT_", unimesh.Option),
        ("UM_LOG_", unimesh.LogLevel),
        ("UM_FEATURE_", unimesh.FeatureKind),
        ("UM_SIDE_", unimesh.Side),
        ("UM_MPAS_FILE_", unimesh.MpasFile),
        ("UM_MPAS_", unimesh.MpasType),
        ("UM_", unimesh.Status),
    )

    def binding_value(self, name):
        for prefix, home in self.HOMES:
            if name.startswith(prefix):
                if home is None:  # module constants keep VERSION_
                    return getattr(unimesh, name[len("UM_"):])
                return home[name[len(prefix):]].value
        self.fail(f"{name}: no home in the binding")

    def test_every_header_constant_is_in_the_binding(self):
        constants = dict(HEADER.int_constants, **HEADER.string_constants)
        for name, value in constants.items():
            with self.subTest(constant=name):
                try:
                    self.assertEqual(self.binding_value(name), value)
                except (KeyError, AttributeError):
                    self.fail(f"{name} = {value} is missing from the binding")

    def test_no_binding_constant_the_header_lacks(self):
        for prefix, home in self.HOMES:
            if home is None:
                continue
            for member in home:
                with self.subTest(member=member):
                    self.assertEqual(HEADER.int_constants.get(prefix + member.name), member.value)


class Version(unittest.TestCase):
    def test_runtime_version_agrees_with_the_header(self):
        major, minor, patch = (HEADER.int_constants[f"UM_VERSION_{p}"]
                               for p in ("MAJOR", "MINOR", "PATCH"))
        self.assertEqual(unimesh.version(), (major, minor, patch))
        self.assertEqual(unimesh.version_number(), HEADER.int_constants["UM_VERSION_NUMBER"])
        self.assertEqual(unimesh.version_number(), major * 10000 + minor * 100 + patch)
        self.assertEqual(unimesh.version_string(), HEADER.string_constants["UM_VERSION_STRING"])
        self.assertEqual(unimesh.__version__, unimesh.version_string())


class StatusCodes(unittest.TestCase):
    def test_strings_and_bands(self):
        self.assertEqual(unimesh.status_string(Status.OK), "success")
        self.assertEqual(unimesh.status_string(12345), "unknown status")
        for status in Status:
            with self.subTest(status=status):
                self.assertNotEqual(unimesh.status_string(status), "unknown status")
                self.assertEqual(unimesh.status_class(status), status // 100 * 100)
        self.assertEqual(unimesh.status_class(-3), 900)

    def test_error_carries_status_and_message(self):
        error = UnimeshError(103, "bad value")
        self.assertIs(error.status, Status.ERR_INVALID_ARGUMENT)
        self.assertEqual(error.status_class, 100)
        self.assertEqual(str(error), "bad value [ERR_INVALID_ARGUMENT = 103]")
        self.assertEqual(UnimeshError(777, "x").status, 777)  # unknown status kept as int
        copy = pickle.loads(pickle.dumps(error))
        self.assertEqual((copy.status, copy.message), (error.status, error.message))


class ContextTests(unittest.TestCase):
    def setUp(self):
        self.ctx = unimesh.Context()
        self.addCleanup(self.ctx.close)

    def test_threads(self):
        self.ctx.threads = 3
        self.assertEqual(self.ctx.threads, 3)
        self.ctx.threads = 0
        self.assertGreaterEqual(self.ctx.threads, 1)
        with unimesh.Context(threads=2) as other:
            self.assertEqual(other.threads, 2)

    def test_memory_cap_beyond_32_bits(self):
        self.ctx.memory_cap = 8 * 1024 ** 3
        self.assertEqual(self.ctx.memory_cap, 8 * 1024 ** 3)
        self.ctx.memory_cap = 0
        self.assertEqual(self.ctx.memory_cap, 0)

    def test_bad_value_raises_with_the_context_message(self):
        self.ctx.threads = 2
        with self.assertRaises(UnimeshError) as caught:
            self.ctx.threads = -2
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
        self.assertIn("n_threads = -2", caught.exception.message)
        self.assertEqual(self.ctx.threads, 2, "a failed call changes nothing")

    def test_each_exception_carries_its_own_message(self):
        # The context keeps only its first error; the binding moves it into
        # the exception, so a second failure is not reported with the first
        # one's message.
        with self.assertRaises(UnimeshError):
            self.ctx.threads = 5000
        self.assertEqual(self.ctx.last_error, "")
        self.assertEqual(self.ctx.last_status, Status.OK)
        with self.assertRaises(UnimeshError) as caught:
            self.ctx.memory_cap = -1
        self.assertIn("bytes = -1", caught.exception.message)
        self.assertNotIn("5000", caught.exception.message)

    def test_errors_of_raw_calls_stay_readable(self):
        status = _capi.C.um_context_set_threads(self.ctx._handle, -7)
        self.assertEqual(status, Status.ERR_INVALID_ARGUMENT)
        self.assertIn("n_threads = -7", self.ctx.last_error)
        self.assertEqual(self.ctx.last_status, Status.ERR_INVALID_ARGUMENT)
        self.ctx.clear_error()
        self.assertEqual(self.ctx.last_error, "")

    def test_an_older_error_of_another_status_is_not_reused(self):
        _capi.C.um_context_set_threads(self.ctx._handle, -7)  # kept, not cleared
        with self.assertRaises(UnimeshError) as caught:
            with unimesh.Options(self.ctx) as opts:
                opts.set_int(Option.REFINE_ALPHA, 1)
        self.assertEqual(caught.exception.status, Status.ERR_OPTION_TYPE)
        self.assertNotIn("n_threads", caught.exception.message)

    def test_close_and_closed_use(self):
        ctx = unimesh.Context()
        self.assertFalse(ctx.closed)
        ctx.close()
        ctx.close()  # twice is fine
        self.assertTrue(ctx.closed)
        with self.assertRaises(UnimeshError) as caught:
            ctx.threads = 1
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_HANDLE)
        self.assertIn("closed", repr(ctx))

    def test_garbage_collection_closes(self):
        ctx = unimesh.Context()
        ctx.set_log(lambda level, message: None)  # must not keep it alive
        handle = ctx._handle
        del ctx
        gc.collect()
        # A destroyed handle is no longer live: C answers with a status.
        self.assertEqual(_capi.C.um_context_set_threads(handle, 1), Status.ERR_INVALID_HANDLE)

    def test_log_callback_sees_errors(self):
        seen = []
        self.ctx.set_log(lambda level, message: seen.append((level, message)),
                         unimesh.LogLevel.ERROR)
        with self.assertRaises(UnimeshError):
            self.ctx.threads = -3
        self.assertEqual(len(seen), 1)
        self.assertIs(seen[0][0], unimesh.LogLevel.ERROR)
        self.assertIn("n_threads = -3", seen[0][1])
        self.ctx.set_log(None)
        with self.assertRaises(UnimeshError):
            self.ctx.threads = -4
        self.assertEqual(len(seen), 1, "removed callback not called")

    def test_exception_in_a_callback_reaches_the_caller(self):
        def failing_log(level, message):
            raise KeyError("from the log callback")
        self.ctx.set_log(failing_log)
        with self.assertRaises(KeyError):
            self.ctx.threads = -5
        self.ctx.threads = 2  # nothing left pending
        self.assertEqual(self.ctx.last_error, "")

    def test_progress_callback_reports_and_cancels(self):
        seen = []
        self.ctx.set_progress(lambda stage, fraction: seen.append((stage, fraction)) and False)
        h = unimesh.Spacing.constant(self.ctx, 1500.0)
        unimesh.Mesh.refine(self.ctx, h).optimise().close()
        stages = {stage.split()[0] for stage, _ in seen}
        self.assertTrue({"refine", "optimise"} <= stages, stages)
        self.assertTrue(all(0.0 <= fraction <= 1.0 for _, fraction in seen))
        # A true return cancels the call, which raises CANCELLED; None removes the callback.
        self.ctx.set_progress(lambda stage, fraction: stage == "optimise")
        mesh = unimesh.Mesh.refine(self.ctx, h)
        with self.assertRaises(UnimeshError) as caught:
            mesh.optimise()
        self.assertEqual(caught.exception.status, Status.CANCELLED)
        mesh.close()
        self.ctx.set_progress(None)
        unimesh.Mesh.refine(self.ctx, h).close()
        h.close()


class OptionsTests(unittest.TestCase):
    def setUp(self):
        self.ctx = unimesh.Context()
        self.addCleanup(self.ctx.close)
        self.opts = unimesh.Options(self.ctx)
        self.addCleanup(self.opts.close)

    def test_defaults_and_typed_access(self):
        self.assertEqual(self.opts.get_double(Option.SPHERE_RADIUS), 6371220.0)
        self.opts.set_double(Option.REFINE_ALPHA, 1.25)
        self.assertEqual(self.opts.get_double(Option.REFINE_ALPHA), 1.25)
        self.opts.set_int(Option.OPTIM_OUTER_ITERATIONS, 8)
        self.assertEqual(self.opts.get_int(Option.OPTIM_OUTER_ITERATIONS), 8)

    def test_access_by_name_and_by_type(self):
        self.opts["refine_rho"] = 1.5
        self.opts[Option.OPTIM_WEIGHTS] = 0
        self.assertEqual(self.opts["refine_rho"], 1.5)
        self.assertIsInstance(self.opts.get("optim_weights"), int)
        self.assertEqual(self.opts.get("optim_weights"), 0)
        with self.assertRaises(TypeError):
            self.opts["optim_weights"] = 0.5  # not silently truncated

    def test_keyword_and_string_settings(self):
        with unimesh.Options(self.ctx, "refine_alpha = 1.5;;", optim_outer_iterations=4,
                             optim_tolerance=1e-5, optim_weights=False) as opts:
            self.assertEqual(opts["refine_alpha"], 1.5)
            self.assertEqual(opts["optim_outer_iterations"], 4)
            self.assertEqual(opts["optim_tolerance"], 1e-5)
            self.assertEqual(opts["optim_weights"], 0)
            self.assertEqual(set(opts.to_dict()), {unimesh.option_name(k) for k in Option})
        self.opts.update({Option.REFINE_BETA: 0.25}, refine_rho=1.2)
        self.assertEqual((self.opts["refine_beta"], self.opts["refine_rho"]), (0.25, 1.2))

    def test_bad_value_raises_naming_the_option(self):
        self.opts["refine_alpha"] = 1.25
        with self.assertRaises(UnimeshError) as caught:
            self.opts["refine_alpha"] = 7.0
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
        self.assertIn("refine_alpha", caught.exception.message)
        self.assertIn("refine_alpha", str(caught.exception))
        self.assertEqual(self.opts["refine_alpha"], 1.25, "a failed set changes nothing")
        with self.assertRaises(UnimeshError) as caught:
            self.opts.set_double(Option.OPTIM_TOLERANCE, float("nan"))
        self.assertIn("optim_tolerance", caught.exception.message)

    def test_wrong_type_and_unknown_keys(self):
        with self.assertRaises(UnimeshError) as caught:
            self.opts.set_int(Option.REFINE_ALPHA, 1)
        self.assertEqual(caught.exception.status, Status.ERR_OPTION_TYPE)
        self.assertIn("refine_alpha", caught.exception.message)
        with self.assertRaises(UnimeshError) as caught:
            self.opts.set_double(9999, 1.0)
        self.assertEqual(caught.exception.status, Status.ERR_UNKNOWN_OPTION)
        self.assertIn("9999", caught.exception.message)
        with self.assertRaises(UnimeshError) as caught:
            self.opts["no_such_option"] = 1
        self.assertEqual(caught.exception.status, Status.ERR_UNKNOWN_OPTION)
        self.assertIn("no_such_option", caught.exception.message)

    def test_several_settings_are_all_or_nothing(self):
        with self.assertRaises(UnimeshError) as caught:
            self.opts.update(optim_outer_iterations=3, refine_rho=0.5)
        self.assertIn("refine_rho", caught.exception.message)
        self.assertEqual(self.opts["optim_outer_iterations"], 20)
        with self.assertRaises(UnimeshError) as caught:
            unimesh.Options(self.ctx, refine_beta=2.0)
        self.assertIn("refine_beta", caught.exception.message)

    def test_options_outlive_their_context(self):
        ctx = unimesh.Context()
        opts = unimesh.Options(ctx)
        ctx.close()
        opts["refine_rho"] = 1.5
        self.assertEqual(opts["refine_rho"], 1.5)
        with self.assertRaises(UnimeshError) as caught:
            opts["refine_rho"] = 0.0
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
        opts.close()
        with self.assertRaises(UnimeshError):
            opts["refine_rho"] = 1.5
        with self.assertRaises(UnimeshError):
            unimesh.Options(ctx)


class OptionTable(unittest.TestCase):
    def test_each_key_names_its_option_in_c(self):
        # The strongest run-time check that the keys were transcribed right.
        for key in Option:
            with self.subTest(key=key):
                name = unimesh.option_name(key)
                self.assertEqual(name, key.name.lower())
                self.assertIs(unimesh.option_key(name), key)
                info = unimesh.option_info(key)
                self.assertIn(info.type, tuple(unimesh.OptionType))
                self.assertLessEqual(info.min, info.default)
                self.assertLessEqual(info.default, info.max)

    def test_types_and_unknowns(self):
        self.assertIs(unimesh.option_info("optim_weights").type, unimesh.OptionType.INT)
        self.assertEqual(unimesh.option_info(Option.REFINE_ALPHA).default, 4.0 / 3.0)
        with self.assertRaises(UnimeshError) as caught:
            unimesh.option_key("no_such_option")
        self.assertEqual(caught.exception.status, Status.ERR_UNKNOWN_OPTION)
        self.assertIn("no_such_option", caught.exception.message)
        with self.assertRaises(UnimeshError):
            unimesh.option_name(4242)


@unittest.skipIf(numpy is None, "numpy is not installed")
class ArrayHelpers(unittest.TestCase):
    """The numpy helpers the array-taking functions are built on."""

    def test_input_array_copies_only_when_needed(self):
        good = numpy.arange(6, dtype=numpy.float64).reshape(2, 3)
        self.assertIs(_arrays.input_array(good, c_double, (-1, 3)), good)
        strided = numpy.arange(12.0).reshape(2, 6)[:, ::2]
        converted = _arrays.input_array(strided, c_double, (-1, 3))
        self.assertTrue(converted.flags.c_contiguous)
        numpy.testing.assert_array_equal(converted, strided)
        as_int = _arrays.input_array([1, 2, 3], c_int32)
        self.assertEqual(as_int.dtype, numpy.int32)
        with self.assertRaisesRegex(ValueError, r"xyz must have shape \(n, 3\)"):
            _arrays.input_array(numpy.zeros((4, 2)), c_double, (-1, 3), name="xyz")

    def test_input_array_refuses_what_would_change_values(self):
        for bad in (numpy.zeros(3, complex), numpy.array(["1", "2"]), [1.0, None],
                    numpy.array([True, False])):
            with self.subTest(values=bad):
                with self.assertRaisesRegex(TypeError, "x must hold real numbers"):
                    _arrays.input_array(bad, c_double, name="x")
        with self.assertRaisesRegex(TypeError, "k must hold integers, not float64"):
            _arrays.input_array([1.5, 2.0], c_int32, name="k")  # not truncated
        with self.assertRaisesRegex(ValueError, "k holds values outside int32"):
            _arrays.input_array(numpy.array([0, 2 ** 31]), c_int32, name="k")  # not wrapped
        in_range = _arrays.input_array(numpy.array([0, 2 ** 31 - 1], dtype=numpy.uint64), c_int32)
        self.assertEqual((in_range.dtype, in_range[1]), (numpy.int32, 2 ** 31 - 1))
        single = _arrays.input_array(numpy.arange(4, dtype=numpy.float32), c_double, (4,))
        self.assertEqual(single.dtype, numpy.float64)
        with self.assertRaisesRegex(ValueError, r"w must have shape \(5\), not \(4,\)"):
            _arrays.input_array(numpy.zeros(4), c_double, (5,), name="w")

    def test_output_array_is_filled_in_place(self):
        out = _arrays.output_array(c_int32, (2, 3))
        self.assertEqual((out.dtype, out.shape), (numpy.int32, (2, 3)))
        pointer = _arrays.pointer(out, c_int32)
        for i in range(_arrays.capacity(out)):
            pointer[i] = 10 * i  # as C would write it
        numpy.testing.assert_array_equal(out.ravel(), numpy.arange(6) * 10)
        self.assertIsNone(_arrays.pointer(None, c_double))
        self.assertEqual(_arrays.capacity(None), 0)

    def test_unusable_out_arrays_are_refused(self):
        with self.assertRaises(TypeError):
            _arrays.output_array(c_int32, (3,), out=numpy.zeros(3, dtype=numpy.int64))
        with self.assertRaises(ValueError):
            _arrays.output_array(c_double, (3,), out=numpy.zeros(6)[::2])
        with self.assertRaises(ValueError):
            _arrays.output_array(c_double, (4,), out=numpy.zeros(3))
        with self.assertRaises(TypeError):
            _arrays.pointer(numpy.zeros(3, dtype=numpy.float32), c_double)
        out = numpy.zeros((5, 3))
        self.assertIs(_arrays.output_array(c_double, (5, 3), out=out), out)


if __name__ == "__main__":
    unittest.main()
