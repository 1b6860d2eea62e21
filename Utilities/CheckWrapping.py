#!/usr/bin/env python3
"""Static check of FFDShapeMatching's ITK wrapping files (wrapping/*.wrap).

A Python-wrapped ITK cannot be built on the project's machines in CI time, so this
checker reads each .wrap file the way ITK's wrapping macros would expand it, with ITK's
default wrapped types, and verifies that:

  * every wrapped class "itk::Foo" is declared in the module's include/itkFoo.h,
  * every itk_wrap_template(...) gives as many template arguments as the class takes
    (defaults counted), a number where the class takes a value and a type where it takes
    a type,
  * every mangled name is the one ITK's conventions give for its C++ arguments
    (float -> F, itk::Image<unsigned char,3> -> IUC3, itk::Mesh<double,3> -> MD3, ...),
  * every variable used is one ITK's wrapping defines, and every class is closed with
    itk_end_wrap_class().

Exit status 0 when every file passes, 1 with one line per problem otherwise.
"""

import argparse
import os
import re
import sys

# ITK's default wrapped types (ITK_WRAP_<type> defaults) and their mangled names.
SCALAR_TYPES = {
    "UC": "unsigned char",
    "US": "unsigned short",
    "UI": "unsigned int",
    "UL": "unsigned long",
    "ULL": "unsigned long long",
    "SC": "signed char",
    "SS": "signed short",
    "SI": "signed int",
    "SL": "signed long",
    "SLL": "signed long long",
    "F": "float",
    "D": "double",
    "B": "bool",
}
TYPE_TO_MANGLED = {cxx: mangled for mangled, cxx in SCALAR_TYPES.items()}
TYPE_TO_MANGLED.update({"short": "SS", "int": "SI", "long": "SL", "char": "SC"})
DEFAULT_LISTS = {
    "ITK_WRAP_IMAGE_DIMS": ["2", "3"],
    "WRAP_ITK_USIGN_INT": ["UC", "US"],
    "WRAP_ITK_SIGN_INT": ["SS"],
    "WRAP_ITK_INT": ["UC", "US", "SS"],
    "WRAP_ITK_REAL": ["F", "D"],
    "WRAP_ITK_SCALAR": ["UC", "US", "SS", "F", "D"],
}
TEMPLATE_CLASSES = {"Image": "I", "Mesh": "M", "PointSet": "PS", "Vector": "V", "CovariantVector": "CV"}


class WrapError(Exception):
    pass


def split_top_level(text, separator=","):
    """Splits at separators that are outside <...> and (...)."""
    parts, depth, current = [], 0, []
    for char in text:
        if char in "<(":
            depth += 1
        elif char in ">)":
            depth -= 1
        if char == separator and depth == 0:
            parts.append("".join(current).strip())
            current = []
        else:
            current.append(char)
    tail = "".join(current).strip()
    if tail or parts:
        parts.append(tail)
    return parts


def mangle(cxx_argument):
    """The mangled name ITK's conventions give to one C++ template argument."""
    argument = " ".join(cxx_argument.split())
    if re.fullmatch(r"\d+", argument):
        return argument
    if argument in TYPE_TO_MANGLED:
        return TYPE_TO_MANGLED[argument]
    match = re.fullmatch(r"itk::(\w+)\s*<(.*)>", argument)
    if match and match.group(1) in TEMPLATE_CLASSES:
        inner = split_top_level(match.group(2))
        return TEMPLATE_CLASSES[match.group(1)] + "".join(mangle(part) for part in inner)
    raise WrapError("no ITK mangling known for template argument '%s'" % argument)


def variables_for(value_lists):
    """ITKM_/ITKT_ variables for the scalar types and their images and meshes."""
    variables = {}
    for mangled, cxx in SCALAR_TYPES.items():
        variables["ITKM_" + mangled] = mangled
        variables["ITKT_" + mangled] = cxx
        for dim in ("2", "3", "4"):
            for kind, prefix in (("Image", "I"), ("Mesh", "M")):
                variables["ITKM_%s%s%s" % (prefix, mangled, dim)] = "%s%s%s" % (prefix, mangled, dim)
                variables["ITKT_%s%s%s" % (prefix, mangled, dim)] = "itk::%s<%s,%s>" % (kind, cxx, dim)
    for name, values in value_lists.items():
        variables[name] = ";".join(values)
    return variables


def parse_template_parameters(header_path, class_name):
    """Returns [(kind, has_default)] for the template parameters of class_name."""
    with open(header_path, encoding="utf-8") as stream:
        text = re.sub(r"//[^\n]*|/\*.*?\*/", " ", stream.read(), flags=re.S)
    pattern = re.compile(r"template\s*<(?P<params>[^;{]*?)>\s*class\s+(?:\w+\s+)*?" + re.escape(class_name) + r"\s*[:{]")
    match = pattern.search(text)
    if not match:
        if re.search(r"class\s+(?:\w+\s+)*?" + re.escape(class_name) + r"\s*[:{]", text):
            return []
        raise WrapError("class %s is not declared in %s" % (class_name, header_path))
    parameters = []
    for parameter in split_top_level(match.group("params")):
        kind = "type" if re.match(r"(typename|class)\b", parameter) else "value"
        parameters.append((kind, "=" in parameter))
    return parameters


