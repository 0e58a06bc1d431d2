#!/usr/bin/env python3
"""Checks the Fortran binding against include/unimesh.h.

No compiler compares a bind(c) interface with the C prototype it stands for:
a missing `value`, an int64 declared as int32 or a forgotten constant compiles
and then fails at run time (or silently passes garbage). This script reads
both sides and compares them:

  - every integer constant of the header (enumerators and #defines) is an
    integer(c_int32_t) parameter of unimesh_cint with the same value, and
    every string #define a character parameter with the same text; no
    UM_* parameter exists that the header lacks;
  - every UM_API function has exactly one bind(c, name="...") interface, with
    the header's parameter names in order and matching types: kind, `value`
    for pass-by-value, intent(in) for const pointers, intent(out/inout) for
    output pointers, and the right result (none for void);
  - every callback typedef (um_*_fn) has an abstract bind(c) interface of the
    same name and signature;
  - the friendly module re-exports every constant.

It understands the regular style unimesh_cint.F90 is written in (see the
comment at its top), not all of Fortran; what it cannot read is reported.

Usage: check_fortran_binding.py --header unimesh.h --cint unimesh_cint.F90
                                --module unimesh.F90
Exits 0 when everything matches, 1 with one line per problem otherwise.
"""

import argparse
import os
import re
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts"))
import unimesh_header  # noqa: E402  (path set just above)


# ----------------------------------------------------------------- Fortran text

def fortran_statements(path):
    """The file as logical statements: comments dropped, '&' lines joined."""
    with open(path, encoding="utf-8") as f:
        lines = [_strip_comment(line).strip() for line in f]
    statements, pending = [], ""
    for line in lines:
        if pending:
            line = line[1:].lstrip() if line.startswith("&") else line
        if line.endswith("&"):
            pending += line[:-1] + " "
            continue
        statement = (pending + line).strip()
        pending = ""
        if statement:
            statements.append(statement)
    return statements


def _strip_comment(line):
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return line[:i]
    return line


def split_top_level(text, separator=","):
    """Splits on separator outside parentheses and quotes."""
    parts, depth, quote, current = [], 0, None, ""
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        elif ch == separator and depth == 0:
            parts.append(current.strip())
            current = ""
            continue
        current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def normalise_type(spec):
    """'integer(kind=c_int32_t)' -> 'integer(c_int32_t)';
    'character(kind=c_char, len=1)' -> 'character(c_char)'."""
    spec = re.sub(r"\s+", "", spec.lower())
    spec = re.sub(r"kind=", "", spec)
    spec = re.sub(r",len=1\)", ")", spec)
    return spec


# ------------------------------------------------------------- declarations

class Declaration:
    """One dummy argument (or function result) of an interface."""

    def __init__(self, type_spec, attributes, array):
        self.type = normalise_type(type_spec)
        self.value = "value" in attributes
        self.optional = "optional" in attributes
        self.array = array or any(a.startswith("dimension") for a in attributes)
        intent = [a for a in attributes if a.startswith("intent")]
        self.intent = intent[0][len("intent("):-1] if intent else None


def parse_declaration(statement):
    """'integer(c_int32_t), intent(out) :: a, b(*)' -> {name: Declaration}."""
    left, _, right = statement.partition("::")
    pieces = split_top_level(left)
    attributes = [re.sub(r"\s+", "", a.lower()) for a in pieces[1:]]
    found = {}
    for entity in split_top_level(right):
        match = re.fullmatch(r"(\w+)\s*(\(.*\))?", entity)
        if not match:
            raise ValueError(f"cannot read declaration '{statement}'")
        found[match.group(1).lower()] = Declaration(pieces[0], attributes, bool(match.group(2)))
    return found


_TYPE_SPEC = r"(?:integer|real|character|type|logical|complex)\s*\([^)]*\)"
# A procedure statement with bind(c): with name="..." it is an interface to
# a C function; without, an abstract interface standing for a callback typedef
# (and then it carries the typedef's name).
_PROCEDURE = re.compile(
    rf"^(?:({_TYPE_SPEC})\s+)?(function|subroutine)\s+(\w+)\s*\(([^)]*)\)\s*"
    r"bind\s*\(\s*c\s*(?:,\s*name\s*=\s*[\"'](\w+)[\"']\s*)?\)\s*"
    r"(?:result\s*\(\s*(\w+)\s*\))?$",
    re.I)
