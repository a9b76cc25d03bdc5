#!/usr/bin/env python3
"""A skeleton engine for stref's conformance corpus (protocol stref-engine/1).

It implements a deliberately tiny subset of the IEC 61131-3 dialects (tecomat,
nexto) and says `unsupported`, with a reason, for everything else; it never
guesses. See README.md next to this file for how to run it and how to grow it.

The subset:
  * one PROGRAM with VAR ... END_VAR blocks of INT, DINT and BOOL variables
    (`a, b : INT := 5;`), run over the request's scan cycles, keeping its
    state from cycle to cycle; `set` entries of the calls write variables
    before their cycle;
  * statements: `x := expr;`, IF/ELSIF/ELSE/END_IF, the empty statement;
  * expressions: decimal integer literals, TRUE/FALSE, variables, ( ),
    unary - and NOT, * + -, < > <= >= = <>, AND (&), XOR, OR;
  * the dialect's integer overflow (policy `overflow`: wrap, saturate or
    trap with the runtime error `overflow`), `after-error` (stop or continue)
    and `short-circuit` (eager or short-circuit evaluation of AND and OR).

Everything else (other types, loops, CASE, functions, function blocks,
globals, located variables, typed or based literals, division, resets, ...)
is answered `unsupported`, and so is a program this engine cannot type-check:
it does not claim to know which programs a dialect rejects.

Standard library only; Python 3.6 or later.
"""

import json
import re
import sys

PROTOCOL = "stref-engine/1"
DIALECTS = ("tecomat", "nexto")

# name -> (minimum, maximum); BOOL is handled apart
INTEGER_TYPES = {"INT": (-32768, 32767), "DINT": (-2147483648, 2147483647)}
TYPES = set(INTEGER_TYPES) | {"BOOL"}

# Names a variable may not take here: the keywords of IEC 61131-3 and of
# CODESYS, and the elementary types. (A dialect may reject more; a name this
# engine is unsure of is not a guess it makes: see `check_name`.)
KEYWORDS = set(
    """ACTION AND ARRAY AT BY CASE CONFIGURATION CONSTANT DO ELSE ELSIF ELSEIF END_ACTION END_CASE
    END_CONFIGURATION END_FOR END_FUNCTION END_FUNCTION_BLOCK END_IF END_PROGRAM END_REPEAT
    END_RESOURCE END_STRUCT END_TYPE END_VAR END_WHILE EXIT FALSE F_EDGE FOR FUNCTION
    FUNCTION_BLOCK IF MOD NOT OF ON OR PROGRAM R_EDGE REPEAT RESOURCE RETAIN NON_RETAIN RETURN
    STRUCT TASK THEN TO TRUE TYPE UNTIL VAR VAR_ACCESS VAR_CONFIG VAR_EXTERNAL VAR_GLOBAL
    VAR_INPUT VAR_IN_OUT VAR_OUTPUT VAR_TEMP WHILE WITH XOR STRING WSTRING CONTINUE JMP POINTER
    REFERENCE METHOD END_METHOD PROPERTY END_PROPERTY EXTENDS THIS SUPER UNION END_UNION
    VAR_STAT VAR_INST PERSISTENT
    BOOL SINT INT DINT LINT USINT UINT UDINT ULINT REAL LREAL TIME LTIME DATE TIME_OF_DAY TOD
    DATE_AND_TIME DT BYTE WORD DWORD LWORD CHAR WCHAR""".split()
)

# Names that IEC 61131-3 or CODESYS give to standard functions, function
# blocks, their parameters and IL operators. A dialect may reserve them
# (reject a variable so named) or not; this engine does not decide which,
# and answers `unsupported` for a program that uses one as a name.
STANDARD_NAMES = set(
    """ABS SQRT LN LOG EXP SIN COS TAN ASIN ACOS ATAN ADD MUL SUB DIV EXPT MOVE SHL SHR ROR ROL
    SEL MAX MIN LIMIT MUX GT GE EQ LE LT NE LEN LEFT RIGHT MID CONCAT INSERT DELETE REPLACE FIND
    TRUNC SR RS TP TON TOF CTU CTD CTUD RTC IN N L P G K MN MX S S1 R R1 CLK Q Q1 CU CD LD PV QU
    QD CV PT ET EN ENO OUT ADR BITADR CAL CALC CALCN INDEXOF JMPC JMPCN LDN PARAMS READ_ONLY
    READ_WRITE RET RETC RETCN SIZEOF ST STN BIT""".split()
)


