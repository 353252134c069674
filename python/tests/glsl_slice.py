"""Runs the part of a GLSL shader that computes one value: the straight-line statements MaterialX's
shader generator emits for a node graph (declarations, assignments, calls of its own functions with
`out` parameters, `#define` aliases, uniforms with their defaults), executed with numpy under GLSL's
rules for the few built-ins such code uses. Only the statements the wanted value depends on run
(a backward slice), so the lighting code around them, which this does not understand, is never
touched. Used by python/tests/test_material_export.py to find the tangent that MaterialX's own
generated code hands to its BSDFs."""

import math
import re
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any

import numpy as np

IDENTIFIER = re.compile(r"[A-Za-z_]\w*")
TYPES = {"float", "int", "bool", "vec2", "vec3", "vec4", "mat3", "mat4", "BSDF", "EDF",
         "surfaceshader", "material", "ClosureData", "lightshader"}


def _vec(*parts: Any) -> np.ndarray:
    """GLSL's vecN constructors: one scalar fills every component, else the parts in order."""
    flat = np.concatenate([np.atleast_1d(np.asarray(p, dtype=float)) for p in parts])
    return flat


def _vec_n(n: int):
    def construct(*parts: Any) -> np.ndarray:
        flat = _vec(*parts)
        return np.full(n, flat[0]) if flat.size == 1 else flat[:n]
    return construct


