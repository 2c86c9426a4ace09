"""RCL's keywords and the form of a name, read from grammar/rcl.lark so that the grammar stays
their only source."""
from __future__ import annotations

import re
from functools import lru_cache

from .resources import grammar_path

_KEYWORD = re.compile(r'^_?[A-Z]+:\s*"([A-Z]+)"i\s*$', re.M)


@lru_cache(maxsize=1)
def keywords() -> tuple[str, ...]:
    """Every keyword, upper case, sorted."""
    return tuple(sorted(set(_KEYWORD.findall(grammar_path().read_text(encoding="utf-8")))))


_TERMINAL = re.compile(r"^(NAME|FRAMENAME)(?:\.\d+)?:\s*/(.+)/i\s*$", re.M)


@lru_cache(maxsize=1)
def _name_forms() -> dict[str, re.Pattern]:
    text = grammar_path().read_text(encoding="utf-8")
    return {kind: re.compile(pattern, re.I | re.A) for kind, pattern in _TERMINAL.findall(text)}


def is_name(text: str) -> bool:
    """Whether text is an RCL name (NAME) or frame name (FRAMENAME, ending in ^), as the
    grammar's terminals have it. Keywords are not excluded."""
    forms = _name_forms()
    return any(forms[kind].fullmatch(text) for kind in ("NAME", "FRAMENAME"))