def is_standard_name(name):
    return name in STANDARD_NAMES or "_TO_" in name or name.startswith("TO_") or re.match(r"^IN[0-9]+$", name)


class Unsupported(Exception):
    """Raised anywhere for what this engine does not implement."""


class RuntimeFault(Exception):
    """A runtime error of the program: its kind (corpus-format §4.3) and line."""

    def __init__(self, kind, line):
        Exception.__init__(self, kind)
        self.kind = kind
        self.line = line


# ---------------------------------------------------------------- lexer


TOKEN = re.compile(
    r"""(?P<space>[ \t\r\n]+)
      | (?P<name>[A-Za-z_][A-Za-z0-9_]*)
      | (?P<number>[0-9][0-9_]*)
      | (?P<op>:=|<=|>=|<>|\*\*|[-+*/<>=();:,&.\[\]#'"%])""",
    re.VERBOSE,
)


TOKENS_NOT_IMPLEMENTED = {
    "**": "exponentiation",
    "/": "division",
    "#": "typed and time literals",
    "'": "STRING literals",
    '"': "WSTRING literals",
    "%": "located variables",
    "[": "arrays",
    "]": "arrays",
    ".": "structured variables and REAL literals",
}


def strip_comments(source, nested):
    """The source with every (* ... *) comment blanked (newlines kept, so that
    line numbers stay those of the file)."""
    out = []
    i, depth, n = 0, 0, len(source)
    while i < n:
        two = source[i : i + 2]
        if two == "(*" and (depth == 0 or nested):
            depth += 1
            out.append("  ")
            i += 2
        elif two == "*)" and depth > 0:
            depth -= 1
            out.append("  ")
            i += 2
        elif depth > 0:
            out.append("\n" if source[i] == "\n" else " ")
            i += 1
        else:
            if two == "//" or two == "/*":
                raise Unsupported("comments other than (* ... *)")
            if source[i] == "{":
                raise Unsupported("pragmas ({ ... })")
            out.append(source[i])
            i += 1
    if depth > 0:
        raise Unsupported("a comment that is not closed")
    return "".join(out)


def tokenize(source, policies):
    """A list of (kind, text, line); names upper-cased (ST is case-insensitive)."""
    text = strip_comments(source, policies.get("nested-comments") == "yes")
    tokens, pos, line = [], 0, 1
    while pos < len(text):
        m = TOKEN.match(text, pos)
        if not m:
            raise Unsupported("the character %r" % text[pos])
        kind, value = m.lastgroup, m.group()
        if kind == "name":
            if not re.match(r"^_?[A-Za-z0-9]+(_[A-Za-z0-9]+)*$", value):
                raise Unsupported("the name %s (underscores other than single ones between letters)" % value)
            tokens.append(("name", value.upper(), line))
        elif kind == "number":
            following = text[m.end() : m.end() + 1]
            if following in ("#", ".") or following.isalpha() or not re.match(r"^[0-9]+(_[0-9]+)*$", value):
                raise Unsupported("literals other than decimal integers (%s%s...)" % (value, following))
            tokens.append(("number", int(value.replace("_", "")), line))
        elif kind == "op":
            if value in TOKENS_NOT_IMPLEMENTED:
                raise Unsupported("%s (the token %s at line %d)" % (TOKENS_NOT_IMPLEMENTED[value], value, line))
            tokens.append(("op", value, line))
        pos = m.end()
        line += value.count("\n") if kind == "space" else 0
    tokens.append(("end", None, line))
    return tokens


