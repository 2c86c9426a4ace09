"""A Pygments lexer for RCL: `pygmentize -l rcl FILE`, and the REPL's colours.

Keywords come from the grammar (rcl.keywords); built-in names from the
built-in tables.
"""
from __future__ import annotations

import re

from pygments.lexer import RegexLexer, words
from pygments.token import Comment, Keyword, Name, Number, Operator, Punctuation, String, Text

from .keywords import keywords
from .types import NAMED


def _builtin_names() -> list[str]:
    """Every built-in's name, from the one table the checker and the interpreter use."""
    from .builtins import default_builtins

    return [b.name for b in default_builtins().values()]


class RclLexer(RegexLexer):
    """RCL, the Robot Control Language."""

    name = "RCL"
    aliases = ["rcl"]
    filenames = ["*.rcl"]
    mimetypes = ["text/x-rcl"]
    flags = re.IGNORECASE | re.MULTILINE

    tokens = {
        "root": [
            (r"\s+", Text),
            (r"//[^\n]*", Comment.Single),
            (r"\{[^}]*\}", Comment.Multiline),
            (r"\(\*[\s\S]*?\*\)", Comment.Multiline),
            (r"'(?:[^'\n]|'')*'", String.Single),
            (r'"(?:[^"\n]|"")*"', String.Double),
            (r"(\d+\.(?!\.)\d*|\.\d+)([eE][+-]?\d+)?|\d+[eE][+-]?\d+", Number.Float),
            (r"\d+", Number.Integer),
            (words(tuple(k for k in keywords() if k not in ("TRUE", "FALSE", "AND", "OR", "NOT", "DIV", "MOD")),
                   prefix=r"\b", suffix=r"\b"), Keyword),
            (words(("TRUE", "FALSE"), prefix=r"\b", suffix=r"\b"), Keyword.Constant),
            (words(("AND", "OR", "NOT", "DIV", "MOD"), prefix=r"\b", suffix=r"\b"), Operator.Word),
            (words(tuple(n.upper() for n in NAMED), prefix=r"\b", suffix=r"\b"), Keyword.Type),
            (words(tuple(n for n in _builtin_names() if not n.endswith("^")), prefix=r"\b", suffix=r"\b(?!\^)"),
             Name.Builtin),
            (r"\b(?:" + "|".join(re.escape(n) for n in _builtin_names() if n.endswith("^")) + r")", Name.Builtin),
            (r"[a-z][a-z0-9_]*\^", Name.Variable.Instance),  # frame names
            (r"[a-z][a-z0-9_]*", Name),
            (r":=|<>|<=|>=|->|\.\.|[=<>+\-*/^]", Operator),
            (r"[()\[\],;:.]", Punctuation),
        ],
    }