_PARAMETER = re.compile(rf"^({_TYPE_SPEC})\s*,\s*parameter\s*::\s*(.+)$", re.I)


class Interface:
    def __init__(self, match):
        self.result_type = normalise_type(match.group(1)) if match.group(1) else None
        self.kind = match.group(2).lower()
        self.fortran_name = match.group(3)
        self.arguments = [a.strip().lower() for a in match.group(4).split(",") if a.strip()]
        self.c_name = match.group(5) or match.group(3).lower()
        self.is_callback = match.group(5) is None
        self.result_name = (match.group(6) or match.group(3)).lower()
        self.declarations = {}


def read_cint(path):
    """Int parameters, string parameters, interfaces by C name, callback
    interfaces by typedef name and duplicated names, read from unimesh_cint."""
    ints, strings, interfaces, callbacks = {}, {}, {}, {}
    duplicates = []
    current = None
    for statement in fortran_statements(path):
        lowered = statement.lower()
        match = _PROCEDURE.match(statement)
        if match:
            current = Interface(match)
            table = callbacks if current.is_callback else interfaces
            if current.c_name in table:
                duplicates.append(current.c_name)
            table[current.c_name] = current
        elif re.match(r"^end\s*(function|subroutine)\b", lowered):
            current = None
        elif current is not None:
            if "::" in statement and not lowered.startswith("import"):
                current.declarations.update(parse_declaration(statement))
        else:
            match = _PARAMETER.match(statement)
            if match:
                _read_parameters(normalise_type(match.group(1)), match.group(2), ints, strings)
    return ints, strings, interfaces, callbacks, duplicates


def _read_parameters(type_spec, body, ints, strings):
    for item in split_top_level(body):
        name, _, value = (p.strip() for p in item.partition("="))
        name = name.upper()
        if type_spec.startswith("character"):
            strings[name] = value.strip("\"'")
        else:
            # Fortran names are case-insensitive: evaluate in upper case.
            known = {k: v for k, (_, v) in ints.items()}
            ints[name] = (type_spec, unimesh_header.evaluate(value.upper(), known))


def read_public_names(path):
    names = set()
    for statement in fortran_statements(path):
        match = re.match(r"^public\s*::\s*(.+)$", statement, re.I)
        if match:
            names.update(n.strip().upper() for n in match.group(1).split(","))
    return names


# ----------------------------------------------------------------- comparison

# What each C category (unimesh_header.CType.kind) must look like in Fortran:
# (allowed types, passed by value?)
_EXPECTED = {
    "int32": ({"integer(c_int32_t)"}, True),
    "int64": ({"integer(c_int64_t)"}, True),
    "double": ({"real(c_double)"}, True),
    "int32*": ({"integer(c_int32_t)"}, False),
    "int64*": ({"integer(c_int64_t)"}, False),
    "double*": ({"real(c_double)"}, False),
    "string": ({"character(c_char)"}, False),
    "opaque": ({"type(c_ptr)"}, True),
    "handle": ({"type(c_ptr)"}, True),
    "handle*": ({"type(c_ptr)"}, False),
    "callback": ({"type(c_funptr)"}, True),
}
_RESULTS = {"int32": "integer(c_int32_t)", "double": "real(c_double)", "string": "type(c_ptr)"}


def compare_function(function, interface):
    where = f"{function.name} (Fortran {interface.fortran_name})"
    callback = interface.is_callback
    problems = []
    expected_kind = function.returns.kind()
    if expected_kind == "void":
        if interface.kind != "subroutine":
            problems.append(f"{where}: C returns void, so it must be a subroutine")
    else:
        result = interface.result_type or getattr(
            interface.declarations.get(interface.result_name), "type", None)
        if interface.kind != "function" or result != _RESULTS[expected_kind]:
            problems.append(f"{where}: result must be {_RESULTS[expected_kind]}, not {result}")

    c_names = [p.name.lower() for p in function.parameters]
    if interface.arguments != c_names:
        problems.append(f"{where}: arguments {interface.arguments} differ from the header's {c_names}")
        return problems
    for parameter in function.parameters:
        declaration = interface.declarations.get(parameter.name.lower())
        if declaration is None:
            problems.append(f"{where}: argument {parameter.name} is not declared")
            continue
        problems += [f"{where}, argument {parameter.name}: {p}"
                     for p in compare_argument(parameter.type, declaration, callback)]
    return problems