# ---------------------------------------------------------------- parser
#
# Expressions are tuples: ("lit", value, line), ("bool", value, line),
# ("var", NAME, line), ("neg", e, line), ("not", e, line),
# ("bin", op, left, right, line). Statements: ("assign", NAME, e, line),
# ("if", [(cond, body), ...], else_body_or_None, line).

BINARY_LEVELS = [  # lowest first
    ["OR"],
    ["XOR"],
    ["AND", "&"],
    ["=", "<>"],
    ["<", ">", "<=", ">="],
    ["+", "-"],
    ["*"],
]


class Parser(object):
    def __init__(self, tokens, policies):
        self.tokens = tokens
        self.i = 0
        self.policies = policies

    def peek(self):
        return self.tokens[self.i]

    def next(self):
        t = self.tokens[self.i]
        self.i += 1
        return t

    def at(self, value):
        kind, text, _ = self.peek()
        return kind in ("name", "op") and text == value

    def expect(self, value):
        kind, text, line = self.next()
        if kind not in ("name", "op") or text != value:
            raise Unsupported("a program this engine cannot parse (expected %s, found %s at line %d)" % (value, text, line))
        return line

    def name(self):
        kind, text, line = self.next()
        if kind != "name" or text in KEYWORDS:
            raise Unsupported("a program this engine cannot parse (expected a name, found %s at line %d)" % (text, line))
        if is_standard_name(text):
            raise Unsupported("the name %s (line %d): whether the dialect reserves it is not implemented" % (text, line))
        limit = self.policies.get("identifier-length", "unlimited")
        if limit.isdigit() and len(text) > int(limit):
            raise Unsupported("a name longer than identifier-length=%s" % limit)
        return text, line

    def unit(self):
        """PROGRAM name VAR...END_VAR* statements END_PROGRAM, and nothing else."""
        if not self.at("PROGRAM"):
            raise Unsupported("declarations other than one PROGRAM (%s)" % self.peek()[1])
        self.next()
        program, _ = self.name()
        variables = {}
        order = []
        while self.at("VAR"):
            self.next()
            if self.peek()[0] == "name" and self.peek()[1] in ("CONSTANT", "RETAIN", "NON_RETAIN", "PERSISTENT"):
                raise Unsupported("VAR %s" % self.peek()[1])
            while not self.at("END_VAR"):
                self.declaration(variables, order)
            self.next()
        kind, text, _ = self.peek()
        if kind == "name" and text.startswith("VAR"):
            raise Unsupported("%s blocks" % text)
        body = self.statements(("END_PROGRAM",))
        self.expect("END_PROGRAM")
        if self.peek()[0] != "end":
            raise Unsupported("more than one program unit (%s after END_PROGRAM)" % self.peek()[1])
        return program, variables, order, body

    def declaration(self, variables, order):
        names = [self.name()]
        while self.at(","):
            self.next()
            names.append(self.name())
        self.expect(":")
        kind, ty, line = self.next()
        if kind != "name" or ty not in TYPES:
            raise Unsupported("variables of type %s" % ty)
        initial = False if ty == "BOOL" else 0
        if self.at(":="):
            self.next()
            initial = constant_value(self.expression(), ty)
        self.expect(";")
        for n, nline in names:
            if n in variables:
                raise Unsupported("a program this engine cannot check (%s declared twice, line %d)" % (n, nline))
            variables[n] = (ty, initial)
            order.append(n)

    def statements(self, enders):
        body = []
        while not any(self.at(e) for e in enders):
            if self.peek()[0] == "end":
                raise Unsupported("a program this engine cannot parse (it ends inside a statement list)")
            s = self.statement()
            if s is not None:
                body.append(s)
        return body

    def statement(self):
        kind, text, line = self.peek()
        if self.at(";"):
            self.next()
            return None
        if kind == "name" and text == "IF":
            return self.if_statement()
        if kind == "name" and text not in KEYWORDS:
            target, line = self.name()
            self.expect(":=")
            e = self.expression()
            self.expect(";")
            return ("assign", target, e, line)
        raise Unsupported("the statement %s (line %d)" % (text, line))

    def if_statement(self):
        line = self.expect("IF")
        branches = []
        cond = self.expression()
        self.expect("THEN")
        body = self.statements(("ELSIF", "ELSE", "END_IF"))
        branches.append((cond, body))
        while self.at("ELSIF"):
            if self.policies.get("elsif-keyword", "ELSIF") not in ("ELSIF", "ELSIF+ELSEIF"):
                raise Unsupported("elsif-keyword=%s" % self.policies.get("elsif-keyword"))
            self.next()
            cond = self.expression()
            self.expect("THEN")
            branches.append((cond, self.statements(("ELSIF", "ELSE", "END_IF"))))
        otherwise = None
        if self.at("ELSE"):
            self.next()
            otherwise = self.statements(("END_IF",))
        self.expect("END_IF")
        self.expect(";")
        return ("if", branches, otherwise, line)

    def expression(self, level=0):
        if level == len(BINARY_LEVELS):
            return self.unary()
        left = self.expression(level + 1)
        while True:
            kind, text, line = self.peek()
            if kind in ("name", "op") and text in BINARY_LEVELS[level]:
                self.next()
                op = "AND" if text == "&" else text
                left = ("bin", op, left, self.expression(level + 1), line)
            else:
                return left

    def unary(self):
        kind, text, line = self.peek()
        if self.at("-"):
            self.next()
            if self.peek()[0] == "number":
                return ("lit", -self.next()[1], line)
            return ("neg", self.unary(), line)
        if self.at("NOT"):
            self.next()
            return ("not", self.unary(), line)
        if self.at("+"):
            raise Unsupported("unary +")
        return self.primary()

    def primary(self):
        kind, text, line = self.next()
        if kind == "number":
            return ("lit", text, line)
        if kind == "name" and text in ("TRUE", "FALSE"):
            return ("bool", text == "TRUE", line)
        if kind == "op" and text == "(":
            e = self.expression()
            self.expect(")")
            return e
        if kind == "name" and text not in KEYWORDS:
            if self.at("("):
                raise Unsupported("calls (%s(...) at line %d)" % (text, line))
            return ("var", text, line)
        raise Unsupported("the expression %s (line %d)" % (text, line))