def tokenize_commands(text):
    """Yields (command, [arguments]) from CMake code, with quoted strings kept whole."""
    text = re.sub(r"#[^\n]*", "", text)
    for match in re.finditer(r"(\w+)\s*\(((?:[^()\"]|\"[^\"]*\"|\([^()]*\))*)\)", text):
        arguments = re.findall(r"\"[^\"]*\"|[^\s\"]+", match.group(2))
        yield match.group(1).lower(), arguments


def expand(argument, variables):
    def replace(match):
        name = match.group(1)
        if name not in variables:
            raise WrapError("unknown variable ${%s}" % name)
        return variables[name]

    previous = None
    while previous != argument:
        previous, argument = argument, re.sub(r"\$\{(\w+)\}", replace, argument)
    return argument


def check_wrap_file(path, include_dir):
    problems = []
    with open(path, encoding="utf-8") as stream:
        commands = list(tokenize_commands(stream.read()))
    variables = variables_for(DEFAULT_LISTS)
    current_class, parameters, wrapped = None, None, 0

    def run(command_list, variables):
        nonlocal current_class, parameters, wrapped
        index = 0
        while index < len(command_list):
            command, arguments = command_list[index]
            if command == "foreach":
                depth, end = 1, index + 1
                while end < len(command_list) and depth:
                    depth += {"foreach": 1, "endforeach": -1}.get(command_list[end][0], 0)
                    end += 1
                if depth:
                    raise WrapError("foreach without endforeach")
                body = command_list[index + 1 : end - 1]
                values = [value for argument in arguments[1:] for value in expand(argument, variables).split(";") if value]
                for value in values:
                    run(body, dict(variables, **{arguments[0]: value}))
                index = end
                continue
            arguments = [expand(argument, variables).strip('"') for argument in arguments]
            if command == "set":
                variables[arguments[0]] = ";".join(arguments[1:])
            elif command == "itk_wrap_filter_dims":
                dims = [d for d in DEFAULT_LISTS["ITK_WRAP_IMAGE_DIMS"] if d in ";".join(arguments[1:]).split(";")]
                variables[arguments[0]] = ";".join(dims)
            elif command == "itk_wrap_include":
                pass
            elif command in ("itk_wrap_class", "itk_wrap_simple_class"):
                if current_class:
                    raise WrapError("itk_wrap_class(%s) inside %s" % (arguments[0], current_class))
                full_name = arguments[0]
                if not full_name.startswith("itk::"):
                    raise WrapError("wrapped class '%s' is not in namespace itk" % full_name)
                short_name = full_name[len("itk::") :]
                header = os.path.join(include_dir, "itk%s.h" % short_name)
                if not os.path.isfile(header):
                    raise WrapError("no header include/itk%s.h for wrapped class %s" % (short_name, full_name))
                parameters = parse_template_parameters(header, short_name)
                if command == "itk_wrap_simple_class":
                    if parameters:
                        raise WrapError("%s is a template: itk_wrap_simple_class cannot wrap it" % full_name)
                    wrapped += 1
                else:
                    current_class = full_name
            elif command == "itk_wrap_template":
                if not current_class:
                    raise WrapError("itk_wrap_template outside itk_wrap_class")
                mangled, cxx = arguments[0], arguments[1]
                cxx_arguments = split_top_level(cxx)
                required = sum(1 for _, has_default in parameters if not has_default)
                if not required <= len(cxx_arguments) <= len(parameters):
                    raise WrapError(
                        "%s takes %d to %d template arguments, '%s' gives %d"
                        % (current_class, required, len(parameters), cxx, len(cxx_arguments))
                    )
                for (kind, _), argument in zip(parameters, cxx_arguments):
                    is_number = re.fullmatch(r"\d+", argument.strip()) is not None
                    if (kind == "value") != is_number:
                        raise WrapError("%s: argument '%s' given where a %s is expected" % (current_class, argument, kind))
                expected = "".join(mangle(argument) for argument in cxx_arguments)
                if mangled != expected:
                    raise WrapError("mangled name '%s' for <%s> should be '%s'" % (mangled, cxx, expected))
                wrapped += 1
            elif command == "itk_end_wrap_class":
                if not current_class:
                    raise WrapError("itk_end_wrap_class without itk_wrap_class")
                current_class = None
            else:
                raise WrapError("command %s() is not understood by this checker" % command)
            index += 1

    try:
        run(commands, variables)
        if current_class:
            raise WrapError("itk_wrap_class(%s) is never closed" % current_class)
        if not wrapped:
            raise WrapError("wraps nothing")
    except WrapError as error:
        problems.append("%s: %s" % (path, error))
    except OSError as error:
        problems.append("%s: %s" % (path, error))
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--wrapping-dir", required=True)
    parser.add_argument("--include-dir", required=True)
    options = parser.parse_args()
    wrap_files = sorted(
        os.path.join(options.wrapping_dir, name) for name in os.listdir(options.wrapping_dir) if name.endswith(".wrap")
    )
    if not wrap_files:
        print("no .wrap files in %s" % options.wrapping_dir)
        return 1
    problems = []
    for path in wrap_files:
        problems.extend(check_wrap_file(path, options.include_dir))
    for problem in problems:
        print(problem)
    print("%d passed, %d failed" % (len(wrap_files) - len(problems), len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