def compare_argument(ctype, declaration, callback=False):
    kind = ctype.kind()
    types, by_value = _EXPECTED[kind]
    if callback and kind == "string":
        # A callback receives the C pointer itself (its length is unknown).
        types, by_value = {"type(c_ptr)"}, True
    problems = []
    if declaration.type not in types:
        problems.append(f"C {kind} needs {' or '.join(sorted(types))}, not {declaration.type}")
    if declaration.value != by_value:
        problems.append("C passes it by value: add `value`" if by_value
                        else "C passes a pointer: remove `value`")
    if kind == "string" and not by_value and not declaration.array:
        problems.append("a C string must be a character array (dimension(*))")
    if not by_value:
        # const pointers are read by C; the others are written.
        wanted = {"in"} if ctype.const else {"out", "inout"}
        if declaration.intent not in wanted:
            problems.append(f"intent({declaration.intent}) for a {'const ' if ctype.const else ''}"
                            f"pointer: use intent({'/'.join(sorted(wanted))})")
    elif declaration.intent not in (None, "in"):
        problems.append(f"intent({declaration.intent}) on a value argument")
    return problems


def check(header_path, cint_path, module_path):
    header = unimesh_header.Header(header_path)
    ints, strings, interfaces, callbacks, duplicates = read_cint(cint_path)
    problems = [f"{name}: more than one interface binds to it" for name in duplicates]

    for name, value in header.int_constants.items():
        if name not in ints:
            problems.append(f"{name} = {value}: missing from {os.path.basename(cint_path)}")
            continue
        type_spec, fortran_value = ints[name]
        if fortran_value != value:
            problems.append(f"{name}: Fortran {fortran_value}, header {value}")
        if type_spec != "integer(c_int32_t)":
            problems.append(f"{name}: declared {type_spec}, the ABI type is integer(c_int32_t)")
    for name, value in header.string_constants.items():
        if strings.get(name) != value:
            problems.append(f'{name}: Fortran "{strings.get(name)}", header "{value}"')
    for name in sorted(set(ints) | set(strings)):
        if name.startswith("UM_") and name not in header.int_constants \
                and name not in header.string_constants:
            problems.append(f"{name}: a Fortran parameter the header does not define")

    for name, function in header.functions.items():
        if name not in interfaces:
            problems.append(f"{name}: no bind(c) interface in {os.path.basename(cint_path)}")
        else:
            problems += compare_function(function, interfaces[name])
    for name in sorted(set(interfaces) - set(header.functions)):
        problems.append(f"{name}: bound in Fortran but not declared in the header")

    for name, callback in header.callbacks.items():
        if name not in callbacks:
            problems.append(f"{name}: no abstract interface in {os.path.basename(cint_path)}")
        else:
            problems += compare_function(callback, callbacks[name])
    for name in sorted(set(callbacks) - set(header.callbacks)):
        problems.append(f"{name}: an abstract bind(c) interface the header has no typedef for")

    public = read_public_names(module_path)
    for name in list(header.int_constants) + list(header.string_constants):
        if name not in public:
            problems.append(f"{name}: not re-exported (public) by {os.path.basename(module_path)}")

    counts = (len(header.int_constants) + len(header.string_constants), len(header.functions),
              len(header.callbacks))
    return problems, counts


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--header", required=True)
    parser.add_argument("--cint", required=True)
    parser.add_argument("--module", required=True)
    args = parser.parse_args()
    problems, (n_constants, n_functions, n_callbacks) = check(args.header, args.cint, args.module)
    for problem in problems:
        print("MISMATCH:", problem)
    if problems:
        print(f"{len(problems)} mismatches between the Fortran binding and the header")
        return 1
    print(f"Fortran binding matches the header: {n_constants} constants, "
          f"{n_functions} functions, {n_callbacks} callback types")
    return 0


if __name__ == "__main__":
    sys.exit(main())