def constant_value(e, ty):
    """An initial value: a literal of the variable's type."""
    if ty == "BOOL" and e[0] == "bool":
        return e[1]
    if ty in INTEGER_TYPES and e[0] == "lit":
        lo, hi = INTEGER_TYPES[ty]
        if lo <= e[1] <= hi:
            return e[1]
    raise Unsupported("an initial value that is not a literal of its variable's type (line %d)" % e[-1])


# ---------------------------------------------------------------- checker
#
# The engine only runs programs whose types it can work out without any of
# the dialect's conversion rules: both operands of an operator have the same
# type, an integer literal takes the type of the other operand (and must fit
# it), and an assignment's value has the type of its target.


def check_unit(variables, body):
    for s in body:
        check_statement(variables, s)


def check_statement(variables, s):
    if s[0] == "assign":
        _, target, e, line = s
        if target not in variables:
            raise Unsupported("a program this engine cannot check (%s is not declared, line %d)" % (target, line))
        typed(variables, e, variables[target][0])
    else:
        _, branches, otherwise, _ = s
        for cond, body in branches:
            typed(variables, cond, "BOOL")
            check_unit(variables, body)
        check_unit(variables, otherwise or [])


def type_of(variables, e):
    """The type of an expression, or None for an integer literal (which takes
    the type its context gives it)."""
    tag = e[0]
    if tag == "lit":
        return None
    if tag == "bool":
        return "BOOL"
    if tag == "var":
        if e[1] not in variables:
            raise Unsupported("a program this engine cannot check (%s is not declared, line %d)" % (e[1], e[2]))
        return variables[e[1]][0]
    if tag == "neg":
        t = type_of(variables, e[1])
        if t not in INTEGER_TYPES:
            raise Unsupported("unary - on %s (line %d)" % (t or "a literal expression", e[2]))
        return t
    if tag == "not":
        typed(variables, e[1], "BOOL")
        return "BOOL"
    _, op, left, right, line = e
    lt, rt = type_of(variables, left), type_of(variables, right)
    t = lt or rt
    if t is None:
        raise Unsupported("an operation on two literals (line %d): its type depends on the dialect's rules" % line)
    typed(variables, left, t)
    typed(variables, right, t)
    if op in ("AND", "OR", "XOR"):
        if t != "BOOL":
            raise Unsupported("%s on %s (line %d)" % (op, t, line))
        return "BOOL"
    if op in ("=", "<>"):
        return "BOOL"
    if t == "BOOL":
        raise Unsupported("%s on BOOL (line %d)" % (op, line))
    return "BOOL" if op in ("<", ">", "<=", ">=") else t


