"""Parse RCL source text into the typed AST of rcl.ast.

grammar/rcl.lark is the single statement of the syntax. The LALR parser
applies the small transformer below as it reduces, so even a deeply nested
program is built without recursion. Syntax errors become Diagnostics.
"""
from __future__ import annotations

import os
from collections.abc import Iterator
from functools import lru_cache
from pathlib import Path
from typing import cast

import lark
from lark import Token, Transformer
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from . import ast as A
from . import types as T
from .errors import Diagnostic, RclStaticError, source_line, source_lines
from .resources import grammar_path


def parse(source: str, filename: str = "<string>") -> A.Module:
    """Parse one source file; raise RclStaticError on a syntax error."""
    try:
        block = cast(A.Block, _parser().parse(source, start="start"))  # the Transformer makes the AST
    except UnexpectedInput as e:
        raise RclStaticError([_syntax_diagnostic(e, source, filename)]) from None
    _not_too_deep(block, source, filename)
    module = A.Module(filename, source, block)
    module.imports = [s for s in block.body if isinstance(s, A.Import)]
    return module


def parse_expression(source: str, filename: str = "<expression>") -> A.Expr:
    """Parse one expression (the REPL's bare expressions); raise RclStaticError on a syntax error."""
    try:
        expr = cast(A.Expr, _parser().parse(source, start="expr"))
    except UnexpectedInput as e:
        raise RclStaticError([_syntax_diagnostic(e, source, filename)]) from None
    _not_too_deep(expr, source, filename)
    return expr


MAX_NESTING = 4000  # syntax-tree levels: blocks within blocks, operands within operands


def _not_too_deep(root: A.Node, source: str, filename: str) -> None:
    """RclStaticError at the first node deeper than MAX_NESTING: the checker, the compiler and the
    running program each go down the tree by recursion, and Python's stack must hold it."""
    pending = [(root, 1)]
    while pending:
        node, depth = pending.pop()
        if depth > MAX_NESTING:
            message = (f"the program nests too deeply: more than {MAX_NESTING} levels of blocks and "
                       f"expressions within one another")
            raise RclStaticError([Diagnostic(filename, node.span, message, source_line(source, node.span.line))])
        pending.extend((child, depth + 1) for child in A.children(node))


def needs_more_input(source: str) -> bool:
    """Whether source is a program cut short (a block still open, an unfinished expression)."""
    try:
        _parser().parse(source, start="start")
    except UnexpectedEOF:
        return True
    except UnexpectedToken as e:
        return e.token.type == "$END"
    except UnexpectedCharacters as e:
        rest = source[e.pos_in_stream:]
        return rest.startswith("{") or rest.startswith("(*")  # a comment still open
    return False


@lru_cache(maxsize=1)
def _parser() -> lark.Lark:
    path = grammar_path()
    return lark.Lark(
        path.read_text(encoding="utf-8"),
        parser="lalr",
        start=["start", "expr"],
        lexer="basic",
        postlex=_BareReturn(),
        transformer=_ToAst(),
        maybe_placeholders=False,
        cache=_cache_file(),
    )


