"""A small reader of include/unimesh.h for the binding tests.

Both bindings mirror the header by hand (a Fortran module, a ctypes table), so
both need the same independent view of what the header declares: its integer
constants (enumerators and #defines), its string #defines and every UM_API
function with its return and parameter types. This module is that one view.

It only has to understand the header's own regular style (one declaration per
statement, pinned enumerators, simple macro arithmetic); anything it does not
recognise raises, so a new construct in the header fails the tests loudly
instead of being skipped.
"""

import re
from dataclasses import dataclass

_COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
_ENUM = re.compile(r"\benum\s*\{(.*?)\}", re.S)
_DEFINE = re.compile(r"^\s*#\s*define\s+(UM_\w+)[ \t]+(.+?)\s*$", re.M)
_FUNCTION = re.compile(r"\bUM_API\s+([^;(]*?)\b(um_\w+)\s*\(([^)]*)\)\s*;", re.S)
_CALLBACK = re.compile(r"\btypedef\s+([^;(]*?)\(\s*\*\s*(um_\w+)\s*\)\s*\(([^)]*)\)\s*;", re.S)
# Macros that are part of the header's machinery, not of the API.
_NOT_CONSTANTS = {"UM_API"}


@dataclass(frozen=True)
class CType:
    """A C type reduced to what an ABI binding has to match.

    base is the type name without qualifiers (e.g. "int32_t", "um_context",
    "char", "um_log_fn"); pointers is the number of '*'.
    """

    base: str
    pointers: int = 0
    const: bool = False

    def kind(self):
        """The binding-relevant category of the type (see the table below)."""
        scalar = _SCALAR_BASES.get(self.base)
        if self.pointers == 0:
            if self.base == "void":
                return "void"
            if self.base.endswith("_fn"):
                return "callback"
            if scalar:
                return scalar
        elif self.pointers == 1:
            if self.base == "char":
                return "string"
            if self.base == "void":
                return "opaque"
            if scalar:
                return scalar + "*"
            if self.base.startswith("um_"):
                return "handle"
        elif self.pointers == 2 and self.base.startswith("um_"):
            return "handle*"
        raise ValueError(f"unimesh_header: no binding category for C type {self}")


# typedefs of the header that are plain fixed-width integers on the ABI.
_SCALAR_BASES = {
    "int32_t": "int32",
    "um_status": "int32",
    "um_option": "int32",
    "int64_t": "int64",
    "double": "double",
}


@dataclass(frozen=True)
class Parameter:
    name: str
    type: CType


@dataclass(frozen=True)
class Function:
    name: str
    returns: CType
    parameters: tuple


def _function(name, returns, params):
    params = params.strip()
    parameters = () if params in ("", "void") else tuple(
        _parse_parameter(p) for p in params.split(","))
    return Function(name, _parse_type(returns), parameters)


def _parse_type(text):
    """'const um_context *' -> CType('um_context', 1, True)."""
    pointers = text.count("*")
    words = text.replace("*", " ").split()
    const = "const" in words
    words = [w for w in words if w != "const"]
    if len(words) != 1:
        raise ValueError(f"unimesh_header: cannot read C type '{text.strip()}'")
    return CType(words[0], pointers, const)


def _parse_parameter(text):
    match = re.fullmatch(r"\s*(.*?)\b(\w+)\s*", text, re.S)
    if not match or not match.group(1).strip():
        raise ValueError(f"unimesh_header: parameter '{text.strip()}' has no name")
    return Parameter(match.group(2), _parse_type(match.group(1)))


def evaluate(expression, known):
    """Integer value of a macro body made of literals, known names and + - * ( )."""
    def substitute(match):
        name = match.group(0)
        if name not in known:
            raise ValueError(f"unimesh_header: '{name}' used before it is defined")
        return f"({known[name]})"

    text = re.sub(r"\b[A-Za-z_]\w*\b", substitute, expression)
    # Division is left out on purpose: C truncates, Python's // floors.
    if not re.fullmatch(r"[\d\s+\-*()]+", text):
        raise ValueError(f"unimesh_header: cannot evaluate '{expression}'")
    return int(eval(text, {"__builtins__": {}}, {}))  # checked: digits and + - * ( ) only


class Header:
    """What unimesh.h declares: int_constants, string_constants, functions
    (the UM_API ones) and callbacks (the function-pointer typedefs), the last
    two as {name: Function}."""

    def __init__(self, path):
        with open(path, encoding="utf-8") as f:
            source = f.read()
        code = _COMMENT.sub(" ", source)
        self.int_constants = {}
        self.string_constants = {}
        self._read_enums(code)
        self._read_defines(code)
        # Preprocessor lines (the UM_API definitions themselves) are not declarations.
        declarations = re.sub(r"^\s*#.*$", " ", code, flags=re.M)
        self.functions = {f.name: f for f in self._read_functions(declarations)}
        self.callbacks = {name: _function(name, returns, params)
                          for returns, name, params in _CALLBACK.findall(declarations)}
        if len(self.callbacks) != len(re.findall(r"\btypedef[^;]*\(\s*\*", declarations)):
            raise ValueError("unimesh_header: some function-pointer typedefs were not understood")

    def _read_enums(self, code):
        for body in _ENUM.findall(code):
            for item in filter(None, (i.strip() for i in body.split(","))):
                name, eq, value = (part.strip() for part in item.partition("="))
                if not eq:
                    # The header pins every value; an implicit one is a bug there.
                    raise ValueError(f"unimesh_header: enumerator {name} has no pinned value")
                self._add_int(name, evaluate(value, self.int_constants))

    def _read_defines(self, code):
        for name, body in _DEFINE.findall(code):
            if name in _NOT_CONSTANTS:
                continue
            string = re.fullmatch(r'"([^"\\]*)"', body)
            if string:
                self.string_constants[name] = string.group(1)
            else:
                self._add_int(name, evaluate(body, self.int_constants))

    def _add_int(self, name, value):
        if name in self.int_constants:
            raise ValueError(f"unimesh_header: {name} defined twice")
        self.int_constants[name] = value

    @staticmethod
    def _read_functions(code):
        found = [_function(name, returns, params)
                 for returns, name, params in _FUNCTION.findall(code)]
        # Every declaration that mentions UM_API must have been understood.
        if len(found) != len(re.findall(r"\bUM_API\b", code)):
            raise ValueError("unimesh_header: some UM_API declarations were not understood")
        return found