def typed(variables, e, wanted):
    t = type_of(variables, e)
    if t is None:
        if wanted not in INTEGER_TYPES:
            raise Unsupported("an integer literal where a %s is expected (line %d)" % (wanted, e[-1]))
        lo, hi = INTEGER_TYPES[wanted]
        if not lo <= literal_value(e) <= hi:
            raise Unsupported("an integer literal outside the range of %s (line %d)" % (wanted, e[-1]))
    elif t != wanted:
        raise Unsupported("a %s where a %s is expected (line %d): the dialect's conversion rules are not implemented" % (t, wanted, e[-1]))


def literal_value(e):
    return e[1]


# ---------------------------------------------------------------- interpreter


class Machine(object):
    def __init__(self, variables, order, policies):
        self.types = dict((n, variables[n][0]) for n in order)
        self.values = dict((n, variables[n][1]) for n in order)
        self.overflow = policies["overflow"]
        self.short_circuit = policies["short-circuit"] == "short-circuit"

    def run(self, body):
        for s in body:
            if s[0] == "assign":
                _, target, e, _ = s
                self.values[target] = self.eval(e, self.types[target])
            else:
                _, branches, otherwise, _ = s
                for cond, b in branches:
                    if self.eval(cond, "BOOL"):
                        self.run(b)
                        break
                else:
                    self.run(otherwise or [])

    def fit(self, value, ty, line):
        """The dialect's integer overflow (policy `overflow`)."""
        lo, hi = INTEGER_TYPES[ty]
        if lo <= value <= hi:
            return value
        if self.overflow == "wrap":
            return (value - lo) % (hi - lo + 1) + lo
        if self.overflow == "saturate":
            return hi if value > hi else lo
        raise RuntimeFault("overflow", line)

    def eval(self, e, context):
        """The value of e; `context` is the type an integer literal takes."""
        tag = e[0]
        if tag in ("lit", "bool"):
            return e[1]
        if tag == "var":
            return self.values[e[1]]
        if tag == "neg":
            ty = self.type_of(e[1], context)
            return self.fit(-self.eval(e[1], ty), ty, e[2])
        if tag == "not":
            return not self.eval(e[1], "BOOL")
        _, op, left, right, line = e
        ty = self.type_of(left, None) or self.type_of(right, None)
        a = self.eval(left, ty)
        if op == "AND" and self.short_circuit and not a:
            return False
        if op == "OR" and self.short_circuit and a:
            return True
        b = self.eval(right, ty)
        if op == "AND":
            return a and b
        if op == "OR":
            return a or b
        if op == "XOR":
            return a != b
        if op == "=":
            return a == b
        if op == "<>":
            return a != b
        if op == "<":
            return a < b
        if op == ">":
            return a > b
        if op == "<=":
            return a <= b
        if op == ">=":
            return a >= b
        exact = {"+": a + b, "-": a - b, "*": a * b}[op]
        return self.fit(exact, ty, line)

    def type_of(self, e, context):
        return type_of(dict((n, (t, None)) for n, t in self.types.items()), e) or context


# ---------------------------------------------------------------- the protocol


