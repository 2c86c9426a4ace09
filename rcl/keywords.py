"""RCL's keywords, read from grammar/rcl.lark so that the grammar stays their only source."""
from __future__ import annotations

import re
from functools import lru_cache

from .resources import grammar_path

_KEYWORD = re.compile(r'^_?[A-Z]+:\s*"([A-Z]+)"i\s*$', re.M)


@lru_cache(maxsize=1)
def keywords() -> tuple[str, ...]:
    """Every keyword, upper case, sorted."""
    return tuple(sorted(set(_KEYWORD.findall(grammar_path().read_text(encoding="utf-8")))))