def _cache_file() -> bool | str:
    """A per-user cache of the analysed grammar (lark checks its hash before use)."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = Path(base) / "rcl"
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError:
        return False
    if not os.access(folder, os.W_OK):
        return False
    return str(folder / f"grammar-lark{lark.__version__}.cache")


class _BareReturn:
    """Postlexer: a RETURN whose next token starts on a later line returns no value."""

    always_accept = ()

    def process(self, stream: Iterator[Token]) -> Iterator[Token]:
        held = None
        for tok in stream:
            if held is not None:
                if held.type == "RETURN" and tok.line > held.line:  # type: ignore[operator]
                    held = Token.new_borrow_pos("RETURN_BARE", held.value, held)
                yield held
            held = tok
        if held is not None:
            if held.type == "RETURN":
                held = Token.new_borrow_pos("RETURN_BARE", held.value, held)
            yield held


# Spans -------------------------------------------------------------------

# lark types a Token's positions int | None; our lexer always sets them. Said with ignores, not
# cast(): these run for every token, and cast is a call.

def _tok_span(t: Token) -> A.Span:
    return A.Span(t.line, t.column, t.end_line, max(t.column, t.end_column - 1))  # type: ignore[arg-type, type-var, operator]


def _span_of(x) -> A.Span:
    return _tok_span(x) if isinstance(x, Token) else x.span


def _covering(items) -> A.Span:
    """The span from the first positioned item to the last."""
    placed = [x for x in items if isinstance(x, (Token, A.Node, A.Ident))]
    return _span_of(placed[0]).to(_span_of(placed[-1]))


def _ident(t: Token) -> A.Ident:
    return A.Ident(str(t), _tok_span(t))


class _ToAst(Transformer):
    """Builds rcl.ast nodes; validates nothing (the checker reports every problem)."""

    # Program structure

    def start(self, c):
        return c[0]

    def block(self, c):
        if c:
            return A.Block(list(c), span=_covering(c))
        return A.Block([], span=A.Span(1, 1, 1, 1))

    def assign(self, c):
        return A.Assign(c[0], c[1], span=_covering(c))

    def call_stmt(self, c):
        return A.CallStmt(c[0], span=c[0].span)

    def if_stmt(self, c):
        kw, cond, body, *rest = c
        branches = [(cond, body)]
        otherwise = None
        for part in rest:
            if isinstance(part, tuple):
                branches.append(part)
            else:
                otherwise = part
        return A.If(branches, otherwise, span=_tok_span(kw).to(cond.span))

    def elsif(self, c):
        return (c[1], c[2])

    def else_part(self, c):
        return c[0]

    def while_stmt(self, c):
        return A.While(c[1], c[2], span=_tok_span(c[0]).to(c[1].span))

    def repeat_stmt(self, c):
        return A.Repeat(c[1], c[2], span=_tok_span(c[0]).to(c[2].span))

    def for_stmt(self, c):
        kw, var, start, direction, stop, *rest = c
        body = rest[-1]
        step = rest[0] if len(rest) == 2 else None
        return A.For(_ident(var), start, stop, step, direction.type == "DOWNTO", body,
                     span=_tok_span(kw).to(stop.span))

    def return_stmt(self, c):
        value = c[1] if len(c) > 1 else None
        return A.Return(value, span=_covering(c))

    def try_stmt(self, c):
        return A.Try(c[1], c[2], span=_tok_span(c[0]))

    def raise_stmt(self, c):
        return A.Raise(c[1], span=_covering(c))

    def solve_stmt(self, c):
        kw, lhs, _eq, rhs, _for, unknown = c
        return A.Solve(lhs, rhs, _ident(unknown), span=_covering(c))

    def import_stmt(self, c):
        return A.Import(_string_value(c[1]), span=_covering(c))

    def var_decl(self, c):
        kw, *rest = c
        typ = rest.pop() if rest and isinstance(rest[-1], A.TypeExpr) else None
        return A.VarDecl([_ident(t) for t in rest], typ, span=_covering(c))

    def const_decl(self, c):
        return A.ConstDecl(_ident(c[1]), c[3], span=_covering(c))

    def proc_decl(self, c):
        kw, name, *rest = c
        params = rest.pop(0) if isinstance(rest[0], list) else []
        return A.RoutineDecl(_ident(name), False, params, None, rest[0],
                             span=_tok_span(kw).to(_tok_span(name)))

    def func_decl(self, c):
        kw, name, *rest = c
        params = rest.pop(0) if isinstance(rest[0], list) else []
        result = rest.pop(0) if isinstance(rest[0], A.TypeExpr) else None
        return A.RoutineDecl(_ident(name), True, params, result, rest[0],
                             span=_tok_span(kw).to(_tok_span(name)))

    def params(self, c):
        return list(c)

    def param_group(self, c):
        return list(c)

    def param_item(self, c):
        by_ref = c[0].type == "VAR"
        if by_ref:
            c = c[1:]
        typ = c[1] if len(c) > 1 else None
        return A.Param(_ident(c[0]), by_ref, typ, span=_covering(c))

    # Types

    def frame_type(self, c):
        refs = None
        if len(c) > 1:
            t = T.parse_refs(str(c[1]))
            refs = (t.src, t.dst)
        return A.FrameTypeExpr(refs, span=_covering(c))

    def named_type(self, c):
        return A.NamedType(_ident(c[0]), span=_tok_span(c[0]))

    def array_type(self, c):
        kw, low, _dots, high, element = c
        return A.ArrayTypeExpr(low, high, element, span=_covering(c))

    def open_array_type(self, c):
        return A.ArrayTypeExpr(None, None, c[1], span=_covering(c))

    # Expressions

    def binop(self, c):
        left, op, right = c
        return A.BinOp(str(op).upper(), left, right, span=left.span.to(right.span), op_span=_tok_span(op))

    def unop(self, c):
        op, operand = c
        return A.UnOp(str(op).upper(), operand, span=_tok_span(op).to(operand.span))

    def field(self, c):
        return A.Field(c[0], _ident(c[1]), span=c[0].span.to(_tok_span(c[1])))

    def index(self, c):
        return A.Index(c[0], c[1], span=c[0].span.to(c[1].span))

    def call(self, c):
        name, *args = c
        return A.Call(_ident(name), list(args), span=_covering(c))

    def name(self, c):
        return A.Name(_ident(c[0]), span=_tok_span(c[0]))

    def integer(self, c):
        return A.Integer(str(c[0]), span=_tok_span(c[0]))

    def real(self, c):
        return A.Real(str(c[0]), span=_tok_span(c[0]))

    def string(self, c):
        return A.String(_string_value(c[0]), span=_tok_span(c[0]))

    def boolean(self, c):
        return A.Boolean(c[0].type == "TRUE", span=_tok_span(c[0]))


def _string_value(tok: Token) -> str:
    quote = tok[0]
    return tok[1:-1].replace(quote * 2, quote)


# Syntax errors -----------------------------------------------------------

_DESCRIBE = {
    "NAME": "a name", "FRAMENAME": "a frame name", "INT": "a number", "REAL": "a number",
    "STRING": "a string", "FRAMEREF": "frame references", "RETURN_BARE": "RETURN",
    "$END": "the end of the file",
}
_EXPRESSION_START = {"NAME", "INT", "LPAR"}


def _describe_terminal(name: str) -> str:
    if name in _DESCRIBE:
        return _DESCRIBE[name]
    try:
        pattern = _parser().get_terminal(name).pattern
    except KeyError:
        return name.lstrip("_")
    if pattern.type == "str":
        return repr(pattern.value.upper()) if pattern.value.isalpha() else repr(pattern.value)
    return name.lstrip("_").lower()


def _expected_text(expected) -> str:
    names = set(expected)
    for closer, text in (("RPAR", "')'"), ("RSQB", "']'"), ("_END", "END"), ("_UNTIL", "UNTIL")):
        if closer in names:
            return text  # the most useful hint: what is still open
    if _EXPRESSION_START <= names:
        return "an expression"
    words = sorted({_describe_terminal(n) for n in names})
    if not words:
        return ""
    if len(words) > 6:
        words = words[:6] + ["..."]
    return words[0] if len(words) == 1 else "one of " + ", ".join(words)


_OPERATORS = {"PLUS", "MINUS", "STAR", "SLASH", "DIV", "MOD", "AND", "OR", "NE", "LT", "LE", "GT", "GE"}


def _terminal_named(text: str) -> str:
    """The grammar's name for an anonymous terminal such as ':='."""
    return next((t.name for t in _parser().terminals if t.pattern.value == text), text)