def scalar(value, ty, what):
    """A value of a `set` entry, checked against the variable's type."""
    if ty == "BOOL" and isinstance(value, bool):
        return value
    if ty in INTEGER_TYPES and isinstance(value, int) and not isinstance(value, bool):
        lo, hi = INTEGER_TYPES[ty]
        if lo <= value <= hi:
            return value
    raise Unsupported("the value %s for %s" % (json.dumps(value), what))


def path_of(program, path):
    """`MAIN.x` -> `X`, for a variable of the program instance."""
    parts = path.split(".")
    if len(parts) != 2 or parts[0].upper() != program:
        raise Unsupported("the variable path %s (only PROGRAM.variable is implemented)" % path)
    return parts[1].upper()


def answer(request):
    if request.get("protocol") != PROTOCOL:
        raise Unsupported("protocol %s (this engine speaks %s)" % (request.get("protocol"), PROTOCOL))
    dialect = request.get("dialect")
    if dialect not in DIALECTS:
        raise Unsupported("the dialect %s (this engine implements a subset of %s)" % (dialect, ", ".join(DIALECTS)))
    policies = request.get("policies", {})
    for name, choices in [
        ("overflow", ("wrap", "saturate", "trap")),
        ("arith-width", ("operand-type",)),
        ("after-error", ("stop", "continue")),
        ("short-circuit", ("eager", "short-circuit")),
        ("lifetime", ("retained",)),
    ]:
        if policies.get(name) not in choices:
            raise Unsupported("the policy %s=%s" % (name, policies.get(name)))
    plc = request.get("plc") or {}
    observe = request.get("observe") or {}
    if plc.get("init") or observe.get("operands"):
        raise Unsupported("located variables")

    program, variables, order, body = Parser(tokenize(request["source"], policies), policies).unit()
    if request.get("program") and request["program"].upper() != program:
        raise Unsupported("the program %s (the file's program is %s)" % (request["program"], program))
    check_unit(variables, body)

    machine = Machine(variables, order, policies)
    error = None
    for call in request.get("calls", []):
        if "reset" in call:
            raise Unsupported("resets of the controller")
        for path, value in sorted((call.get("set") or {}).items()):
            name = path_of(program, path)
            if name not in machine.types:
                raise Unsupported("the variable path %s" % path)
            machine.values[name] = scalar(value, machine.types[name], path)
        try:
            machine.run(body)
        except RuntimeFault as fault:
            # the cycle ends at the error; the answer reports the first one
            error = error or {"kind": fault.kind, "line": fault.line}
            if policies["after-error"] == "stop":
                break

    observed = {}
    for path in observe.get("vars", []):
        name = path_of(program, path)
        if name not in machine.values:
            raise Unsupported("the variable path %s" % path)
        observed[path] = machine.values[name]
    return {"verdict": "runtime-error" if error else "ok", "vars": observed, "operands": {}, "error": error}


def respond(text):
    """The answer to one request, as one line of JSON."""
    try:
        request = json.loads(text)
    except ValueError as e:
        sys.stderr.write("example engine: the request is not JSON: %s\n" % e)
        return None
    if not isinstance(request, dict) or not isinstance(request.get("source"), str):
        sys.stderr.write("example engine: the request is not a stref-engine/1 request (an object with a source)\n")
        return None
    try:
        result = answer(request)
    except Unsupported as e:
        result = {"verdict": "unsupported", "reason": "example engine: " + str(e)}
    except RecursionError:
        result = {"verdict": "unsupported", "reason": "example engine: a program nested too deeply"}
    return json.dumps(result)


def main():
    if sys.argv[1:] == ["--persistent"]:
        # one request a line, one answer a line, until the end of the input
        # (stref conformance --persistent)
        while True:
            line = sys.stdin.readline()
            if not line:
                return 0
            if line.strip():
                reply = respond(line)
                if reply is None:
                    return 2
                sys.stdout.write(reply + "\n")
                sys.stdout.flush()
    reply = respond(sys.stdin.read())
    if reply is None:
        return 2
    sys.stdout.write(reply + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