def _normalize(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


BUILTINS: dict[str, Any] = {
    "vec2": _vec_n(2), "vec3": _vec_n(3), "vec4": _vec_n(4), "float": float, "int": int,
    "normalize": _normalize, "cross": np.cross, "dot": lambda a, b: float(np.dot(a, b)),
    "length": lambda v: float(np.linalg.norm(v)), "sqrt": np.sqrt, "sin": math.sin,
    "cos": math.cos, "radians": math.radians, "abs": abs, "max": np.maximum, "min": np.minimum,
    "pow": np.power, "exp": np.exp, "log": np.log, "sign": np.sign, "floor": np.floor,
    "clamp": lambda x, lo, hi: np.clip(x, lo, hi), "mix": lambda a, b, t: a * (1 - t) + b * t,
    "true": True, "false": False,
}


@dataclass
class Statement:
    """One top-level statement: the variables it sets, the identifiers it reads, its Python."""
    sets: list[str]
    reads: set[str]
    kind: str  # "assign" or "call"
    target: str = ""
    expression: str = ""
    function: str = ""
    arguments: list[str] = field(default_factory=list)
    branches: list[list["Statement"]] = field(default_factory=list)


@dataclass
class Function:
    parameters: list[tuple[str, str]]  # (qualifier: "in"/"out"/"inout", name)
    body: list[Statement]
    text: str  # the body as written, for calls inside blocks


def _split_arguments(text: str) -> list[str]:
    parts, depth, current = [], 0, ""
    for ch in text:
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        if ch == "," and depth == 0:
            parts.append(current.strip())
            current = ""
        else:
            current += ch
    if current.strip():
        parts.append(current.strip())
    return parts


def _matching(text: str, i: int, opening: str, closing: str) -> int:
    """The index of the bracket that closes the one at `i`."""
    depth = 0
    for j in range(i, len(text)):
        if text[j] == opening:
            depth += 1
        elif text[j] == closing:
            depth -= 1
            if depth == 0:
                return j
    raise ValueError(f"unbalanced {opening} at {i}")


SWIZZLE = {"x": 0, "y": 1, "z": 2, "w": 3, "r": 0, "g": 1, "b": 2, "a": 3}


def _python_expression(text: str) -> str:
    """A GLSL expression of generated node code as Python: its only non-Python syntax is the
    ternary `(c) ? a : b` and `.x`-style member access, which numpy arrays do not have."""
    ternary = re.fullmatch(r"\((.*)\)\s*\?\s*(.+?)\s*:\s*(.+)", text.strip())
    if ternary:
        condition, yes, no = ternary.groups()
        return (f"({_python_expression(yes)} if ({_python_expression(condition)}) "
                f"else {_python_expression(no)})")
    # A vector's components (v.x, v.xyz) as numpy indexing; vd's members stay attributes.
    def component(match: re.Match) -> str:
        indices = [SWIZZLE[c] for c in match.group(2)]
        return match.group(1) + (f"[{indices[0]}]" if len(indices) == 1 else f"[{indices}]")
    text = re.sub(r"(?<!vd)(\b\w+|\))\.([xyzw]{1,4})\b", component, text)
    return text.replace("&&", " and ").replace("||", " or ")


class Shader:
    """The functions, uniforms and aliases of one stage's generated source."""

    def __init__(self, source: str):
        source = re.sub(r"//[^\n]*", "", source)
        self.aliases = dict(re.findall(r"^#define\s+(\w+)\s+(\S+)\s*$", source, re.M))
        self.uniforms: dict[str, str] = dict(
            (name, value) for name, value in
            re.findall(r"^uniform\s+\w+\s+(\w+)\s*=\s*([^;]+);", source, re.M))
        self.functions: dict[str, Function] = {}
        for match in re.finditer(r"^\w+\s+(\w+)\(([^)]*)\)\s*\n\{\n(.*?)^\}", source, re.M | re.S):
            name, parameters, body = match.groups()
            self.functions[name] = Function(self._parameters(parameters), [], body)
        for function in self.functions.values():
            function.body = self._statements(function.text)

    @staticmethod
    def _parameters(text: str) -> list[tuple[str, str]]:
        out = []
        for part in _split_arguments(text):
            words = part.split()
            qualifier = words[0] if words[0] in ("out", "inout") else "in"
            out.append((qualifier, words[-1]))
        return out

    def _statements(self, body: str) -> list[Statement]:
        """The body's statements: simple ones, and `if (c) {...} else {...}` with its branches."""
        out: list[Statement] = []
        i = 0
        while i < len(body):
            if body[i].isspace():
                i += 1
                continue
            branch = re.match(r"if\s*\(", body[i:])
            if branch:
                close = _matching(body, i + branch.end() - 1, "(", ")")
                condition = body[i + branch.end():close]
                then_body, i = self._block(body, close + 1)
                else_body: list[Statement] = []
                rest = re.match(r"\s*else\b", body[i:])
                if rest:
                    else_body, i = self._block(body, i + rest.end())
                reads = set(IDENTIFIER.findall(condition))
                sets: list[str] = []
                for statement in then_body + else_body:
                    reads |= statement.reads
                    sets += statement.sets
                out.append(Statement(sets, reads, "if", expression=_python_expression(condition),
                                     branches=[then_body, else_body]))
                continue
            if body[i] == "{":
                block, i = self._block(body, i)
                out += block
                continue
            end = body.index(";", i)
            statement = self._statement(body[i:end])
            if statement is not None:
                out.append(statement)
            i = end + 1
        return out

    def _block(self, body: str, i: int) -> tuple[list[Statement], int]:
        """The statements of the block or single statement at `i`, and where it ends."""
        while body[i].isspace():
            i += 1
        if body[i] == "{":
            close = _matching(body, i, "{", "}")
            return self._statements(body[i + 1:close]), close + 1
        if re.match(r"if\s*\(", body[i:]):
            # else if: one statement that is itself a branch; find its end by parsing it alone.
            parsed = self._statements(body[i:])
            return parsed[:1], len(body) if len(parsed) == 1 else self._end_of_first(body, i)
        end = body.index(";", i)
        statement = self._statement(body[i:end])
        return ([statement] if statement else []), end + 1

    def _end_of_first(self, body: str, i: int) -> int:
        close = _matching(body, body.index("(", i), "(", ")")
        _, after = self._block(body, close + 1)
        rest = re.match(r"\s*else\b", body[after:])
        return self._block(body, after + rest.end())[1] if rest else after

    def _statement(self, text: str) -> Statement | None:
        text = re.sub(r"^(if|else)\b.*", "", text.strip()).strip()
        words = text.split()
        if not words or words[0] == "return":
            return None
        if words[0] == "const":
            text = text[len("const"):].strip()
            words = words[1:]
        if len(words) > 1 and words[0] in TYPES and IDENTIFIER.fullmatch(words[1]) and "=" in text:
            text = text[len(words[0]):].strip()
        assignment = re.fullmatch(r"([\w.]+)\s*([*+]?=)\s*(.+)", text, re.S)
        if assignment and not text.startswith("("):
            target, operator, expression = assignment.groups()
            if operator != "=":
                expression = f"{target} {operator[0]} ({expression})"
            return Statement([target], set(IDENTIFIER.findall(expression)), "assign", target,
                             _python_expression(expression))
        call = re.fullmatch(r"(\w+)\((.*)\)", text, re.S)
        if call and call.group(1) in self.functions:
            name, arguments = call.groups()
            args = _split_arguments(arguments)
            parameters = self.functions[name].parameters
            sets = [a for (q, _), a in zip(parameters, args, strict=True) if q in ("out", "inout")]
            reads = {i for (q, _), a in zip(parameters, args, strict=True) if q != "out"
                     for i in IDENTIFIER.findall(a)}
            return Statement(sets, reads, "call", function=name, arguments=args)
        return None

    def _value(self, expression: str, scope: dict[str, Any]) -> Any:
        names: dict[str, Any] = dict(BUILTINS)
        for alias, target in self.aliases.items():
            if target in BUILTINS:
                names[alias] = BUILTINS[target]
            elif re.fullmatch(r"[\d.eE+-]+", target):
                names[alias] = float(target)
        names.update(scope)
        return eval(expression, {"__builtins__": {}}, names)  # noqa: S307 (generated code)

    @staticmethod
    def _slice(statements: list[Statement], wanted: set[str]) -> tuple[list[Statement], set[str]]:
        needed, chosen = set(wanted), []
        for statement in reversed(statements):
            if needed & ({t.split(".")[0] for t in statement.sets} | set(statement.sets)):
                chosen.append(statement)
                needed |= statement.reads
        return chosen, needed

    def needs(self, function: str, wanted: set[str]) -> set[str]:
        """The names `wanted` depends on in `function`'s top-level statements (its parameters
        among them)."""
        return self._slice(self.functions[function].body, wanted)[1]

    def run(self, statements: list[Statement], wanted: set[str], scope: dict[str, Any]) -> None:
        """Runs, in order, the statements that `wanted` depends on, in `scope`."""
        chosen, needed = self._slice(statements, wanted)
        for name in needed:
            if name not in scope and name in self.uniforms:
                scope[name] = self._value(self.uniforms[name], scope)
        for statement in reversed(chosen):
            if statement.kind == "if":
                taken = statement.branches[0 if self._value(statement.expression, scope) else 1]
                self.run(taken, needed, scope)
            elif statement.kind == "assign":
                value = self._value(statement.expression, scope)
                if "." in statement.target:
                    owner, member = statement.target.split(".", 1)
                    if member in SWIZZLE:
                        scope.setdefault(owner, np.zeros(4))[SWIZZLE[member]] = value
                    else:
                        setattr(scope[owner], member, value)
                else:
                    scope[statement.target] = value
            else:
                outputs = self.call(statement.function,
                                    [self._value(a, scope) if q != "out" else None
                                     for (q, _), a in zip(
                                         self.functions[statement.function].parameters,
                                         statement.arguments, strict=True)],
                                    wanted=None)
                for (q, name), argument in zip(self.functions[statement.function].parameters,
                                               statement.arguments, strict=True):
                    if q in ("out", "inout"):
                        scope[argument] = outputs[name]

    def call(self, name: str, arguments: list[Any], wanted: set[str] | None) -> dict[str, Any]:
        """Runs function `name` with its in-arguments; returns its out parameters (or `wanted`)."""
        function = self.functions[name]
        scope = {p: a for (_, p), a in zip(function.parameters, arguments, strict=True)
                 if a is not None}
        outs = {p for q, p in function.parameters if q in ("out", "inout")}
        self.run(function.body, wanted if wanted is not None else outs, scope)
        return scope

    def calls_named(self, caller: str, callee: str) -> list[tuple[str, dict[str, str]]]:
        """Every call of a function whose name matches the regular expression `callee` in
        `caller` (inside blocks too): (its name, {parameter name: the caller's expression})."""
        out = []
        for match in re.finditer(rf"\b({callee})\((.*?)\);", self.functions[caller].text, re.S):
            if match.group(1) not in self.functions:
                continue
            names = [p for _, p in self.functions[match.group(1)].parameters]
            arguments = _split_arguments(match.group(2))
            out.append((match.group(1), dict(zip(names, arguments, strict=True))))
        return out


def vertex_data(vertex: Shader, normal: np.ndarray, tangent: np.ndarray) -> SimpleNamespace:
    """The vertex stage's world-space data for a vertex whose world normal and tangent are given:
    its own code derives the rest (the bitangent)."""
    vd = SimpleNamespace(normalWorld=normal, tangentWorld=tangent)
    main = vertex.functions["main"]
    derived = [s for s in main.body if s.kind == "assign" and s.target.startswith("vd.")
               and s.target not in ("vd.normalWorld", "vd.tangentWorld", "vd.positionWorld")]
    vertex.run(derived, {s.target for s in derived}, {"vd": vd})
    return vd


def bsdf_lobe_axes(pixel_source: str, vertex_source: str, normal: np.ndarray,
                   tangent: np.ndarray) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """For each microfacet BSDF the generated surface shader calls (every call with a tangent `X`
    and a `roughness`), the tangent and the (alpha_x, alpha_y) pair that the generated code hands
    it, for a fragment whose world normal and tangent are given: (BSDF, X, roughness). alpha_x is
    the roughness along X."""
    pixel, vertex = Shader(pixel_source), Shader(vertex_source)
    vd = vertex_data(vertex, normal, tangent)
    surface_calls = [(name, arguments) for name, arguments in pixel.calls_named("main", r"NG_\w+")]
    if len(surface_calls) != 1:
        raise LookupError(f"expected one surface shader call in main, found {surface_calls}")
    surface, surface_arguments = surface_calls[0]
    out = []
    for bsdf, arguments in pixel.calls_named(surface, r"mx_\w*_bsdf"):
        if "X" not in arguments or "roughness" not in arguments:
            continue
        wanted = {arguments["X"], arguments["roughness"]}
        parameters = [p for _, p in pixel.functions[surface].parameters]
        inputs = pixel.needs(surface, wanted) & set(parameters)
        main_scope: dict[str, Any] = {"vd": vd}
        expressions = {p: surface_arguments[p] for p in inputs}
        pixel.run(pixel.functions["main"].body,
                  {i for e in expressions.values() for i in IDENTIFIER.findall(e)}, main_scope)
        scope = {p: pixel._value(e, main_scope) for p, e in expressions.items()}
        pixel.run(pixel.functions[surface].body, wanted, scope)
        out.append((bsdf, np.asarray(pixel._value(arguments["X"], scope), dtype=float),
                    np.asarray(pixel._value(arguments["roughness"], scope), dtype=float)))
    return out