def _unclosed(source: str, at: Token) -> Token | None:
    """The innermost '(' or '[' still open where the token `at` stands, if any."""
    stack: list[Token] = []
    try:
        for tok in _parser().lex(source):
            if cast(int, tok.start_pos) >= cast(int, at.start_pos):
                break
            if tok.type in ("LPAR", "LSQB"):
                stack.append(tok)
            elif tok.type in ("RPAR", "RSQB") and stack:
                stack.pop()
    except UnexpectedInput:
        return None
    return stack[-1] if stack else None


def _syntax_diagnostic(e: UnexpectedInput, source: str, filename: str) -> Diagnostic:
    if isinstance(e, UnexpectedCharacters):
        line, col = e.line, e.column
        rest = source[e.pos_in_stream:]
        if rest.startswith("{") or rest.startswith("(*"):
            message = "unterminated comment"
        elif rest[:1] in ("'", '"'):
            message = "unterminated string (strings end on the line they start)"
        elif rest[:1] == "^":
            message = "'^' must follow a name directly, as in W^"
        else:
            ch = rest[:1]
            message = f"unexpected character {ch!r}"
        span = A.Span(line, col, line, col)
    elif isinstance(e, UnexpectedToken) and e.token.type != "$END":
        tok = e.token
        span = _tok_span(tok)
        what = "RETURN" if tok.type == "RETURN_BARE" else repr(str(tok))
        expected = _expected_text(e.expected)
        message = f"unexpected {what}" + (f"; expected {expected}" if expected else "")
        after_target = _terminal_named(":=") in e.expected  # a statement so far: a name, a field, a call
        opener = _unclosed(source, tok) if {"RPAR", "RSQB"} & set(e.expected) else None
        if opener is not None:  # what is still open, not what a merged parser state also allows
            expected = "')'" if opener.type == "LPAR" else "']'"
            message = f"unexpected {what}; expected {expected}"
        if tok.start_pos is not None and source.startswith("(*", tok.start_pos):
            message = "unterminated comment: (* has no matching *)"
        elif after_target and tok.type == "EQ":
            message = "unexpected '='; ':=' assigns (x := 3), '=' compares"
        elif after_target and tok.type in _OPERATORS:
            message = (f"unexpected {what}: an expression on its own is not a statement; assign it (x := ...) "
                       f"or show it (WRITELN(...))")
        elif opener is not None and opener.line < tok.line:
            message += f": the {str(opener)!r} at {opener.line}:{opener.column} is still open"
    else:
        lines = list(source_lines(source))
        while len(lines) > 1 and not lines[-1].strip():  # the end of file: after the last text
            lines.pop()
        line = len(lines)
        col = len(lines[-1]) + 1
        span = A.Span(line, col, line, col)
        expected = _expected_text(getattr(e, "expected", ()) or ())
        message = "unexpected end of file" + (f"; expected {expected}" if expected else "")
    return Diagnostic(filename, span, message, source_line(source, span.line))
